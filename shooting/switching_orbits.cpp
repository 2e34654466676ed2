#include "shooting/switching_orbits.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/core.h>

namespace rubcont {
namespace {

// The switches of the orbit at `point` (solved with `options`) as segment boundaries on `base`,
// with the start moved to the middle of the orbit's longest stretch without a switch.
std::pair<OrbitStart, EventMesh> OnSwitches(OdeSystem& system, OrbitKind kind,
                                            const ShootingOptions& options,
                                            const ShootingOptions& base, const BranchPoint& point,
                                            int samples) {
  std::string failure;
  const OrbitSamples orbit =
      SampleOrbit(system, kind, options, point.u, point.lambda, samples, &failure);
  OrbitStart start = OrbitStartAt(system, kind, options, point);
  EventMesh mesh;
  if (!orbit.valid) {
    mesh.message = "the orbit could not be sampled: " + failure;
    return {start, mesh};
  }
  // The samples just after a switch, in time, each once.
  std::vector<Index> switches;
  for (const SurfaceCrossing& crossing : SurfaceCrossings(system, orbit)) {
    switches.push_back(crossing.sample);
  }
  std::sort(switches.begin(), switches.end());
  switches.erase(std::unique(switches.begin(), switches.end()), switches.end());
  const Index m = orbit.times.size();
  if (!switches.empty()) {
    // The longest stretch in time between switches, round the period (the last sample is the
    // first's image under the return map: the stretch wraps from the last switch to the first).
    const double T = orbit.period;
    double best_from = orbit.times(switches.back());
    double best_length = T - best_from + orbit.times(switches.front());
    for (std::size_t k = 1; k < switches.size(); ++k) {
      const double length = orbit.times(switches[k]) - orbit.times(switches[k - 1]);
      if (length > best_length) {
        best_from = orbit.times(switches[k - 1]);
        best_length = length;
      }
    }
    // Any state of the orbit starts it (of a relative one too: the rotation commutes with the
    // flow), so a stretch that wraps round the end starts one period earlier: the sample nearest
    // its middle.
    const double t_middle = std::fmod(best_from + 0.5 * best_length, T);
    Index middle = 0;
    for (Index j = 1; j + 1 < m; ++j) {
      if (std::abs(orbit.times(j) - t_middle) < std::abs(orbit.times(middle) - t_middle)) {
        middle = j;
      }
    }
    start.x0 = orbit.states.col(middle);
    mesh = EventMeshOf(system, base, orbit, orbit.times(middle) / orbit.period);
    return {start, mesh};
  }
  mesh = EventMeshOf(system, base, orbit);
  return {start, mesh};
}

}  // namespace

void Validate(const SwitchingOrbitOptions& options) {
  Validate(options.family);
  if (!options.family.shooting.event_boundaries.empty()) {
    throw std::invalid_argument(
        "SwitchingOrbitOptions.family.shooting.event_boundaries: must be empty (the pieces on "
        "switches get theirs from WithEventBoundaries)");
  }
  if (options.direction != 1 && options.direction != -1) {
    throw std::invalid_argument(fmt::format(
        "SwitchingOrbitOptions.direction = {}: must be +1 or -1", options.direction));
  }
  if (options.max_pieces < 1) {
    throw std::invalid_argument(fmt::format(
        "SwitchingOrbitOptions.max_pieces = {}: must be at least 1", options.max_pieces));
  }
  if (options.samples < 16) {
    throw std::invalid_argument(fmt::format(
        "SwitchingOrbitOptions.samples = {}: must be at least 16", options.samples));
  }
}

SwitchingOrbitFamily ContinueAcrossSwitches(OdeSystem& system, OrbitKind kind,
                                            const OrbitStart& start,
                                            const SwitchingOrbitOptions& options) {
  Validate(options);
  if (kind == OrbitKind::kForced) {
    throw std::invalid_argument(
        "ContinueAcrossSwitches: kind kForced cannot have segment boundaries on switches; make "
        "the system autonomous (e.g. AutonomousSoftImpactOscillator)");
  }
  if (system.SwitchingCount() == 0) {
    throw std::invalid_argument("ContinueAcrossSwitches: the system has no switching functions");
  }
  SwitchingOrbitFamily result;
  const ShootingOptions& base = options.family.shooting;
  OrbitStart from = start;
  int direction = options.direction;
  EventMesh mesh;             // the switches of the next piece (none: the options' mesh)
  bool after_change = false;  // the piece starts where a phase vanished
  for (int piece = 0; piece < options.max_pieces; ++piece) {
    PeriodicOrbitBranchOptions o = options.family;
    o.direction = direction;
    if (direction > 0 ? from.lambda >= o.lambda_max : from.lambda <= o.lambda_min) {
      result.message = fmt::format("at the end of the range, λ = {:.10g}", from.lambda);
      return result;
    }
    const bool on_switches = !mesh.options.event_boundaries.empty();
    if (on_switches) o.shooting = mesh.options;
    // The first orbit that crosses a surface more often than the piece's mesh has switches
    // (on the options' mesh: at all) ends the piece.
    bool crossed = false;
    o.on_step = [&](const Branch& b) {
      if (options.family.on_step && !options.family.on_step(b)) return false;
      std::string failure;
      const BranchPoint& p = b.points.back();
      const OrbitSamples orbit =
          SampleOrbit(system, kind, o.shooting, p.u, p.lambda, options.samples, &failure);
      const int zeros = orbit.valid ? static_cast<int>(SurfaceCrossings(system, orbit).size()) : 0;
      crossed = zeros > mesh.zeros;
      return !crossed;
    };
    SwitchingOrbitPiece current;
    current.switches = static_cast<int>(mesh.options.event_boundaries.size());
    current.family = ContinuePeriodicOrbits(system, kind, from, o);
    result.work += current.family.work;
    // Past a vanished phase the family goes on where its orbits stay clear of the surface, which
    // may be back the way it came (a grazing fold: the hardening soft impact oscillator's upper
    // grazing, approached from its fold): one step that crosses again at once is tried the
    // other way.
    const auto crossed_at_once = [&](const PeriodicOrbitBranch& family) {
      return crossed && family.branch.points.size() <= 2;
    };
    const bool room = -direction > 0 ? from.lambda < o.lambda_max : from.lambda > o.lambda_min;
    if (after_change && !on_switches && crossed_at_once(current.family) && room) {
      o.direction = -direction;
      crossed = false;
      PeriodicOrbitBranch other = ContinuePeriodicOrbits(system, kind, from, o);
      result.work += other.work;
      if (!crossed_at_once(other)) {
        current.family = std::move(other);
      } else {
        crossed = true;  // both ways: keep the first
      }
    }
    after_change = false;
    const Branch& branch = current.family.branch;
    const bool kept = branch.points.size() >= 2;
    if (kept) {
      const double last = branch.points.back().lambda;
      direction = last >= branch.points[branch.points.size() - 2].lambda ? +1 : -1;
    }
    mesh = EventMesh();
    // A located pattern change first: the orbit at the event, tangent to a surface, may sample
    // as crossing it more often (measured on the rub: 28 zeros at a vanished phase).
    const bool changed =
        on_switches && branch.status == BranchStatus::kSwitchRefused && kept;
    if (changed) {
      after_change = true;
      current.end = branch.message + "; on the options' mesh from there";
      from = OrbitStartAt(system, kind, current.family.shooting, branch.points.back());
    } else if (crossed && kept) {
      auto [moved, switches] = OnSwitches(system, kind, current.family.shooting, base,
                                          branch.points.back(), options.samples);
      if (!switches.ok) {
        current.end = fmt::format("crosses a surface at λ = {:.10g}, but: {}",
                                  branch.points.back().lambda, switches.message);
        result.message = current.end;
        result.pieces.push_back(std::move(current));
        return result;
      }
      current.end = fmt::format(
          "crosses a surface{} at λ = {:.10g}: {} switches, {} boundaries",
          on_switches ? " where it had none" : "", moved.lambda, switches.zeros,
          switches.options.event_boundaries.size());
      from = moved;
      mesh = std::move(switches);
    } else {
      current.end = branch.message;
      result.message = branch.message;
      result.pieces.push_back(std::move(current));
      return result;
    }
    result.pieces.push_back(std::move(current));
  }
  result.message = fmt::format("reached the maximum of {} pieces", options.max_pieces);
  return result;
}

}  // namespace rubcont
