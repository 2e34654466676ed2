#include "waves/rotating_wave_branches.h"

#include <algorithm>
#include <cmath>

namespace rubcont {

namespace {

// The measures that identify a rotating wave independently of its phase reference.
struct Signature {
  double precession_hz = 0.0;
  double normal_phase_deg = 0.0;
  std::vector<double> normal_force;
};

Signature SignatureOf(const Vector& measures, Index contacts) {
  Signature s;
  s.precession_hz = measures(0);
  s.normal_phase_deg = measures(1);
  for (Index k = 0; k < contacts; ++k) s.normal_force.push_back(measures(2 + k));
  return s;
}

double AngleDifference(double a_deg, double b_deg) {
  double d = std::fmod(a_deg - b_deg, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return std::abs(d);
}

bool Matches(const Signature& a, const Signature& b, double tolerance, double force_scale) {
  if (std::abs(a.precession_hz - b.precession_hz) > tolerance * std::abs(b.precession_hz)) return false;
  if (AngleDifference(a.normal_phase_deg, b.normal_phase_deg) > tolerance * 180.0) return false;
  for (std::size_t k = 0; k < a.normal_force.size(); ++k) {
    if (std::abs(a.normal_force[k] - b.normal_force[k]) >
        tolerance * std::max(std::abs(b.normal_force[k]), force_scale)) {
      return false;
    }
  }
  return true;
}

// Whether (speed, signature, piece) lies on `branch`: some segment of one piece brackets the speed
// and the signature interpolated there matches.
bool OnBranch(const Branch& branch, double speed, const Signature& start, const std::string& piece,
              Index contacts, double tolerance, double force_scale) {
  const auto& p = branch.points;
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    if (p[i].piece != piece || p[i + 1].piece != piece) continue;
    const double a = p[i].lambda, b = p[i + 1].lambda;
    if (speed < std::min(a, b) || speed > std::max(a, b)) continue;
    const double w = a == b ? 0.0 : (speed - a) / (b - a);
    const Vector m = (1.0 - w) * p[i].measures + w * p[i + 1].measures;
    Signature s = SignatureOf(m, contacts);
    // The phase may wrap between the two points: interpolate it as an angle.
    const double pa = p[i].measures(1), pb = p[i + 1].measures(1);
    double d = pb - pa;
    if (d > 180.0) d -= 360.0;
    if (d < -180.0) d += 360.0;
    s.normal_phase_deg = pa + w * d;
    if (Matches(s, start, tolerance, force_scale)) return true;
  }
  return false;
}

}  // namespace

std::string PatternName(const std::vector<double>& normals) {
  if (normals.size() == 1) return "single";
  if (normals.size() == 2) {
    if (normals[0] != 0.0 && normals[1] != 0.0) return normals[1] > 0.0 ? "mode1" : "mode2";
    return normals[0] != 0.0 ? "left_only" : "right_only";
  }
  return "all";
}

const char* ContactModeName(double code) {
  switch (static_cast<int>(std::lround(code))) {
    case 0: return "free";
    case 1: return "stick";
    case 2: return "slip+";
    case 3: return "slip-";
  }
  return "?";
}

std::vector<RotatingWaveBranch> ComputeRotatingWaveBranches(
    const RubStructure& structure, FrictionLawKind law, const RotatingWaveBranchOptions& options,
    const BranchProgress& progress) {
  Validate(options.search);
  ContinuationOptions continuation = options.continuation;
  continuation.bounds.lambda_min = options.search.speed_min;
  continuation.bounds.lambda_max = options.search.speed_max;
  Validate(continuation);

  // A rotating wave needs rotational symmetry: the imbalance (forward at ω) is left out.
  RubStructure balanced = structure;
  balanced.imbalance = 0.0;
  RotatingWaveProblem problem(balanced, law);
  const std::vector<RotatingWaveStart> starts = FindRotatingWaveStarts(problem, options.search);
  const Index contacts = problem.Contacts();
  double force_scale = 0.0;  // forces below 1e-3 of the largest support force count as zero
  for (Index k = 0; k < structure.Coordinates(); ++k) {
    force_scale = std::max(force_scale, structure.stiffness(k, k));
  }
  force_scale *= 1e-3 * structure.contacts[0].geometry.clearance;

  std::vector<RotatingWaveBranch> branches;
  int tried = 0;
  for (const RotatingWaveStart& start : starts) {
    ++tried;
    problem.SetModes(start.modes);
    problem.SetPhaseReference(start.u);
    const Signature signature =
        SignatureOf(problem.Measures(start.u, start.speed), contacts);
    const std::string piece = problem.PieceLabel();
    const bool known = std::any_of(branches.begin(), branches.end(), [&](const RotatingWaveBranch& b) {
      return OnBranch(b.branch, start.speed, signature, piece, contacts,
                      options.duplicate_tolerance, force_scale);
    });
    if (known) continue;
    RotatingWaveBranch result;
    result.name = "branch" + std::to_string(branches.size() + 1);
    result.family = start.family;
    result.normals = start.normals;
    // Down in speed, then up from the same start in its own contact modes (the first run
    // switches them at its events).
    continuation.direction = -1;
    const Branch backward = Continue(problem, start.u, start.speed, continuation);
    problem.SetModes(start.modes);
    problem.SetPhaseReference(start.u);
    continuation.direction = +1;
    const Branch forward = Continue(problem, start.u, start.speed, continuation);
    result.branch = backward.points.empty() ? forward
                    : forward.points.empty() ? backward
                                             : JoinAtStart(backward, forward);
    for (SpecialPoint& sp : result.branch.special_points) {
      if (sp.type != SpecialPointType::kHopf) continue;
      const LyapunovCoefficient c = problem.FirstLyapunov(sp.u, sp.lambda, sp.critical_value);
      if (c.valid) {
        sp.lyapunov = c.l1;
      } else {
        sp.note += (sp.note.empty() ? "" : "; ") + ("first Lyapunov coefficient: " + c.message);
      }
    }
    branches.push_back(std::move(result));
    if (progress) progress(static_cast<int>(branches.size()), tried, static_cast<int>(starts.size()));
  }
  return branches;
}

}  // namespace rubcont
