#include "shooting/torus_branches.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "shooting/shooting.h"
#include "solvers/constants.h"

namespace rubcont {

namespace {

// Multipliers closer than this (in ρ) to 0, 1/4, 1/3 or 1/2 are strong resonances.
constexpr double kStrongResonance = 1e-3;
// A harmonic at least this many times the one below it stands out of a circle's decaying spectrum.
constexpr double kLockingExcess = 2.0;

// The engine's options for a torus family: the range, no Jacobian spectrum.
ContinuationOptions EngineOptions(const TorusBranchOptions& options);
// The circle problem of a family's circles with K harmonics: its events (the tail's at TailBound)
// and grazing tests set.
std::unique_ptr<InvariantCircleProblem> CircleProblem(std::shared_ptr<OdeSystem> system,
                                                      OrbitKind kind, int harmonics,
                                                      const TorusBranchOptions& options);
// The family from a started stepper on `problem` to its end; with max_harmonics, refined in K at
// its tail events and continued (TorusBranchOptions::max_harmonics). Fills result.branch,
// point_harmonics and refinements; returns the problem of the finest K.
struct Family {
  std::unique_ptr<InvariantCircleProblem> problem;
  // Why a tail event at K < max_harmonics was not followed by a refinement ("" where none was).
  std::string unrefined;
};
Family RunFamily(std::shared_ptr<OdeSystem> system, std::unique_ptr<InvariantCircleProblem> problem,
                 Continuation& stepper, const TorusBranchOptions& options,
                 const StepCallback& on_step, TorusBranch& result);
// The family's end (TorusEnd, end_note, p:q) read from its last circle (u0 when it has none), and
// the Lyapunov stability of every torus when asked for.
void ReadEnd(Family& family, const Vector& u0, const TorusBranchOptions& options,
             TorusBranch& result);

}  // namespace

void Validate(const TorusBranchOptions& options) {
  auto fail = [](const std::string& field, double value, const std::string& rule) {
    throw std::invalid_argument(
        fmt::format("TorusBranchOptions: {} = {}: {}", field, value, rule));
  };
  if (!std::isfinite(options.lambda_min) || !std::isfinite(options.lambda_max) ||
      !(options.lambda_min < options.lambda_max)) {
    fail("lambda_max", options.lambda_max, "must be finite and above lambda_min");
  }
  if (options.harmonics < 1) fail("harmonics", options.harmonics, "must be at least 1");
  if (!(options.amplitude > 0.0) || !std::isfinite(options.amplitude)) {
    fail("amplitude", options.amplitude, "must be positive");
  }
  if (!(options.max_fourier_tail > 0.0 && options.max_fourier_tail < 1.0)) {
    fail("max_fourier_tail", options.max_fourier_tail, "must be in (0, 1)");
  }
  if (!(options.min_radius >= 0.0 && options.min_radius < options.amplitude / std::sqrt(2.0))) {
    fail("min_radius", options.min_radius,
         fmt::format("must be in [0, amplitude / √2 = {:g}) (the first circle's radius)",
                     options.amplitude / std::sqrt(2.0)));
  }
  if (options.lyapunov_iterates < 0) {
    fail("lyapunov_iterates", options.lyapunov_iterates, "must be ≥ 0");
  }
  if (options.max_harmonics < 0 || options.max_harmonics > 1000) {
    fail("max_harmonics", options.max_harmonics, "must be in 0 … 1000");
  }
  if (!(options.converged_tail > 0.0 && options.converged_tail <= options.max_fourier_tail)) {
    fail("converged_tail", options.converged_tail,
         fmt::format("must be in (0, max_fourier_tail = {:g}]", options.max_fourier_tail));
  }
  ValidateRefinementImages("TorusBranchOptions: ", options.refinement_images);
  Validate(options.integrator);
  Validate(options.continuation);
}

const char* ToString(TorusEnd end) {
  switch (end) {
    case TorusEnd::kBound: return "reached the range's end";
    case TorusEnd::kSteps: return "reached the step limit";
    case TorusEnd::kBreakdown: return "breakdown";
    case TorusEnd::kLocking: return "phase locking";
    case TorusEnd::kGrazing: return "grazing";
    case TorusEnd::kShrinks: return "the circle shrinks onto its centre";
    case TorusEnd::kFailed: return "failed";
  }
  return "?";
}

int TorusBranch::SolvedHarmonics(std::size_t i) const {
  return i < point_harmonics.size() ? point_harmonics[i] : harmonics;
}

Vector TorusBranch::SolvedCircle(std::size_t i) const {
  return CircleWithHarmonics(branch.points.at(i).u, state_dimension, harmonics, SolvedHarmonics(i));
}

TorusBranch ContinueToriFromNeimarkSacker(std::shared_ptr<OdeSystem> system,
                                          const PeriodicOrbitBranch& family,
                                          std::size_t special_point,
                                          const TorusBranchOptions& options,
                                          const StepCallback& on_step) {
  Validate(options);
  const Branch& branch = family.branch;
  if (special_point >= branch.special_points.size() ||
      branch.special_points[special_point].type != SpecialPointType::kNeimarkSacker) {
    throw std::invalid_argument(fmt::format(
        "ContinueToriFromNeimarkSacker: special point {} of {} is not a Neimark–Sacker point",
        special_point, branch.special_points.size()));
  }
  if (family.kind == OrbitKind::kForced) {
    throw std::invalid_argument(
        "ContinueToriFromNeimarkSacker: the family's orbits are forced: start a forced torus from a "
        "circle (InvariantCircleProblem) instead");
  }
  const SpecialPoint& point = branch.special_points[special_point];
  TorusBranch result;
  result.special_point = special_point;
  result.kind = family.kind;
  result.harmonics = options.harmonics;
  result.coordinates = options.coordinates;
  result.birth_lambda = point.lambda;

  // The family's return map at the point, and its critical pair.
  const OrbitReturnMap at = ReturnMapAt(*system, family, point);
  if (!at.ok) {
    result.message = at.message;
    return result;
  }
  const Index n = at.map.rows();
  result.state_dimension = n;
  const double period = at.period, phi = at.rotation;
  const Matrix& map = at.map;
  const Eigen::EigenSolver<Matrix> eigen(map);
  // The pair nearest the multiplier the engine located at the point (Im μ > 0), or, where it
  // recorded none, the pair nearest the unit circle: the located one decides where two pairs lie
  // near the circle.
  std::complex<double> target = point.critical_value;
  if (target.imag() < 0.0) target = std::conj(target);
  const bool located = std::abs(target) > 0.0;
  auto distance = [&](std::complex<double> mu) {
    return located ? std::abs(mu - target) : std::abs(std::abs(mu) - 1.0);
  };
  Index critical = -1;
  for (Index k = 0; k < n; ++k) {
    const std::complex<double> mu = eigen.eigenvalues()(k);
    if (mu.imag() <= 1e-8 * std::abs(mu)) continue;  // one of each pair, Im μ > 0
    if (critical < 0 || distance(mu) < distance(eigen.eigenvalues()(critical))) critical = k;
  }
  if (critical < 0 || std::abs(std::abs(eigen.eigenvalues()(critical)) - 1.0) > 0.05) {
    result.message = "the return map has no complex pair within 0.05 of the unit circle at the point";
    return result;
  }
  const std::complex<double> mu = eigen.eigenvalues()(critical);
  const double rho = std::arg(mu) / kTwoPi;  // (0, 1/2)
  result.birth_rotation_number = rho;
  result.birth_modulus = std::abs(mu);
  for (const double resonance : {0.0, 0.25, 1.0 / 3.0, 0.5}) {
    if (std::abs(rho - resonance) < kStrongResonance) {
      result.message = fmt::format(
          "the multiplier's angle gives ρ = {:.6f}, a strong resonance (0, 1/4, 1/3, 1/2): the "
          "torus is not born from the point as a smooth circle",
          rho);
      return result;
    }
  }

  // The first circle: x₀ + ε(Re v cos θ − Im v sin θ), ‖v ./ scale‖ = 1.
  const Vector scale = system->StateScale();
  const Eigen::VectorXcd v = eigen.eigenvectors().col(critical);
  const double size = std::sqrt(v.real().cwiseQuotient(scale).squaredNorm() +
                                v.imag().cwiseQuotient(scale).squaredNorm());
  std::unique_ptr<InvariantCircleProblem> circle =
      CircleProblem(system, family.kind, options.harmonics, options);
  InvariantCircleProblem& problem = *circle;
  // In the circle's coordinates: the centre y₀ = Ψ⁻¹(x₀), the directions D⁻¹ v.
  Matrix centre = Matrix::Zero(n, 2 * options.harmonics + 1), ellipse = centre;
  centre.col(0) = problem.ToCoordinates(at.starts.col(0));
  const Eigen::PartialPivLU<Matrix> chart(problem.CoordinateJacobian(centre.col(0)));
  ellipse.col(1) = chart.solve(Vector(v.real() / size));
  ellipse.col(2) = chart.solve(Vector(-v.imag() / size));
  const Vector u0 =
      problem.Pack(centre + options.amplitude * ellipse, rho, period, phi);
  problem.SetPhaseReference(u0);
  const Vector du = problem.Pack(ellipse, 0.0, 0.0, 0.0).cwiseQuotient(problem.Scale());

  Continuation stepper(problem, EngineOptions(options));
  stepper.StartWithTangent(u0, point.lambda, du, 0.0);
  Family tori = RunFamily(system, std::move(circle), stepper, options, on_step, result);
  result.ok = true;
  ReadEnd(tori, u0, options, result);
  return result;
}

TorusBranch ContinueTori(std::shared_ptr<OdeSystem> system, OrbitKind kind, const Vector& u0,
                         double lambda0, const TorusBranchOptions& options,
                         const StepCallback& on_step) {
  Validate(options);
  std::unique_ptr<InvariantCircleProblem> circle =
      CircleProblem(system, kind, options.harmonics, options);
  InvariantCircleProblem& problem = *circle;
  if (u0.size() != problem.Dimension()) {
    throw std::invalid_argument(fmt::format(
        "ContinueTori: the circle has {} unknowns; {} harmonics of {} states need {}", u0.size(),
        options.harmonics, problem.states(), problem.Dimension()));
  }
  problem.SetPhaseReference(u0);
  TorusBranch result;
  result.kind = kind;
  result.state_dimension = problem.states();
  result.harmonics = options.harmonics;
  result.coordinates = options.coordinates;
  Continuation stepper(problem, EngineOptions(options));
  if (stepper.Start(u0, lambda0) == StepResult::kFailed) {
    result.message = "the start did not converge: " + stepper.branch().message;
    return result;
  }
  Family tori = RunFamily(system, std::move(circle), stepper, options, on_step, result);
  result.ok = true;
  ReadEnd(tori, u0, options, result);
  return result;
}

namespace {

ContinuationOptions EngineOptions(const TorusBranchOptions& options) {
  ContinuationOptions continuation = options.continuation;
  continuation.bounds.lambda_min = options.lambda_min;
  continuation.bounds.lambda_max = options.lambda_max;
  continuation.detect.stability = false;
  continuation.bounds.end_at_grazing = !options.grazing.empty();
  return continuation;
}

// The tail event's level for circles of K harmonics: converged_tail while K can still double,
// else max_fourier_tail.
bool CanDouble(const TorusBranchOptions& options, int harmonics) {
  return options.max_harmonics > 0 && 2 * harmonics <= options.max_harmonics;
}
double TailBound(const TorusBranchOptions& options, int harmonics) {
  return CanDouble(options, harmonics) ? options.converged_tail : options.max_fourier_tail;
}

std::unique_ptr<InvariantCircleProblem> CircleProblem(std::shared_ptr<OdeSystem> system,
                                                      OrbitKind kind, int harmonics,
                                                      const TorusBranchOptions& options) {
  auto problem = std::make_unique<InvariantCircleProblem>(system, harmonics, kind,
                                                          options.integrator, options.coordinates);
  problem->SetMaxFourierTail(TailBound(options, harmonics));
  problem->SetMinRadius(options.min_radius);
  problem->SetGrazingTests(options.grazing);
  return problem;
}

// Whether the family ended at the located tail event.
bool EndedAtTail(const Branch& tori) {
  return tori.status == BranchStatus::kSwitchRefused && !tori.special_points.empty() &&
         tori.special_points.back().type == SpecialPointType::kEvent &&
         tori.special_points.back().label == kFourierTailReached;
}

// `segment`, continued from the last point of `branch` after its refinement to `harmonics`,
// appended: the points and special points before written in its layout (coarse's, padded: the
// same circles), the tail event the refinement answered dropped, arclengths and indices carried
// on, the statistics summed, the status and message the segment's.
void AppendSegment(Branch& branch, const InvariantCircleProblem& coarse, int harmonics,
                   Branch segment) {
  const Index dimension = coarse.Dimension();
  auto padded = [&](const Vector& u) {
    return CircleWithHarmonics(u, coarse.states(), coarse.harmonics(), harmonics);
  };
  auto pad = [&](Vector& u, Vector& tangent) {
    if (u.size() == dimension) u = padded(u);
    if (tangent.size() == dimension + 1) {
      const double lambda = tangent(dimension);
      const Vector head = padded(tangent.head(dimension));
      tangent.resize(head.size() + 1);
      tangent << head, lambda;
    }
  };
  for (BranchPoint& p : branch.points) pad(p.u, p.tangent);
  if (EndedAtTail(branch)) branch.special_points.pop_back();
  for (SpecialPoint& p : branch.special_points) pad(p.u, p.tangent);
  const Index offset = static_cast<Index>(branch.points.size());
  const double arclength = branch.points.empty() ? 0.0 : branch.points.back().arclength;
  for (BranchPoint& p : segment.points) {
    p.arclength += arclength;
    branch.points.push_back(std::move(p));
  }
  for (SpecialPoint& p : segment.special_points) {
    p.index += offset;
    branch.special_points.push_back(std::move(p));
  }
  branch.statistics += segment.statistics;
  branch.status = segment.status;
  branch.message = std::move(segment.message);
}

Family RunFamily(std::shared_ptr<OdeSystem> system, std::unique_ptr<InvariantCircleProblem> problem,
                 Continuation& stepper, const TorusBranchOptions& options,
                 const StepCallback& on_step, TorusBranch& result) {
  constexpr Index kTail = 1;  // Measures' "fourier_tail"
  // A segment whose start's tail already exceeds its K's bound is refined before it is continued
  // (the event would never fire from above).
  auto run = [&](Continuation& c, int harmonics) {
    const std::vector<BranchPoint>& points = c.branch().points;
    const bool refine_first = !points.empty() && CanDouble(options, harmonics) &&
                              points.front().measures(kTail) >= options.converged_tail;
    return refine_first || c.branch().status != BranchStatus::kRunning ? c.TakeBranch()
                                                                       : RunToEnd(c, on_step);
  };
  Family family;
  Branch branch = run(stepper, problem->harmonics());
  result.point_harmonics.assign(branch.points.size(), problem->harmonics());
  int steps = branch.statistics.steps;
  const int max_steps = options.continuation.bounds.max_steps;
  while (!branch.points.empty() && CanDouble(options, problem->harmonics())) {
    const int k = problem->harmonics();
    const BranchPoint last = branch.points.back();
    if (!EndedAtTail(branch) && !(last.measures(kTail) >= options.converged_tail)) break;
    if (steps >= max_steps) {
      family.unrefined = fmt::format("not refined to K = {}: the step limit ({}) was reached", 2 * k,
                                     max_steps);
      break;
    }
    std::unique_ptr<InvariantCircleProblem> finer = CircleProblem(system, problem->kind(), 2 * k, options);
    NewtonOptions newton;
    newton.residual_tolerance = options.continuation.corrector.residual_tolerance;
    newton.step_tolerance = options.continuation.corrector.step_tolerance;
    newton.max_iterations = 30;
    newton.max_step_halvings = 8;
    const CircleRefinement refined =
        RefineCircle(*problem, last.u, last.lambda, *finer, options.refinement_images, newton);
    if (!refined.converged) {
      family.unrefined = fmt::format("not refined to K = {}: {}", 2 * k, refined.failures);
      break;
    }
    finer->SetPhaseReference(refined.u);
    ContinuationOptions engine = EngineOptions(options);
    engine.bounds.max_steps = max_steps - steps;
    Continuation next(*finer, engine);
    const Index dimension = problem->Dimension();
    const StepResult started =
        last.tangent.size() == dimension + 1
            ? next.StartWithTangent(
                  refined.u, last.lambda,
                  CircleWithHarmonics(last.tangent.head(dimension), problem->states(), k, 2 * k),
                  last.tangent(dimension))
            : next.Start(refined.u, last.lambda);
    if (started == StepResult::kFailed) {
      family.unrefined = fmt::format("not continued at K = {}: its refined circle did not start: {}",
                                     2 * k, next.branch().message);
      break;
    }
    result.refinements.push_back({last.lambda, k, 2 * k, refined.images,
                                  problem->RotationNumber(last.u),
                                  finer->RotationNumber(next.branch().points.front().u),
                                  last.measures(kTail),
                                  next.branch().points.front().measures(kTail)});
    Branch segment = run(next, 2 * k);
    steps += segment.statistics.steps;
    result.point_harmonics.insert(result.point_harmonics.end(), segment.points.size(), 2 * k);
    AppendSegment(branch, *problem, 2 * k, std::move(segment));
    problem = std::move(finer);
  }
  result.branch = std::move(branch);
  result.harmonics = problem->harmonics();
  family.problem = std::move(problem);
  return family;
}

// The located event "circle shrinks onto its centre" a family ended at, or null.
const SpecialPoint* ShrinkEvent(const Branch& tori) {
  if (tori.status != BranchStatus::kSwitchRefused || tori.special_points.empty()) return nullptr;
  const SpecialPoint& last = tori.special_points.back();
  return last.type == SpecialPointType::kEvent && last.label == kShrinksOntoCentre ? &last : nullptr;
}

// Counts the tori not converged in K (TorusBranch::unconverged_in_k) and says which.
std::string ConvergenceInK(const TorusBranchOptions& options, TorusBranch& result) {
  const Branch& tori = result.branch;
  const Index tail = tori.MeasureIndex("fourier_tail");
  std::size_t first = 0, last = 0;
  double least = kInfinity, most = 0.0;
  result.unconverged_in_k = 0;
  for (std::size_t i = 0; i < tori.points.size(); ++i) {
    const double t = tori.points[i].measures(tail);
    if (result.SolvedHarmonics(i) < result.harmonics || !(t > options.converged_tail)) continue;
    if (result.unconverged_in_k++ == 0) first = i;
    last = i;
    least = std::min(least, t);
    most = std::max(most, t);
  }
  if (result.unconverged_in_k == 0) {
    return fmt::format("every torus converged in K (Fourier tail ≤ {:g})", options.converged_tail);
  }
  return fmt::format("{} of the {} tori, at K = {} (the finest) from λ = {:.9g} to {:.9g}, are not "
                     "converged in K: Fourier tails {:.2g} to {:.2g}, above {:g}",
                     result.unconverged_in_k, tori.points.size(), result.harmonics,
                     tori.points[first].lambda, tori.points[last].lambda, least, most,
                     options.converged_tail);
}

void ReadEnd(Family& family, const Vector& u0, const TorusBranchOptions& options,
             TorusBranch& result) {
  InvariantCircleProblem& problem = *family.problem;
  // How it ended: a harmonic standing out of the circle's decaying spectrum names the resonance.
  const Branch& tori = result.branch;
  const Vector end_u = tori.points.empty() ? u0 : tori.points.back().u;
  const double end_rho = problem.RotationNumber(end_u);
  auto harmonic = [&](int k) { return problem.HarmonicSize(end_u, k); };
  int standing = 0;  // the harmonic standing out most (0: K = 1, none can)
  double excess = 0.0;
  for (int k = 2; k <= problem.harmonics(); ++k) {
    const double ratio = harmonic(k) / std::max(harmonic(k - 1), 1e-300);
    if (ratio > excess) {
      excess = ratio;
      standing = k;
    }
  }
  // The resonance p:q in lowest terms: a multiple of q can stand out instead of q itself (C(a)'s
  // family refined to K = 32 ends with harmonic 30 standing out at ρ = 0.400342: 12:30, i.e. 2:5).
  int p = static_cast<int>(std::lround(standing * end_rho)), q = standing;
  if (q > 0) {
    const int common = std::gcd(p, q);
    p /= common;
    q /= common;
  }
  const double distance = q >= 2 ? std::abs(end_rho - static_cast<double>(p) / q) : 1.0;
  switch (tori.status) {
    case BranchStatus::kReachedLambdaBound: result.end = TorusEnd::kBound; break;
    case BranchStatus::kMaxSteps: result.end = TorusEnd::kSteps; break;
    case BranchStatus::kGrazing: result.end = TorusEnd::kGrazing; break;
    case BranchStatus::kSwitchRefused:
      result.end = ShrinkEvent(tori) ? TorusEnd::kShrinks
                   : excess >= kLockingExcess && distance <= 0.5 / (q * q) ? TorusEnd::kLocking
                                                                           : TorusEnd::kBreakdown;
      break;
    default: result.end = TorusEnd::kFailed; break;
  }
  if (!family.unrefined.empty()) result.end = TorusEnd::kFailed;
  const double bound = TailBound(options, problem.harmonics());
  const std::string spectrum =
      standing == 0 ? std::string()
      : excess >= kLockingExcess
          ? fmt::format("; harmonic {} stands out ({:.2g} × harmonic {}, {:.2g} of the first), "
                        "ρ − {}/{} = {:+.2e}",
                        standing, excess, standing - 1,
                        harmonic(standing) / std::max(harmonic(1), 1e-300), p, q,
                        end_rho - static_cast<double>(p) / q)
          : fmt::format("; no harmonic stands out (the largest step up, harmonic {} over {}, is "
                        "{:.2g})",
                        standing, standing - 1, excess);
  const std::string tail = fmt::format("the Fourier tail reached {:g} at ρ = {:.6f}{}", bound,
                                       end_rho, spectrum);
  if (result.end == TorusEnd::kLocking) {
    result.locking_p = p;
    result.locking_q = q;
  }
  const SpecialPoint* shrink = ShrinkEvent(tori);
  result.end_note =
      !family.unrefined.empty()
          ? fmt::format("the Fourier tail reached {:g} at K = {}, λ = {:.9g}, ρ = {:.6f}, and was {}",
                        bound, problem.harmonics(), tori.points.back().lambda, end_rho,
                        family.unrefined)
      : result.end == TorusEnd::kLocking
          ? fmt::format("phase locking near the {}:{} resonance: {}", p, q, tail)
      : result.end == TorusEnd::kBreakdown ? "breakdown: " + tail
      : result.end == TorusEnd::kGrazing
          ? fmt::format("the torus grazes: {} at λ = {:.9g} with ρ = {:.6f}",
                        tori.special_points.back().label, tori.points.back().lambda, end_rho)
      : result.end == TorusEnd::kShrinks
          ? fmt::format("the circle shrinks onto its centre: its radius reached {:g} at λ = {:.9g} "
                        "with ρ = {:.6f} (a Neimark–Sacker point of the orbit at its centre next "
                        "to it: ContinueCentreOrbits)",
                        options.min_radius, shrink->lambda, problem.RotationNumber(shrink->u))
                                           : fmt::format("{} at ρ = {:.6f}{}: {}", ToString(result.end),
                                                         end_rho, spectrum, tori.message);
  if (options.max_harmonics > 0) result.convergence_note = ConvergenceInK(options, result);

  if (options.lyapunov_iterates > 0) {
    for (const BranchPoint& torus : tori.points) {
      if (options.on_exponents) options.on_exponents(result.stability.size(), tori.points.size());
      result.stability.push_back(
          problem.LyapunovStability(torus.u, torus.lambda, options.lyapunov_iterates));
    }
  }
}

}  // namespace

LockedOrbits ContinueLockedOrbits(std::shared_ptr<OdeSystem> system,
                                  const PeriodicOrbitBranch& family, const TorusBranch& tori,
                                  const TorusBranchOptions& options,
                                  const StepCallback& on_step) {
  Validate(options);
  const std::vector<BranchPoint>& points = tori.branch.points;
  if (tori.end != TorusEnd::kLocking || points.empty() || tori.locking_q < 2) {
    throw std::invalid_argument(
        "ContinueLockedOrbits: the torus family did not end in phase locking at a p:q resonance");
  }
  LockedOrbits result;
  result.p = tori.locking_p;
  result.q = tori.locking_q;
  const int q = result.q;
  InvariantCircleProblem circle(system, tori.harmonics, tori.kind, options.integrator,
                                options.coordinates);
  const BranchPoint& last = points.back();
  const double period = circle.Period(last.u, last.lambda), phi = circle.Rotation(last.u);
  const double rho = circle.RotationNumber(last.u), target = static_cast<double>(result.p) / q;
  // Where ρ reaches p/q, from the slope of the last two tori (or 1e-3 of the parameter beyond).
  double step = 1e-3 * std::max(std::abs(last.lambda), 1.0);
  if (points.size() >= 2) {
    const BranchPoint& before = points[points.size() - 2];
    const double slope = (rho - circle.RotationNumber(before.u)) / (last.lambda - before.lambda);
    if (std::isfinite(slope) && slope != 0.0) step = (target - rho) / slope;
  }
  ShootingOptions shooting = family.shooting;
  shooting.refresh_phase_reference = true;
  shooting.segments = q * family.segments;
  shooting.mesh.clear();
  if (family.shooting.period_scale > 0.0) shooting.period_scale = q * family.shooting.period_scale;
  ContinuationOptions continuation = options.continuation;
  continuation.bounds.lambda_min = options.lambda_min;
  continuation.bounds.lambda_max = options.lambda_max;
  continuation.detect.stability = true;
  const Index tries = std::min<Index>(2 * tori.harmonics + 1, 5);
  std::string tried;
  for (const double factor : {1.0, 2.0, 3.0, 4.0}) {
    const double lambda = last.lambda + factor * step;
    if (lambda < options.lambda_min || lambda > options.lambda_max) break;
    for (Index j = 0; j < tries; ++j) {
      const double theta = kTwoPi * static_cast<double>(j) / (2 * tori.harmonics + 1);
      system->SetParameter(lambda);
      ShootingProblem problem(*system, tori.kind, shooting);
      const Vector u0 =
          problem.InitialGuess(circle.PointAt(last.u, theta), q * period, lambda, q * phi);
      // The locked orbits form a closed curve through the tongue's two edges.
      Branch branch =
          Continue(problem, u0, lambda, continuation, on_step, EndRoundClosedCurve(lambda));
      if (branch.status == BranchStatus::kStartFailed) continue;
      result.ok = true;
      result.orbits = FamilyOf(problem, shooting, lambda, std::move(branch));
      result.folds = DistinctFolds(result.orbits.branch);
      if (result.folds.size() == 2) {
        result.tori_inside = static_cast<std::size_t>(
            std::count_if(points.begin(), points.end(), [&](const BranchPoint& torus) {
              return torus.lambda > result.folds[0] && torus.lambda < result.folds[1];
            }));
      }
      result.message = fmt::format("found at λ = {:.9g} from the circle's point θ = {:.4f}", lambda,
                                   theta);
      return result;
    }
    tried += fmt::format("{}{:.9g}", tried.empty() ? "" : ", ", lambda);
  }
  result.message = fmt::format(
      "no {}-lap orbit converged from the last circle's first {} points at λ = {} (where ρ "
      "extrapolates to {}/{} and beyond)",
      q, tries, tried, result.p, q);
  return result;
}

CentreOrbits ContinueCentreOrbits(std::shared_ptr<OdeSystem> system, const TorusBranch& tori,
                                  PeriodicOrbitBranchOptions options) {
  Validate(options);
  const SpecialPoint* shrink = ShrinkEvent(tori.branch);
  if (tori.end != TorusEnd::kShrinks || shrink == nullptr) {
    throw std::invalid_argument(
        "ContinueCentreOrbits: the torus family did not end with its circle shrinking onto its "
        "centre");
  }
  CentreOrbits result;
  // From the located event's circle (radius min_radius): its centre lies that close to the orbit.
  // (The circle's integrator is not used: only its unknowns are read.)
  InvariantCircleProblem circle(system, tori.harmonics, tori.kind, IntegratorOptions{},
                                tori.coordinates);
  OrbitStart start;
  start.lambda = shrink->lambda;
  start.period = circle.Period(shrink->u, start.lambda);
  start.rotation = circle.Rotation(shrink->u);
  start.x0 = circle.Centre(shrink->u);
  start.valid = true;
  // The point lies next to the start, in the direction the family moved in at its end (the
  // options' where its last two tori share λ).
  const std::vector<BranchPoint>& points = tori.branch.points;
  if (points.size() >= 2 && points.back().lambda != points[points.size() - 2].lambda) {
    options.direction = points.back().lambda > points[points.size() - 2].lambda ? 1 : -1;
  }
  result.orbits = ContinuePeriodicOrbits(*system, tori.kind, start, options);
  const Branch& branch = result.orbits.branch;
  if (branch.status == BranchStatus::kStartFailed) {
    result.message = fmt::format(
        "no orbit converged from the last circle's centre at λ = {:.9g} (T = {:.9g}, φ = {:.6g}): "
        "{}",
        start.lambda, start.period, start.rotation, branch.message);
    return result;
  }
  result.ok = true;
  if (const SpecialPoint* p = branch.FirstLocated(SpecialPointType::kNeimarkSacker)) {
    result.located = true;
    result.lambda = p->lambda;
    result.rotation_number = std::abs(std::arg(p->critical_value)) / kTwoPi;
  }
  result.message =
      result.located
          ? fmt::format("a Neimark–Sacker point at λ = {:.9g} with arg μ / 2π = {:.6f}, the "
                        "family's end at λ = {:.9g} with ρ = {:.6f}",
                        result.lambda, result.rotation_number, start.lambda,
                        circle.RotationNumber(shrink->u))
          : fmt::format("no Neimark–Sacker point located on the orbits from λ = {:.9g} ({})",
                        start.lambda, branch.message);
  return result;
}

}  // namespace rubcont
