#include "waves/rotating_wave_families.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>

#include <fmt/core.h>

#include "solvers/constants.h"

namespace rubcont {

namespace {

struct Guess {
  double precession = 0.0;  // Ω [rad/s]
  double speed = 0.0;       // ω [rad/s]
  std::vector<ContactMode> modes;
  std::string family;
  // Where on its grid it was found: the contact that rolls (whirl) or whose μ_req crosses (whip),
  // the sign of the crossing (0 for whirl), and the grid interval [lo, hi] [rad/s] it came from.
  Index contact = 0;
  int sign = 0;
  double lo = 0.0, hi = 0.0;
};

std::string PatternName(const std::vector<double>& normals) {
  if (normals.size() == 1) return "single contact";
  if (normals.size() == 2 && normals[0] != 0.0 && normals[1] != 0.0) {
    return normals[1] > 0.0 ? "Mode 1" : "Mode 2";
  }
  return normals[0] != 0.0 ? "left contact only" : "right contact only";
}

// [lo, hi] intervals of consecutive grid points where `ok` holds.
std::vector<std::pair<double, double>> Intervals(const Vector& grid, const std::vector<bool>& ok) {
  std::vector<std::pair<double, double>> out;
  for (Index i = 0; i < grid.size(); ++i) {
    if (!ok[i]) continue;
    Index j = i;
    while (j + 1 < grid.size() && ok[j + 1]) ++j;
    out.emplace_back(grid(i), grid(j));
    i = j;
  }
  return out;
}

bool SameSolution(const RotatingWaveStart& a, const RotatingWaveStart& b, Index omega_index,
                  const std::vector<ContactMode>& modes_b) {
  if (a.modes != modes_b) return false;
  if (std::abs(a.speed - b.speed) > 1e-9 * std::abs(a.speed)) return false;
  return (a.u - b.u).head(omega_index + 1).cwiseAbs().maxCoeff() <=
         1e-6 * b.u.head(omega_index + 1).cwiseAbs().maxCoeff();
}

// The guesses of one contact pattern from the closed form sampled on `grid` (increasing Ω > 0):
// whirl where contact r can roll, whip where some μ_req crosses ±μ (the rules of the header).
std::vector<Guess> GuessesOnGrid(const RubStructure& s, const std::vector<double>& normals,
                                 const std::vector<double>& rci, const Vector& grid,
                                 const FamilySearchOptions& options) {
  const Index m = static_cast<Index>(normals.size());
  const double mu = s.law.friction;
  std::vector<std::complex<double>> n(normals.begin(), normals.end());
  std::vector<Index> active;
  for (Index k = 0; k < m; ++k) {
    if (normals[k] != 0.0) active.push_back(k);
  }
  std::vector<std::vector<std::complex<double>>> force(grid.size());
  std::vector<bool> touching(grid.size());
  for (Index i = 0; i < grid.size(); ++i) {
    force[i] = SolveRigidContactOrbit(s, grid(i), n).force;
    touching[i] = std::all_of(active.begin(), active.end(),
                              [&](Index k) { return force[i][k].real() > 0.0; });
  }
  auto mu_required = [&](Index i, Index k) { return force[i][k].imag() / force[i][k].real(); };

  std::vector<Guess> guesses;
  // Whirl: contact r rolls.
  for (Index r : active) {
    std::vector<bool> ok(grid.size());
    for (Index i = 0; i < grid.size(); ++i) {
      ok[i] = touching[i] && std::abs(mu_required(i, r)) <= mu;
    }
    for (auto [lo, hi] : Intervals(grid, ok)) {
      const double interval_lo = lo, interval_hi = hi;
      lo = std::max(lo, rci[r] * options.speed_min);
      hi = std::min(hi, rci[r] * options.speed_max);
      if (!(hi > lo)) continue;
      Guess g;
      g.precession = 0.5 * (lo + hi);
      g.speed = g.precession / rci[r];
      g.modes.assign(m, ContactMode::kFree);
      const Index i = std::min<Index>(grid.size() - 1, std::lround(g.precession / grid(0)) - 1);
      for (Index k : active) {
        const bool equal_rci = std::abs(rci[k] / rci[r] - 1.0) < 1e-9;
        if (k == r || (equal_rci && std::abs(mu_required(i, k)) <= mu)) {
          g.modes[k] = ContactMode::kStick;
        } else {
          const double sign = equal_rci ? mu_required(i, k) : rci[k] - rci[r];
          g.modes[k] = sign > 0.0 ? ContactMode::kSlipPositive : ContactMode::kSlipNegative;
        }
      }
      g.family = fmt::format("whirl, {} rolls, {}", s.contacts[r].name, PatternName(normals));
      g.contact = r;
      g.lo = interval_lo;
      g.hi = interval_hi;
      guesses.push_back(g);
    }
  }
  // Whip: every touching contact slips where some μ_req crosses ±μ.
  double rci_lo = kInfinity, rci_hi = 0.0;
  for (Index j : active) {
    rci_lo = std::min(rci_lo, rci[j]);
    rci_hi = std::max(rci_hi, rci[j]);
  }
  for (Index k : active) {
    for (int sign : {+1, -1}) {
      for (Index i = 0; i + 1 < grid.size(); ++i) {
        if (!touching[i] || !touching[i + 1]) continue;
        const double a = mu_required(i, k) - sign * mu, b = mu_required(i + 1, k) - sign * mu;
        if ((a > 0.0) == (b > 0.0)) continue;
        Guess g;
        g.precession = grid(i) + (grid(i + 1) - grid(i)) * a / (a - b);
        // Slip velocity ωR − ΩC of the sign of the friction at every touching contact.
        g.speed = sign > 0 ? std::max(options.speed_min, 1.05 * g.precession / rci_lo)
                           : std::min(options.speed_max, 0.95 * g.precession / rci_hi);
        if (g.speed > options.speed_max || g.speed < options.speed_min) continue;
        g.modes.assign(m, ContactMode::kFree);
        for (Index j : active) {
          g.modes[j] = sign > 0 ? ContactMode::kSlipPositive : ContactMode::kSlipNegative;
        }
        g.family = fmt::format("whip, {} μ_req crosses {}μ, {}", s.contacts[k].name,
                               sign > 0 ? "+" : "−", PatternName(normals));
        g.contact = k;
        g.sign = sign;
        g.lo = grid(i);
        g.hi = grid(i + 1);
        guesses.push_back(g);
      }
    }
  }
  return guesses;
}

// Whether guess `g` of the fixed grid is one the range's grid found too: the same contact and
// kind, and grid intervals that overlap (a whirl interval, or the cells that bracket a crossing).
bool FoundOnRangeGrid(const Guess& g, const std::vector<Guess>& range_guesses) {
  return std::any_of(range_guesses.begin(), range_guesses.end(), [&](const Guess& r) {
    return r.contact == g.contact && r.sign == g.sign && r.lo <= g.hi && g.lo <= r.hi;
  });
}

}  // namespace

void Validate(const FamilySearchOptions& o) {
  if (!(o.speed_min > 0.0) || !(o.speed_max > o.speed_min) || !std::isfinite(o.speed_max)) {
    throw std::invalid_argument(fmt::format(
        "FamilySearchOptions: speed range [{}, {}] rad/s must satisfy 0 < min < max < ∞",
        o.speed_min, o.speed_max));
  }
  if (!std::isfinite(o.precession_max)) {
    throw std::invalid_argument(
        fmt::format("FamilySearchOptions.precession_max = {}: must be finite", o.precession_max));
  }
  if (o.samples < 10) {
    throw std::invalid_argument(
        fmt::format("FamilySearchOptions.samples = {}: must be at least 10", o.samples));
  }
  Validate(o.newton);
}

std::vector<RotatingWaveStart> FindRotatingWaveStarts(RotatingWaveProblem& problem,
                                                      const FamilySearchOptions& options) {
  Validate(options);
  const RubStructure& s = problem.structure();
  const Index m = problem.Contacts();
  std::vector<double> rci(m);
  for (Index k = 0; k < m; ++k) rci[k] = s.contacts[k].geometry.radius / s.contacts[k].geometry.clearance;
  const double rci_max = *std::max_element(rci.begin(), rci.end());
  // The range's grid: `samples` points up to the highest whirl Ω of the speed range. Its spacing
  // grows with the range, so a wide range could step over a crossing a narrow one finds (A(a)'s
  // Mode 1 whip at Ω = 10.5 rad/s lies below the first point, 13 rad/s, of the grid for
  // [20, 1000] rpm). The fixed grid, `samples` points over (0, precession_max], does not depend
  // on the speed range: what it finds that the range's grid did not is added, so a wider range
  // finds every family a narrower one finds there.
  const double precession_max = std::max(options.precession_max, rci_max * options.speed_max);
  const Vector grid = Vector::LinSpaced(options.samples, precession_max / options.samples,
                                        precession_max);
  const bool fixed_grid = options.precession_max > 0.0 && options.precession_max < precession_max;
  const Vector fixed = fixed_grid ? Vector::LinSpaced(options.samples,
                                                      options.precession_max / options.samples,
                                                      options.precession_max)
                                  : Vector();

  std::vector<std::vector<double>> patterns;
  if (m == 1) {
    patterns = {{1.0}};
  } else if (m == 2) {
    patterns = {{1.0, 1.0}, {1.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}};
  } else {
    patterns = {std::vector<double>(m, 1.0)};
  }

  std::vector<RotatingWaveStart> starts;
  const Index omega_index = 2 * s.Coordinates();
  for (const std::vector<double>& normals : patterns) {
    std::vector<Guess> guesses = GuessesOnGrid(s, normals, rci, grid, options);
    if (fixed_grid) {
      const std::vector<Guess> on_range_grid = guesses;
      for (const Guess& g : GuessesOnGrid(s, normals, rci, fixed, options)) {
        if (!FoundOnRangeGrid(g, on_range_grid)) guesses.push_back(g);
      }
    }
    std::sort(guesses.begin(), guesses.end(),
              [](const Guess& a, const Guess& b) { return a.precession < b.precession; });

    const std::vector<std::complex<double>> n(normals.begin(), normals.end());
    for (const Guess& g : guesses) {
      problem.SetModes(g.modes);
      RotatingWaveStart start;
      start.u = problem.FromRigidContactOrbit(SolveRigidContactOrbit(s, g.precession, n));
      const auto result = problem.SolveConsistent(start.u, g.speed, options.newton);
      if (!result.consistent) continue;
      start.speed = g.speed;
      start.modes = problem.modes();
      start.normals = normals;
      start.family = g.family;
      const bool known = std::any_of(starts.begin(), starts.end(), [&](const RotatingWaveStart& x) {
        return SameSolution(x, start, omega_index, start.modes);
      });
      if (!known) starts.push_back(start);
    }
  }
  return starts;
}

}  // namespace rubcont
