#include "continuation/continuation.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include <fmt/core.h>

#include "continuation/branch_point.h"
#include "continuation/branch_switching.h"
#include "continuation/fold.h"
#include "continuation/scaled_system.h"
#include "continuation/spectrum_crossing.h"
#include "solvers/constants.h"
#include "solvers/linear_algebra.h"
#include "solvers/scalar_root.h"

namespace rubcont {

namespace {

// Tier 1 of docs/conventions.md: a broken internal invariant aborts, saying where and with which values.
[[noreturn]] void InvariantFailed(const char* file, int line, const char* condition,
                                  const std::string& values) {
  std::fprintf(stderr, "%s:%d: continuation invariant violated: %s (%s)\n", file, line, condition,
               values.c_str());
  std::abort();
}

#define RUBCONT_INVARIANT(condition, ...)                                  \
  do {                                                                     \
    if (!(condition)) {                                                    \
      InvariantFailed(__FILE__, __LINE__, #condition, fmt::format(__VA_ARGS__)); \
    }                                                                      \
  } while (false)

// What the detectors compare between consecutive points of one piece.
struct PointData {
  CorrectedPoint point;
  bool singular_start = false;  // a located branch point used as the first point
  Vector events;                // event margins, taken at arclength `events_sigma` from the point
  double events_sigma = 0.0;    // along its tangent (a probe point just after a switch), else 0
  Vector tests;                 // Problem::TestFunctions
  Spectrum spectrum;
  bool has_spectrum = false;    // stability computed and valid
  SpectrumCounts counts;
  std::string piece;
};

// A located zero on arclength.
struct ArcRoot {
  bool converged = false;
  bool found = false;  // a point is available (converged or the best bracket end)
  CorrectedPoint point;
  double sigma = 0.0;
  double value = 0.0;
  double last_step = 0.0;
  int evaluations = 0;
  // The sign change is a jump or a pole, not a zero: the bracket shrank a thousandfold and the
  // function at its ends is not below half its largest value at the first bracket's ends (at a
  // zero both would be near 0). E.g. a test function τ_Ω/τ_λ through a fold, or the k-th
  // eigenvalue of a spectrum whose order changes within the step.
  bool discontinuous = false;
  bool evaluation_failed = false;  // a trial point could not be corrected or evaluated
  double f_lower = 0.0;  // the function at the final bracket's ends
  double f_upper = 0.0;
};

// Predicate for a trial point: sets the test function value, false when it cannot be evaluated.
using ArcFunction = std::function<bool(const CorrectedPoint& point, double& value)>;

double Clamp(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

StepResult ResultOf(BranchStatus status) {
  if (status == BranchStatus::kRunning) return StepResult::kContinue;
  return IsFailure(status) ? StepResult::kFailed : StepResult::kStop;
}

}  // namespace

struct Continuation::Impl {
  Impl(Problem& problem_in, const ContinuationOptions& options_in)
      : problem(problem_in),
        options(options_in),
        system(problem_in, &branch.statistics),
        corrector(system, options_in.corrector) {
    branch.options = options;
    ds = options.step.initial;
  }

  // Declared first: `system` keeps a pointer to branch.statistics.
  Branch branch;
  Problem& problem;
  ContinuationOptions options;
  ScaledSystem system;
  BorderedCorrector corrector;

  PointData current;
  double ds = 0.0;
  // StepOptions::failure_memory: the bound on ds after a corrector failure, for ceiling_steps more
  // points.
  double ceiling = kInfinity;
  int ceiling_steps = 0;
  // StepOptions::curved_predictor: the accepted point before `current` on the same piece (empty at
  // a start and after a switch).
  Vector previous_x;
  bool started = false;
  bool stability_on = false;
  std::vector<std::string> event_names;
  std::vector<std::string> test_names;
  // The start, for closure.
  Vector start_x;
  Vector start_tangent;
  std::string start_piece;

  // ---- small helpers ----------------------------------------------------------------------

  double LambdaOf(const Vector& x) const { return system.LambdaOf(x); }

  StepResult End(BranchStatus status, std::string message) {
    branch.status = status;
    branch.message = std::move(message);
    return ResultOf(status);
  }

  void ReadPieceNames() {
    event_names = options.detect.events ? problem.EventNames() : std::vector<std::string>{};
    test_names =
        options.detect.test_functions ? problem.TestFunctionNames() : std::vector<std::string>{};
  }

  Vector EventsAt(const Vector& x) {
    if (event_names.empty()) return Vector();
    const Vector g = problem.EventFunctions(system.StateOf(x), LambdaOf(x));
    if (g.size() != static_cast<Index>(event_names.size())) {
      throw std::invalid_argument(
          fmt::format("Problem::EventFunctions returned {} values; EventNames() has {}", g.size(),
                      event_names.size()));
    }
    return g;
  }

  Vector TestsAt(const Vector& x) {
    if (test_names.empty()) return Vector();
    const Vector t = problem.TestFunctions(system.StateOf(x), LambdaOf(x));
    if (t.size() != static_cast<Index>(test_names.size())) {
      throw std::invalid_argument(
          fmt::format("Problem::TestFunctions returned {} values; TestFunctionNames() has {}",
                      t.size(), test_names.size()));
    }
    return t;
  }

  // The k-th test function along the arc (not evaluable where it is not finite).
  ArcFunction TestArc(Index k) {
    return [this, k](const CorrectedPoint& p, double& value) {
      value = TestsAt(p.x)(k);
      return std::isfinite(value);
    };
  }

  Spectrum StabilityAt(const Vector& x) {
    ++branch.statistics.stability_evaluations;
    return problem.Stability(system.StateOf(x), LambdaOf(x));
  }

  void ComputeStability(PointData& data) {
    data.has_spectrum = false;
    if (!stability_on) return;
    data.spectrum = StabilityAt(data.point.x);
    data.has_spectrum = data.spectrum.valid;
    if (data.has_spectrum) {
      data.counts = CountUnstable(data.spectrum, options.detect.imaginary_tolerance,
                                  problem.StabilityTolerance());
    }
  }

  void FillEventsAndTests(PointData& data) {
    data.events = EventsAt(data.point.x);
    data.events_sigma = 0.0;
    data.tests = TestsAt(data.point.x);
  }

  void AppendPoint(const PointData& data, double step) {
    BranchPoint point;
    system.ToUnscaled(data.point.x, point.u, point.lambda);
    point.measures = problem.Measures(point.u, point.lambda);
    if (point.measures.size() != static_cast<Index>(branch.measure_names.size())) {
      throw std::invalid_argument(
          fmt::format("Problem::Measures returned {} values; MeasureNames() has {}",
                      point.measures.size(), branch.measure_names.size()));
    }
    point.tangent = data.point.tangent;
    point.step = step;
    point.arclength = branch.points.empty() ? 0.0 : branch.points.back().arclength + step;
    point.newton_iterations = data.point.iterations;
    point.residual_norm = data.point.residual_norm;
    if (stability_on) {
      point.spectrum = data.spectrum;  // valid = false when the operator failed here
      if (data.has_spectrum) {
        point.num_unstable = data.spectrum.UnstableCount(problem.StabilityTolerance());
      }
    }
    point.piece = data.piece;
    branch.points.push_back(std::move(point));
    const BranchPoint& stored = branch.points.back();
    problem.PointAccepted(stored.u, stored.lambda);
  }

  SpecialPoint MakeSpecialPoint(SpecialPointType type, const CorrectedPoint& at) {
    SpecialPoint sp;
    sp.type = type;
    system.ToUnscaled(at.x, sp.u, sp.lambda);
    sp.measures = problem.Measures(sp.u, sp.lambda);
    sp.tangent = at.tangent;
    sp.index = static_cast<Index>(branch.points.size()) - 1;
    sp.piece = current.piece;
    sp.residual_norm = at.residual_norm;
    return sp;
  }

  // ---- points X(σ) on the branch near the current step --------------------------------------

  // Trial points with τ̂_kᵀ(X − x̂_k) = σ, corrected from a linear interpolation of the nearest
  // known ones; cached, so that every σ is corrected once. The two ends of the step are copied
  // into the cache only when a location needs it (most steps locate nothing).
  class Sampler {
   public:
    Sampler(Impl& impl, const PointData& from, const CorrectedPoint& end, double sigma_end)
        : impl_(impl), from_(from), end_(end), sigma_end_(sigma_end) {}

    bool At(double sigma, CorrectedPoint& out) {
      if (known_.empty()) {
        known_.push_back({0.0, from_.point});
        known_.push_back({sigma_end_, end_});
      }
      const std::pair<double, CorrectedPoint>* lo = nullptr;
      const std::pair<double, CorrectedPoint>* hi = nullptr;
      for (const auto& entry : known_) {
        if (entry.first == sigma) {
          out = entry.second;
          return true;
        }
        if (entry.first < sigma && (lo == nullptr || entry.first > lo->first)) lo = &entry;
        if (entry.first > sigma && (hi == nullptr || entry.first < hi->first)) hi = &entry;
      }
      Vector guess;
      // Their tangents' σ-components (nearly 1 on a step the angle test passed).
      const auto along = [this](const std::pair<double, CorrectedPoint>* p) {
        return from_.point.tangent.dot(p->second.tangent);
      };
      constexpr double kMinAlong = 0.5;
      if (lo != nullptr && hi != nullptr && impl_.options.step.curved_predictor &&
          along(lo) > kMinAlong && along(hi) > kMinAlong) {
        // The cubic Hermite arc between them, dX/dσ = τ/(τ̂_kᵀτ) at each (the corrector's).
        const double width = hi->first - lo->first;
        const double t = (sigma - lo->first) / width;
        const Vector m0 = lo->second.tangent / along(lo);
        const Vector m1 = hi->second.tangent / along(hi);
        guess = (2 * t * t * t - 3 * t * t + 1) * lo->second.x +
                (t * t * t - 2 * t * t + t) * width * m0 +
                (-2 * t * t * t + 3 * t * t) * hi->second.x + (t * t * t - t * t) * width * m1;
      } else if (lo != nullptr && hi != nullptr) {
        const double t = (sigma - lo->first) / (hi->first - lo->first);
        guess = (1.0 - t) * lo->second.x + t * hi->second.x;
      } else {
        guess = from_.point.x + sigma * from_.point.tangent;
      }
      const CorrectorStatus status = impl_.corrector.Correct(
          from_.point.x, from_.point.tangent, sigma, guess, out, true);
      if (status != CorrectorStatus::kConverged) return false;
      known_.push_back({sigma, out});
      return true;
    }

   private:
    Impl& impl_;
    const PointData& from_;
    const CorrectedPoint& end_;
    double sigma_end_;
    std::vector<std::pair<double, CorrectedPoint>> known_;
  };

  // Illinois on σ ∈ [a, b] for a function of trial points, fa and fb of opposite signs.
  ArcRoot LocateOnArc(Sampler& sampler, const ArcFunction& function, double a, double fa,
                      double b, double fb) {
    ArcRoot root;
    BracketedRootOptions root_options;
    root_options.max_evaluations = options.location.max_iterations;
    root_options.x_tolerance = options.location.step_tolerance;
    CorrectedPoint trial;
    auto f = [&](double sigma, double& value) {
      return sampler.At(sigma, trial) && function(trial, value);
    };
    const BracketedRootResult result = IllinoisRoot(f, a, fa, b, fb, root_options);
    root.converged = result.Converged();
    root.sigma = result.x;
    root.value = result.fx;
    root.last_step = result.last_step;
    root.evaluations = result.evaluations;
    root.f_lower = result.f_lower;
    root.f_upper = result.f_upper;
    root.evaluation_failed = result.status == BracketedRootStatus::kEvaluationFailed;
    root.discontinuous = result.status != BracketedRootStatus::kEvaluationFailed &&
                         result.upper - result.lower <= 1e-3 * std::abs(b - a) &&
                         std::max(std::abs(result.f_lower), std::abs(result.f_upper)) >
                             0.5 * std::max(std::abs(fa), std::abs(fb));
    root.found = sampler.At(result.x, root.point);
    return root;
  }

  // ---- starting ------------------------------------------------------------------------------

  void CheckStartArguments(const Vector& u0, double lambda0) {
    const Index n = problem.Dimension();
    if (u0.size() != n) {
      throw std::invalid_argument(fmt::format(
          "Continuation::Start: u0 has {} entries; the problem's Dimension() = {}", u0.size(), n));
    }
    if (!u0.allFinite() || !std::isfinite(lambda0)) {
      throw std::invalid_argument("Continuation::Start: u0 or lambda0 is not finite");
    }
    if (lambda0 < options.bounds.lambda_min || lambda0 > options.bounds.lambda_max) {
      throw std::invalid_argument(fmt::format(
          "Continuation::Start: lambda0 = {} lies outside the bounds [{}, {}]", lambda0,
          options.bounds.lambda_min, options.bounds.lambda_max));
    }
    for (const Vector* box : {&options.bounds.state_lower, &options.bounds.state_upper}) {
      if (box->size() != 0 && box->size() != n) {
        throw std::invalid_argument(fmt::format(
            "ContinuationOptions.bounds.state_{} has {} entries: must be empty or Dimension() = "
            "{}",
            box == &options.bounds.state_lower ? "lower" : "upper", box->size(), n));
      }
    }
    if (started) {
      throw std::invalid_argument("Continuation::Start: this stepper has already been started");
    }
  }

  void Prepare() {
    system.Refresh();
    corrector.Resize();
    stability_on = options.detect.stability && problem.HasStability();
    branch.measure_names = problem.MeasureNames();
    ReadPieceNames();
    started = true;
  }

  // Stores `data` (already corrected, with an oriented tangent) as the first point.
  StepResult FinishStart(PointData& data) {
    data.piece = problem.PieceLabel();
    FillEventsAndTests(data);
    if (!data.singular_start) {
      for (Index k = 0; k < data.events.size(); ++k) {
        if (data.events(k) < 0.0) {
          return End(BranchStatus::kStartFailed,
                     fmt::format("the start point violates event margin '{}' = {:.6g} < 0 on "
                                 "piece '{}' (margins must be ≥ 0 on the valid piece)",
                                 event_names[k], data.events(k), data.piece));
        }
      }
    }
    ComputeStability(data);
    current = data;
    previous_x.resize(0);
    AppendPoint(current, 0.0);
    start_x = current.point.x;
    start_tangent = current.point.tangent;
    start_piece = current.piece;
    return StepResult::kContinue;
  }

  // Corrects x on the hyperplane normal to `border` through x, then orients the tangent along
  // `orientation` (its λ-component sign when `by_lambda`, else its dot product).
  StepResult CorrectStart(const Vector& x0, const Vector& border, int direction,
                          bool orient_by_lambda) {
    PointData data;
    CorrectorStatus status = corrector.Correct(x0, border, 0.0, x0, data.point);
    std::string first_failure;
    if (status != CorrectorStatus::kConverged && orient_by_lambda) {
      // F_u may be singular at λ0 (a fold): correct along the SVD null vector of DF̂ instead.
      first_failure = ToString(status);
      Matrix DF;
      if (system.Jacobian(x0, DF)) {
        const Vector null = SmallestSingularVectors(DF, 1).right.col(0);
        status = corrector.Correct(x0, null, 0.0, x0, data.point);
      }
    }
    if (status != CorrectorStatus::kConverged) {
      return End(BranchStatus::kStartFailed,
                 fmt::format("the start point at λ = {:.10g} could not be corrected: {}{}",
                             LambdaOf(x0), ToString(status),
                             first_failure.empty() ? "" : " (at fixed λ: " + first_failure + ")"));
    }
    if (!first_failure.empty()) {
      branch.start_note = fmt::format(
          "the start corrected along the null vector from λ = {:.10g} to {:.10g} (at fixed λ: {})",
          LambdaOf(x0), LambdaOf(data.point.x), first_failure);
    }
    Vector tangent = data.point.tangent;
    const double along = orient_by_lambda ? tangent(system.n()) : tangent.dot(border);
    if (along * direction < 0.0) tangent = -tangent;
    if (!corrector.TangentAt(data.point.x, tangent, data.point.tangent, data.point.det)) {
      return End(BranchStatus::kStartFailed,
                 fmt::format("the bordered Jacobian is singular at the start point λ = {:.10g}",
                             LambdaOf(data.point.x)));
    }
    return FinishStart(data);
  }

  // ---- detection and location in one interval -------------------------------------------------

  // Special points between `from` and `to` (σ from 0 to sigma_end), sorted by σ.
  // `located_tests`: the problem's test functions whose zero in the step is already located (a
  // grazing that ends the branch).
  std::vector<SpecialPoint> Detect(Sampler& sampler, const PointData& from, const PointData& to,
                                   double sigma_end, const std::vector<Index>& located_tests) {
    std::vector<std::pair<double, SpecialPoint>> found;
    if (from.singular_start) return {};
    const Index n = system.n();
    const bool locate = options.detect.locate;
    bool fold_or_branch_point = false;

    // Folds.
    if (options.detect.folds && from.point.tangent(n) * to.point.tangent(n) < 0.0) {
      fold_or_branch_point = true;
      found.push_back(LocateFoldIn(sampler, from, to, sigma_end, locate));
    }

    // Simple branch points.
    if (options.detect.branch_points && from.point.det.sign * to.point.det.sign < 0) {
      // det at σ = 0 with this step's border (the stored one used the previous tangent).
      Vector tangent0;
      LogDeterminant det0;
      if (corrector.TangentAt(from.point.x, from.point.tangent, tangent0, det0) &&
          det0.sign != 0) {
        const double reference = det0.log_abs;
        ArcFunction psi = [reference](const CorrectedPoint& p, double& value) {
          // det.sign = 0: the trial point is singular, i.e. the branch point itself.
          value = p.det.sign == 0 ? 0.0 : p.det.sign * std::exp(p.det.log_abs - reference);
          return std::isfinite(value);
        };
        const double fa = det0.sign;
        const double fb = to.point.det.sign * std::exp(to.point.det.log_abs - reference);
        // With this step's border the determinant may keep its sign: the change was the border's
        // (met on A(a)'s modulated whip), not a branch point in this step.
        if (fa * fb < 0.0) {
          fold_or_branch_point = true;
          found.push_back(LocateBranchPointIn(sampler, psi, fa, fb, from, to, sigma_end, locate));
        }
      }
    }

    // Eigenvalue and multiplier crossings.
    if (stability_on && from.has_spectrum && to.has_spectrum) {
      const int total_change = to.counts.total - from.counts.total;
      // Where every kind keeps its number of values over the step, the unstable counts say which
      // kind crossed. Where a complex pair collided on the real axis (or two real values became a
      // pair) they may not — a collision moves values between kinds, and the step's end may
      // count a real crossing for a Hopf point — and the sign changes of SpectralProduct do. So
      // a kind is examined where its count changed (and then kept only if located, or if no
      // collision explains the change) or, where the kinds changed, where its product's sign did.
      const double imaginary_tolerance = options.detect.imaginary_tolerance;
      const bool kinds_changed = KindSizes(from.spectrum, imaginary_tolerance) !=
                                 KindSizes(to.spectrum, imaginary_tolerance);
      for (int kind = 0; kind < kSpectralKinds; ++kind) {
        const SpectralKind spectral_kind = static_cast<SpectralKind>(kind);
        const int change = to.counts.unstable[kind] - from.counts.unstable[kind];
        const bool counted =
            change != 0 && total_change != 0 && (change > 0) == (total_change > 0);
        const bool product_changes = kinds_changed && ProductChanges(from, to, spectral_kind);
        if (!counted && !product_changes) continue;
        const SpecialPointType type = CrossingType(spectral_kind);
        if ((type == SpecialPointType::kRealEigenvalueCrossing ||
             type == SpecialPointType::kMultiplierPlusOne) &&
            fold_or_branch_point) {
          continue;  // already reported as a fold or branch point
        }
        auto entry = LocateCrossing(sampler, from, to, sigma_end, spectral_kind, counted,
                                    kinds_changed, locate);
        if (entry) found.push_back(std::move(*entry));
      }
    }

    // The problem's own test functions.
    if (from.tests.size() == to.tests.size()) {
      for (Index k = 0; k < from.tests.size(); ++k) {
        if (!(from.tests(k) * to.tests(k) < 0.0)) continue;
        if (std::find(located_tests.begin(), located_tests.end(), k) != located_tests.end()) {
          continue;
        }
        const ArcFunction psi = TestArc(k);
        // A test function's sign change through a pole or a jump is no special point (the knee
        // test dΩ/dω − ½R/C of rotating waves at a fold, which is reported as the fold).
        bool not_a_zero = false;
        auto entry = FromArc(problem.TestFunctionType(static_cast<int>(k)), sampler, psi,
                             from.tests(k), to.tests(k), to, sigma_end, locate, &not_a_zero);
        if (not_a_zero) continue;
        entry.second.label = test_names[k];
        found.push_back(std::move(entry));
      }
    }

    std::sort(found.begin(), found.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    // A fold of the continuation parameter at the same point as a higher-codimension test zero
    // (a cusp of a fold curve turns back in η there): keep the latter, say so.
    std::vector<SpecialPoint> result;
    for (auto& entry : found) result.push_back(std::move(entry.second));
    for (size_t i = 0; i < result.size(); ++i) {
      if (result[i].type != SpecialPointType::kFold) continue;
      for (size_t j = 0; j < result.size(); ++j) {
        if (j == i || result[j].type == SpecialPointType::kFold ||
            result[j].type == SpecialPointType::kBranchPoint ||
            result[j].type == SpecialPointType::kEvent) {
          continue;
        }
        if (SamePoint(result[i], result[j])) {
          result[j].note += (result[j].note.empty() ? "" : "; ") +
                            std::string("the branch also turns back in its parameter here (a "
                                        "fold at the same point)");
          result.erase(result.begin() + static_cast<std::ptrdiff_t>(i));
          --i;
          break;
        }
      }
    }
    return result;
  }

  // Two special points located at the same point of the branch (to the location tolerance).
  bool SamePoint(const SpecialPoint& a, const SpecialPoint& b) const {
    Vector xa, xb;
    system.ToScaled(a.u, a.lambda, xa);
    system.ToScaled(b.u, b.lambda, xb);
    return (xa - xb).lpNorm<Eigen::Infinity>() <=
           1e3 * options.location.step_tolerance * std::max(1.0, xa.lpNorm<Eigen::Infinity>());
  }

  // Appends a special point found in the last step. A real value's crossing is the fold or branch
  // point at the same point when one was found there in a neighbouring step: the crossing is
  // located on its spectral product from where it crosses the stability tolerance (which decides
  // the counts) to where it crosses 0, and that may lie in the next step (case default, RCI ratio
  // 0.855: a pair meets on the real axis, and one of the two values crosses 0.1 s⁻¹ one step
  // before the fold where it crosses 0). Keeps the fold or branch point.
  void AddSpecialPoint(SpecialPoint sp) {
    auto is_fold = [](const SpecialPoint& p) {
      return p.type == SpecialPointType::kFold || p.type == SpecialPointType::kBranchPoint;
    };
    auto is_real_crossing = [](const SpecialPoint& p) {
      return p.type == SpecialPointType::kRealEigenvalueCrossing ||
             p.type == SpecialPointType::kMultiplierPlusOne;
    };
    if (!branch.special_points.empty()) {
      SpecialPoint& last = branch.special_points.back();
      if (is_real_crossing(sp) && is_fold(last) && SamePoint(sp, last)) return;
      if (is_fold(sp) && is_real_crossing(last) && SamePoint(sp, last)) {
        last = std::move(sp);
        return;
      }
    }
    branch.special_points.push_back(std::move(sp));
  }

  // A special point located by Illinois on ψ along arclength, with its σ for sorting.
  // `discontinuous` (optional) is set when the sign change is a jump or a pole (ArcRoot).
  std::pair<double, SpecialPoint> FromArc(SpecialPointType type, Sampler& sampler,
                                          const ArcFunction& psi, double fa, double fb,
                                          const PointData& to, double sigma_end, bool locate,
                                          bool* discontinuous = nullptr) {
    if (locate) {
      const ArcRoot root = LocateOnArc(sampler, psi, 0.0, fa, sigma_end, fb);
      if (discontinuous != nullptr) *discontinuous = root.found && root.discontinuous;
      if (root.found) {
        SpecialPoint sp = MakeSpecialPoint(type, root.point);
        sp.converged = root.converged && !root.discontinuous;
        sp.iterations = root.evaluations;
        sp.test_value = root.value;
        sp.last_correction = root.last_step;
        if (root.discontinuous) {
          sp.note = fmt::format("not a zero: the function jumps from {:.4g} to {:.4g} within the "
                                "bracket (from {:.4g} and {:.4g} at the step's ends)",
                                root.f_lower, root.f_upper, fa, fb);
        } else if (!root.converged) {
          sp.note = "not located to tolerance: a guess within the bracket";
        }
        return {root.sigma, sp};
      }
    }
    // Not located: record the end of the interval nearer to the zero.
    const bool at_end = std::abs(fb) < std::abs(fa);
    SpecialPoint sp = MakeSpecialPoint(type, at_end ? to.point : current.point);
    sp.converged = false;
    sp.test_value = at_end ? fb : fa;
    sp.note = locate ? "location failed: the nearer end of the step" : "detected, not located";
    return {at_end ? sigma_end : 0.0, sp};
  }

  // A simple branch point between from and to: Newton on the branch-point system
  // (continuation/branch_point.h) from where the normalized det [DF̂; τ̂ᵀ] interpolates to 0, else
  // Illinois on that determinant along arclength (which stalls short of the point: the corrector
  // is singular there).
  std::pair<double, SpecialPoint> LocateBranchPointIn(Sampler& sampler, const ArcFunction& det,
                                                      double fa, double fb, const PointData& from,
                                                      const PointData& to, double sigma_end,
                                                      bool locate) {
    if (locate && system.n() + 1 <= options.location.branch_point_newton_max_unknowns) {
      const double theta = fa / (fa - fb);
      const Vector guess = from.point.x + theta * (to.point.x - from.point.x);
      const BranchPointLocation located = LocateBranchPoint(system, guess, options.location);
      const double sigma = from.point.tangent.dot(located.x - from.point.x);
      const bool inside = sigma >= -0.25 * sigma_end && sigma <= 1.25 * sigma_end &&
                          (located.x - guess).norm() <= 2.0 * sigma_end;
      if (located.converged && inside &&
          std::abs(located.beta) <= options.location.residual_tolerance) {
        CorrectedPoint at;
        at.x = located.x;
        at.tangent = from.point.tangent;  // the incoming branch's; branch switching projects it
        at.residual_norm = located.residual_norm;
        SpecialPoint sp = MakeSpecialPoint(SpecialPointType::kBranchPoint, at);
        sp.converged = true;
        sp.iterations = located.iterations;
        sp.last_correction = located.last_correction;
        sp.test_value = located.beta;
        return {sigma, sp};
      }
      auto entry = FromArc(SpecialPointType::kBranchPoint, sampler, det, fa, fb, to, sigma_end, locate);
      entry.second.note += (entry.second.note.empty() ? "" : "; ") +
                           fmt::format("located on det (the branch-point Newton: {})",
                                       located.converged ? "converged outside the step"
                                                         : located.message);
      entry.second.tangent = from.point.tangent;
      return entry;
    }
    // The tangent the corrector computes at a point ever closer to the branch point is any vector
    // of the nearly two-dimensional kernel (measured on A(a)'s modulated whip: the other branch's);
    // branch switching needs the incoming branch's.
    auto entry = FromArc(SpecialPointType::kBranchPoint, sampler, det, fa, fb, to, sigma_end, locate);
    entry.second.tangent = from.point.tangent;
    return entry;
  }

  std::pair<double, SpecialPoint> LocateFoldIn(Sampler& sampler, const PointData& from,
                                               const PointData& to, double sigma_end,
                                               bool locate) {
    const Index n = system.n();
    const double ta = from.point.tangent(n);
    const double tb = to.point.tangent(n);
    if (locate) {
      // Newton on the minimally augmented system from the point where τ̂_λ interpolates to 0.
      const double theta = ta / (ta - tb);
      const Vector guess = from.point.x + theta * (to.point.x - from.point.x);
      const FoldLocation fold =
          LocateFold(problem, system.StateOf(guess), LambdaOf(guess), options.location);
      Vector x;
      system.ToScaled(fold.u, fold.lambda, x);
      const double sigma = from.point.tangent.dot(x - from.point.x);
      const bool inside = sigma >= -0.25 * sigma_end && sigma <= 1.25 * sigma_end &&
                          (x - guess).norm() <= 2.0 * sigma_end;
      CorrectedPoint at;
      at.x = x;
      if (fold.converged && inside &&
          corrector.TangentAt(x, from.point.tangent, at.tangent, at.det)) {
        SpecialPoint sp = MakeSpecialPoint(SpecialPointType::kFold, at);
        sp.converged = true;
        sp.iterations = fold.iterations;
        sp.residual_norm = fold.residual_norm;
        sp.test_value = fold.test_value;
        sp.last_correction = fold.last_correction;
        return {sigma, sp};
      }
    }
    // Fallback (or locate = false): Illinois on τ̂_λ along arclength.
    ArcFunction psi = [n](const CorrectedPoint& p, double& value) {
      value = p.tangent(n);
      return true;
    };
    auto entry = FromArc(SpecialPointType::kFold, sampler, psi, ta, tb, to, sigma_end, locate);
    if (locate) {
      entry.second.note += (entry.second.note.empty() ? "" : "; ") +
                           std::string("located on τ_λ (the minimally augmented Newton failed)");
    }
    return entry;
  }

  // A crossing of `kind` between from and to. `by_counts`: the unstable counts of the kind changed:
  // located on the order statistic of the kind, and where that jumps, stalls or is unavailable,
  // on SpectralProduct. Otherwise the product's sign changed where the kinds changed over the
  // step (`kinds_changed`): located on the product. Empty when it is no crossing: the product's
  // zero is a neutral saddle, a complex pair crossing that the unstable counts do not need
  // (FewestPairCrossings = 0), or a change of the counts that a collision explains.
  std::optional<std::pair<double, SpecialPoint>> LocateCrossing(
      Sampler& sampler, const PointData& from, const PointData& to, double sigma_end,
      SpectralKind kind, bool by_counts, bool kinds_changed, bool locate) {
    const SpecialPointType type = CrossingType(kind);
    // Two real values that meet in the step make a pair: the counts then see a new pair, and the
    // pair product may change sign, without any pair crossing the boundary. Case A(a), tanh law:
    // on the Mode 2 whirl at its 52.33 rpm branch point an unstable real value and one that crossed
    // 0 form a pair while a stable pair splits (one more unstable value; the order statistic jumps
    // and the pair product's zero is a neutral saddle); on the Mode 2 whip at its 90.476 rpm fold
    // the value that crossed 0 meets a stable one (one fewer unstable value). Where the order
    // statistic did not locate it, a pair crossing is claimed only when the counts need one.
    const bool pair_needed = !IsPairKind(kind) || FewestPairCrossings(from, to) != 0;
    if (!by_counts) {
      if (!pair_needed) return std::nullopt;
      if (locate) {
        bool neutral_saddle = false;
        auto entry = LocateOnProduct(sampler, from, to, sigma_end, kind, neutral_saddle);
        if (entry) return entry;
        if (neutral_saddle) return std::nullopt;
      }
      SpecialPoint sp = MakeSpecialPoint(type, to.point);
      sp.note = locate ? "located neither on the order statistic nor on the spectral product"
                       : "detected, not located";
      return std::make_pair(sigma_end, sp);
    }
    auto entry = LocateOnOrderStatistic(sampler, from, to, sigma_end, kind, locate);
    if (!locate || entry.second.converged) return entry;
    if (!pair_needed) return std::nullopt;
    bool neutral_saddle = false;
    auto on_product = LocateOnProduct(sampler, from, to, sigma_end, kind, neutral_saddle);
    if (on_product) {
      on_product->second.note = "located on the spectral product; the order statistic: " +
                                entry.second.note;
      return on_product;
    }
    // The kinds changed over the step and the product changes no sign, or only at a neutral
    // saddle: the counts' change is the collision's (e.g. a pair met on the real axis: two more
    // unstable real values, one pair fewer).
    if (kinds_changed && (!ProductChanges(from, to, kind) || neutral_saddle)) return std::nullopt;
    return entry;
  }

  // SpectralProduct of `kind`, its boundary at the counts' tolerance, changes sign from `from`
  // to `to`.
  bool ProductChanges(const PointData& from, const PointData& to, SpectralKind kind) const {
    const double shift = problem.StabilityTolerance();
    return SpectralProduct(from.spectrum, kind, shift).sign *
               SpectralProduct(to.spectrum, kind, shift).sign <
           0;
  }

  // The fewest complex pairs crossing the boundary that explain the change Δ of the unstable
  // count over the step: Δ = 2h + r, r the net number of real values crossing, odd exactly when
  // an odd number of the real kinds' products change sign; h = (Δ − r) / 2 with the smallest |r|
  // of that parity.
  int FewestPairCrossings(const PointData& from, const PointData& to) const {
    bool odd = false;
    for (SpectralKind kind : {SpectralKind::kRealEigenvalue, SpectralKind::kRealPositiveMultiplier,
                              SpectralKind::kRealNegativeMultiplier}) {
      odd = odd != ProductChanges(from, to, kind);
    }
    const int delta = to.counts.total - from.counts.total;
    const int r = odd ? (delta >= 0 ? 1 : -1) : 0;
    return (delta - r) / 2;
  }

  // Illinois on SpectralProduct (continuation/spectrum_crossing.h) along arclength, its boundary
  // at the counts' tolerance, then RefineToBoundary: empty when its sign does not change over the
  // step or the location fails; `neutral_saddle` set when its zero is a neutral saddle.
  std::optional<std::pair<double, SpecialPoint>> LocateOnProduct(
      Sampler& sampler, const PointData& from, const PointData& to, double sigma_end,
      SpectralKind kind, bool& neutral_saddle) {
    const double shift = problem.StabilityTolerance();
    const LogDeterminant pa = SpectralProduct(from.spectrum, kind, shift);
    const LogDeterminant pb = SpectralProduct(to.spectrum, kind, shift);
    if (pa.sign * pb.sign >= 0) return std::nullopt;
    const double reference = std::max(pa.log_abs, pb.log_abs);
    ArcFunction psi = [&, this](const CorrectedPoint& p, double& value) {
      const Spectrum spectrum = StabilityAt(p.x);
      if (!spectrum.valid) return false;
      const LogDeterminant product = SpectralProduct(spectrum, kind, shift);
      value = product.sign * std::exp(product.log_abs - reference);
      return std::isfinite(value);
    };
    // A zero that is a neutral saddle leaves an odd number of zeros on one side of it (the sign
    // changes over the step): look there, a few times.
    double a = 0.0, fa = pa.sign * std::exp(pa.log_abs - reference);
    double b = sigma_end, fb = pb.sign * std::exp(pb.log_abs - reference);
    ArcRoot root;
    SpectralValue critical;
    for (int attempt = 0;; ++attempt) {
      root = LocateOnArc(sampler, psi, a, fa, b, fb);
      if (!root.found || !root.converged || root.discontinuous) return std::nullopt;
      const Spectrum spectrum = StabilityAt(root.point.x);
      if (!spectrum.valid) return std::nullopt;
      if (CriticalValueAtZero(spectrum, kind, options.detect.imaginary_tolerance, shift,
                              critical)) {
        break;
      }
      neutral_saddle = true;
      const double gap = 1e-6 * std::abs(b - a);
      double f_left = 0.0, f_right = 0.0;
      CorrectedPoint p;
      if (attempt == 3 || !sampler.At(root.sigma - gap, p) || !psi(p, f_left) ||
          !sampler.At(root.sigma + gap, p) || !psi(p, f_right)) {
        return std::nullopt;
      }
      if (fa * f_left < 0.0) {
        b = root.sigma - gap;
        fb = f_left;
      } else if (f_right * fb < 0.0) {
        a = root.sigma + gap;
        fa = f_right;
      } else {
        return std::nullopt;
      }
    }
    neutral_saddle = false;
    double sigma = root.sigma;
    CorrectedPoint at = root.point;
    int iterations = root.evaluations;
    double last_step = root.last_step;
    std::string note = "located on the spectral product";
    if (shift != 0.0) {
      // The boundary is looked for near the step only (as the fold and branch-point Newtons'
      // results are accepted): a value that crosses 0 far from where it crosses the tolerance is a
      // marginal one, located where it crosses the tolerance, as LocateOnOrderStatistic does.
      double refined_sigma = sigma, refined_step = last_step;
      CorrectedPoint refined_at = at;
      SpectralValue refined_critical = critical;
      int refined_iterations = iterations;
      if (RefineToBoundary(sampler, kind, refined_sigma, refined_at, refined_critical,
                           refined_iterations, refined_step) &&
          refined_sigma >= -0.25 * sigma_end && refined_sigma <= 1.25 * sigma_end) {
        sigma = refined_sigma;
        at = refined_at;
        critical = refined_critical;
        iterations = refined_iterations;
        last_step = refined_step;
      } else {
        note += fmt::format(", where the critical value crosses the stability tolerance {:g}, "
                            "not the boundary (not reached from there within the step)",
                            shift);
      }
    }
    SpecialPoint sp = MakeSpecialPoint(CrossingType(kind), at);
    sp.converged = true;
    sp.iterations = iterations;
    sp.test_value = critical.measure;
    sp.last_correction = last_step;
    sp.critical_value = critical.value;
    SetFrequency(sp);
    sp.note = note;
    return std::make_pair(sigma, sp);
  }

  // From the point where the critical value's measure crosses the stability tolerance (the
  // product's boundary) to where it crosses 0: secant steps on arclength, the value followed by
  // continuity (at each trial, the value of its kind nearest the last one; over an arc this short
  // it is not confused with another). On success updates the point, its σ and value, the
  // evaluation count and the last step; false (nothing changed) when a trial fails, the nearest
  // value is not clearly the nearest, or the secant does not converge.
  bool RefineToBoundary(Sampler& sampler, SpectralKind kind, double& sigma, CorrectedPoint& point,
                        SpectralValue& value, int& evaluations, double& last_step) {
    const double tolerance = options.location.step_tolerance;
    auto follow = [&](double s, const SpectralValue& previous, CorrectedPoint& p,
                      SpectralValue& v) {
      if (!sampler.At(s, p)) return false;
      const Spectrum spectrum = StabilityAt(p.x);
      if (!spectrum.valid) return false;
      const std::vector<SpectralValue> values =
          ValuesOfKind(spectrum, kind, options.detect.imaginary_tolerance);
      // The nearest value, if it is clearly the nearest (the matching is unambiguous).
      double best = kInfinity, second = best;
      for (const SpectralValue& candidate : values) {
        const double distance = std::abs(candidate.value - previous.value);
        if (distance < best) {
          second = best;
          best = distance;
          v = candidate;
        } else {
          second = std::min(second, distance);
        }
      }
      return best < 0.5 * second;
    };
    double s0 = sigma, m0 = value.measure;
    SpectralValue v0 = value;
    // A first probe a little way along the arc gives the secant its slope.
    double s1 = s0 + std::max(1e3 * tolerance, 1e-6 * std::max(1.0, std::abs(s0)));
    CorrectedPoint p1;
    SpectralValue v1;
    int count = 0;
    for (int iteration = 0; iteration < options.location.max_iterations; ++iteration) {
      ++count;
      if (!follow(s1, v0, p1, v1)) return false;
      const double m1 = v1.measure;
      const double step = (m1 == m0) ? 0.0 : -m1 * (s1 - s0) / (m1 - m0);
      if (!std::isfinite(step) || step == 0.0) return false;
      s0 = s1;
      m0 = m1;
      v0 = v1;
      s1 = s1 + step;
      if (std::abs(step) <= tolerance) {
        CorrectedPoint p2;
        SpectralValue v2;
        ++count;
        if (!follow(s1, v0, p2, v2)) return false;
        sigma = s1;
        point = p2;
        value = v2;
        evaluations += count;
        last_step = std::abs(step);
        return true;
      }
    }
    return false;
  }

  static void SetFrequency(SpecialPoint& sp) {
    if (sp.type == SpecialPointType::kHopf) sp.frequency = std::abs(sp.critical_value.imag());
    if (sp.type == SpecialPointType::kNeimarkSacker) {
      sp.frequency = std::abs(std::arg(sp.critical_value));
    }
  }

  // Illinois on the (k+1)-th largest measure of the kind (continuation/spectrum_crossing.h).
  std::pair<double, SpecialPoint> LocateOnOrderStatistic(Sampler& sampler, const PointData& from,
                                                         const PointData& to, double sigma_end,
                                                         SpectralKind kind, bool locate) {
    const double imaginary_tolerance = options.detect.imaginary_tolerance;
    const auto k = static_cast<size_t>(
        std::min(from.counts.unstable[static_cast<int>(kind)],
                 to.counts.unstable[static_cast<int>(kind)]));
    auto critical = [&](const Spectrum& spectrum, SpectralValue& value) {
      const std::vector<SpectralValue> values =
          ValuesOfKind(spectrum, kind, imaginary_tolerance);
      if (values.size() <= k) return false;
      value = values[k];
      return true;
    };
    SpectralValue va, vb;
    const SpecialPointType type = CrossingType(kind);
    if (!critical(from.spectrum, va) || !critical(to.spectrum, vb)) {
      SpecialPoint sp = MakeSpecialPoint(type, to.point);
      sp.note = "detected from the unstable counts; no continuous critical value to locate";
      return {sigma_end, sp};
    }
    // Locate the boundary itself (Re μ = 0, |μ| = 1). The counts use StabilityTolerance: when a
    // value within that tolerance of the boundary makes both ends lie on one side of it, locate
    // where the value crosses the tolerance instead.
    const double shift =
        va.measure * vb.measure <= 0.0 ? 0.0 : problem.StabilityTolerance();
    SpectralValue located = vb;
    ArcFunction psi = [&, this](const CorrectedPoint& p, double& value) {
      const Spectrum spectrum = StabilityAt(p.x);
      SpectralValue v;
      if (!spectrum.valid || !critical(spectrum, v)) return false;
      value = v.measure - shift;
      located = v;
      return true;
    };
    auto entry = FromArc(type, sampler, psi, va.measure - shift, vb.measure - shift, to,
                         sigma_end, locate);
    // The critical value at the returned point (re-evaluated if the last trial was elsewhere).
    SpecialPoint& sp = entry.second;
    if (locate) {
      Vector x;
      system.ToScaled(sp.u, sp.lambda, x);
      const Spectrum spectrum = StabilityAt(x);
      if (spectrum.valid) critical(spectrum, located);
    }
    sp.critical_value = located.value;
    if (shift != 0.0) {
      sp.note += fmt::format("{}located where the critical value crosses the stability tolerance "
                             "{:g}, not the boundary: it lies on one side of the boundary at both "
                             "ends of the step (a marginal value)",
                             sp.note.empty() ? "" : "; ", shift);
    }
    SetFrequency(sp);
    return entry;
  }

  // ---- one step ------------------------------------------------------------------------------

  bool OutsideStateBounds(const Vector& x, std::string& why) const {
    const Index n = system.n();
    const BoundsOptions& bounds = options.bounds;
    const Vector u = system.StateOf(x);
    if (bounds.state_lower.size() == n) {
      for (Index i = 0; i < n; ++i) {
        if (u(i) < bounds.state_lower(i)) {
          why = fmt::format("u({}) = {:.6g} < bounds.state_lower({}) = {:.6g}", i, u(i), i,
                            bounds.state_lower(i));
          return true;
        }
      }
    }
    if (bounds.state_upper.size() == n) {
      for (Index i = 0; i < n; ++i) {
        if (u(i) > bounds.state_upper(i)) {
          why = fmt::format("u({}) = {:.6g} > bounds.state_upper({}) = {:.6g}", i, u(i), i,
                            bounds.state_upper(i));
          return true;
        }
      }
    }
    const double norm = x.head(n).lpNorm<Eigen::Infinity>();
    if (norm > bounds.max_state_norm) {
      why = fmt::format("‖u ./ Scale()‖∞ = {:.6g} > bounds.max_state_norm = {:.6g}", norm,
                        bounds.max_state_norm);
      return true;
    }
    return false;
  }

  StepResult StepOnce() {
    if (!started) {
      throw std::invalid_argument("Continuation::Step called before Start");
    }
    if (branch.status != BranchStatus::kRunning) return ResultOf(branch.status);
    const StepOptions& step = options.step;
    // At most this many shorter tries of a step that may have jumped to another branch (Advance):
    // a margin or a special point can also fail to be located for other reasons (a branch that
    // nears a singular point, a contact's force → 0). Ten: a tanh whip that meets the rolling
    // line changes within 1e-3 of a step where its slip falls to the law's velocity scale (random
    // scene 61 of seed 1); four halvings did not resolve it.
    constexpr int kMaxJumpRejections = 10;
    int rejections = 0;
    for (;;) {
      CorrectedPoint candidate;
      double sigma = ds;
      double angle = 0.0;
      if (!CorrectStep(candidate, sigma, angle)) return ResultOf(branch.status);
      const double iteration_factor =
          std::pow(2.0, 0.5 * (step.target_iterations - candidate.iterations));
      const double angle_factor = angle > 0.0 ? step.target_angle / angle : step.max_growth;
      const double factor = Clamp(std::min(iteration_factor, angle_factor), 0.5, step.max_growth);
      double next_ds = Clamp(ds * factor, step.min, step.max);
      if (ceiling_steps > 0) next_ds = std::max(std::min(next_ds, ceiling), step.min);
      RUBCONT_INVARIANT(std::abs(candidate.tangent.norm() - 1.0) <= 1e-12 &&
                            candidate.tangent.dot(current.point.tangent) > 0.0,
                        "|τ| = {}, τ_k·τ_(k+1) = {}", candidate.tangent.norm(),
                        candidate.tangent.dot(current.point.tangent));
      const bool shortest = ds <= step.min * (1.0 + 1e-12) || rejections == kMaxJumpRejections;
      bool left_branch = false;
      const StepResult result = Advance(candidate, sigma, shortest, left_branch);
      if (left_branch) {
        ++branch.statistics.jump_rejections;
        ++rejections;
        ds = std::max(0.5 * ds, step.min);
        continue;
      }
      ds = next_ds;
      if (ceiling_steps > 0 && --ceiling_steps == 0) ceiling = kInfinity;
      return result;
    }
  }

  // The corrector's first iterate at arclength σ: x̂_k + σ τ̂_k, or with
  // StepOptions::curved_predictor the parabola x̂_k + σ τ̂_k + σ² c through the previous point
  // x̂_{k−1} (c = (x̂_{k−1} − x̂_k + h τ̂_k)/h², h = −τ̂_kᵀ(x̂_{k−1} − x̂_k), so c ⊥ τ̂_k and the guess
  // lies on the corrector's hyperplane τ̂_kᵀ(x̂ − x̂_k) = σ as the tangent's does). Its error is
  // O(σ³) where the tangent's is O(σ²): fewer Newton iterations per step, and longer steps for the
  // same target.
  Vector Predictor(double sigma) const {
    Vector guess = current.point.x + sigma * current.point.tangent;
    if (!options.step.curved_predictor || previous_x.size() != guess.size()) return guess;
    const Vector back = previous_x - current.point.x;
    const double h = -current.point.tangent.dot(back);
    if (!(h > 0.0)) return guess;  // the previous point is not behind: no parabola
    guess += (sigma * sigma / (h * h)) * (back + h * current.point.tangent);
    return guess;
  }

  // The corrector's point at arclength ds along the tangent, the step halved until it converges
  // and the tangent turns at most step.max_angle (or the step is the smallest): false when it
  // fails at the smallest step (the branch has ended, kStepTooSmall).
  bool CorrectStep(CorrectedPoint& candidate, double& sigma, double& angle) {
    const StepOptions& step = options.step;
    for (;;) {
      sigma = ds;
      const Vector guess = Predictor(sigma);
      const CorrectorStatus status =
          corrector.Correct(current.point.x, current.point.tangent, sigma, guess, candidate);
      const bool at_minimum = ds <= step.min * (1.0 + 1e-12);
      const std::string stray = status == CorrectorStatus::kConverged
                                    ? problem.StrayPoint(system.StateOf(candidate.x), LambdaOf(candidate.x))
                                    : std::string();
      if (status != CorrectorStatus::kConverged || !stray.empty()) {
        ++(stray.empty() ? branch.statistics.corrector_failures : branch.statistics.stray_rejections);
        if (step.failure_memory > 0) {
          constexpr double kCeilingFraction = 0.75;  // of the step that failed
          ceiling = std::min(ceiling_steps > 0 ? ceiling : kInfinity, kCeilingFraction * ds);
          ceiling_steps = step.failure_memory;
        }
        if (at_minimum) {
          End(BranchStatus::kStepTooSmall,
              stray.empty()
                  ? fmt::format("the corrector failed ({}) with the minimum step {:.3g} at λ = {:.10g}",
                                ToString(status), ds, LambdaOf(current.point.x))
                  : fmt::format("the corrector's point at the minimum step {:.3g} from λ = {:.10g} "
                                "continues no branch: {}", ds, LambdaOf(current.point.x), stray));
          return false;
        }
        ds = std::max(0.5 * ds, step.min);
        continue;
      }
      angle = std::acos(Clamp(candidate.tangent.dot(current.point.tangent), -1.0, 1.0));
      if (angle > step.max_angle && !at_minimum) {
        ++branch.statistics.angle_rejections;
        ds = std::max(0.5 * ds, step.min);
        continue;
      }
      RefineNearFold(candidate);
      return true;
    }
  }

  // The corrector's tangent comes from the Jacobian at its last iterate, near the point; where the
  // contact is stiff and nearly open that Jacobian can differ from the point's (random scene 117
  // of seed 1: k = 8.1e10 N/m, penetrations 4e-11 m; τ̂_λ = −3.4e-3 from the last iterate, 7e-9
  // away, and +1.3e-3 at the point itself), and a fold's sign change lands in the wrong step,
  // where it looks like a jump at the step's start. On a smooth arc the chord bisects the two
  // tangents, τ₁ ≈ 2(c·τ₀)c − τ₀; where |τ̂_λ| is small and disagrees with that by half its size,
  // the tangent and det are taken at the point: one Jacobian more, rarely (for an orbit it is an
  // integration with sensitivities).
  void RefineNearFold(CorrectedPoint& point) {
    constexpr double kSmallLambdaComponent = 1e-2;
    const Index n = system.n();
    const double lambda_component = point.tangent(n);
    if (std::abs(lambda_component) >= kSmallLambdaComponent) return;
    const Vector& from = current.point.tangent;
    Vector chord = point.x - current.point.x;
    const double length = chord.norm();
    if (!(length > 0.0)) return;
    chord /= length;
    const double predicted = 2.0 * chord.dot(from) * chord(n) - from(n);
    if (std::abs(predicted - lambda_component) <= 0.5 * std::abs(lambda_component)) return;
    Vector tangent;
    LogDeterminant det;
    if (corrector.TangentAt(point.x, point.tangent, tangent, det)) {
      point.tangent = tangent;
      point.det = det;
    }
  }

  enum class Cut { kNone, kLambdaBound, kEvent, kClosed, kGrazing };

  // The located zeros of the kGrazing test functions that change sign between `current` and `to`
  // (at arclength sigma_end), as (test index, σ, point): the earliest, and any other at the same
  // point (a symmetric rotor's two contacts graze together), in order of σ. Zeros that did not
  // converge are left to Detect, as every other test's.
  struct LocatedTest {
    Index test = 0;
    double sigma = 0.0;
    SpecialPoint point;
  };
  std::vector<LocatedTest> FirstGrazing(Sampler& sampler, const PointData& to, double sigma_end) {
    std::vector<LocatedTest> located;
    if (!options.detect.locate || current.tests.size() != to.tests.size()) return located;
    for (Index k = 0; k < to.tests.size(); ++k) {
      if (problem.TestFunctionType(static_cast<int>(k)) != SpecialPointType::kGrazing ||
          !(current.tests(k) * to.tests(k) < 0.0)) {
        continue;
      }
      auto [sigma, sp] = FromArc(SpecialPointType::kGrazing, sampler, TestArc(k), current.tests(k),
                                 to.tests(k), to, sigma_end, true);
      if (!sp.converged) continue;
      sp.label = test_names[static_cast<size_t>(k)];
      located.push_back({k, sigma, std::move(sp)});
    }
    std::sort(located.begin(), located.end(),
              [](const LocatedTest& a, const LocatedTest& b) { return a.sigma < b.sigma; });
    if (!located.empty()) {
      const SpecialPoint& first = located.front().point;  // remove_if leaves the front in place
      located.erase(std::remove_if(located.begin() + 1, located.end(),
                                   [&](const LocatedTest& t) { return !SamePoint(first, t.point); }),
                    located.end());
    }
    return located;
  }

  // Takes the corrected step to `candidate` (at arclength sigma_end): bounds, events, a grazing that
  // ends the branch, closure, special points, the point itself. `left_branch` (nothing changed, the
  // step is to be taken again shorter): an event margin jumps within the step or cannot be followed
  // along it, or a special point cannot be located, unless `shortest` (the smallest step, or the
  // last try).
  StepResult Advance(CorrectedPoint candidate, double sigma_end, bool shortest,
                     bool& left_branch) {
    // The step's end as the corrector found it: `candidate` may be cut below, this stays.
    const CorrectedPoint step_end = candidate;
    Sampler sampler(*this, current, step_end, sigma_end);
    Cut cut = Cut::kNone;
    const double s_lambda = system.lambda_scale();

    // 1. λ bounds: cut the step where it meets the bound.
    double bound = 0.0;
    const double lambda_end = LambdaOf(candidate.x);
    if (lambda_end > options.bounds.lambda_max || lambda_end < options.bounds.lambda_min) {
      bound = lambda_end > options.bounds.lambda_max ? options.bounds.lambda_max
                                                     : options.bounds.lambda_min;
      const double fa = (LambdaOf(current.point.x) - bound) / s_lambda;
      const double fb = (lambda_end - bound) / s_lambda;
      // fa = 0, or of fb's sign by rounding: the current point already lies on the bound.
      if (fa * fb >= 0.0) {
        return End(BranchStatus::kReachedLambdaBound,
                   fmt::format("reached λ {} = {:.10g}", bound == options.bounds.lambda_max
                                                             ? "max" : "min", bound));
      }
      ArcFunction psi = [this, bound, s_lambda](const CorrectedPoint& p, double& value) {
        value = (LambdaOf(p.x) - bound) / s_lambda;
        return true;
      };
      const ArcRoot root = LocateOnArc(sampler, psi, 0.0, fa, sigma_end, fb);
      // A point inside the step the corrector could not reach: the root is not bracketed any
      // more, and taking the step's end would store a point beyond the bound. Shorter, unless
      // this is the shortest step.
      if (root.evaluation_failed && !shortest) {
        left_branch = true;
        return StepResult::kContinue;
      }
      if (!root.found || root.sigma <= 0.0 || root.evaluation_failed) {
        return End(BranchStatus::kReachedLambdaBound,
                   fmt::format("reached λ {} = {:.10g} (the last point could not be placed on "
                               "it)",
                               bound == options.bounds.lambda_max ? "max" : "min", bound));
      }
      candidate = root.point;
      sigma_end = root.sigma;
      cut = Cut::kLambdaBound;
    }

    // 2. State bounds: end at the previous point.
    std::string why;
    if (OutsideStateBounds(candidate.x, why)) {
      return End(BranchStatus::kReachedStateBound,
                 fmt::format("reached a state bound after λ = {:.10g}: {}",
                             LambdaOf(current.point.x), why));
    }

    PointData next;
    next.point = candidate;
    next.piece = current.piece;
    FillEventsAndTests(next);

    // 3. Events: the earliest margin that turns negative.
    int event = -1;
    ArcRoot event_root;
    if (next.events.size() > 0 && current.events.size() == next.events.size() &&
        sigma_end > current.events_sigma) {
      for (Index k = 0; k < next.events.size(); ++k) {
        if (!(next.events(k) < 0.0 && current.events(k) >= 0.0)) continue;
        ArcFunction psi = [this, k](const CorrectedPoint& p, double& value) {
          value = EventsAt(p.x)(k);
          return std::isfinite(value);
        };
        const ArcRoot root = LocateOnArc(sampler, psi, current.events_sigma, current.events(k),
                                         sigma_end, next.events(k));
        // A margin that jumps within the step (the bracket closed on no zero), or whose trial
        // points between the step's ends cannot be corrected: the corrector's end point may lie
        // on another branch, the step jumped to it (random scene 37 of seed 1: a full-slip whip,
        // the same state at every speed, which a 30 rpm step left for a branch with the right
        // contact open). Taken again shorter, a few times.
        if (root.found && (root.discontinuous || root.evaluation_failed) && !shortest) {
          left_branch = true;
          return StepResult::kContinue;
        }
        if (!root.found) continue;
        if (event < 0 || root.sigma < event_root.sigma) {
          event = static_cast<int>(k);
          event_root = root;
        }
      }
      if (event >= 0) {
        cut = Cut::kEvent;
        next.point = event_root.point;
        sigma_end = event_root.sigma;
        FillEventsAndTests(next);
      }
    }

    // 4. A grazing that ends the branch (bounds.end_at_grazing): the step is cut at it, like at a
    // λ bound, so that nothing past it is located.
    std::vector<LocatedTest> grazing;
    std::string grazing_end;
    if (options.bounds.end_at_grazing) {
      grazing = FirstGrazing(sampler, next, sigma_end);
      if (!grazing.empty()) {
        const LocatedTest& first = grazing.front();
        // The located point, from the sampler's cache.
        const bool cached = sampler.At(first.sigma, next.point);
        RUBCONT_INVARIANT(cached, "the located grazing at σ = {} is not in the cache", first.sigma);
        cut = Cut::kGrazing;
        sigma_end = first.sigma;
        FillEventsAndTests(next);
        grazing_end = fmt::format(
            "ended at the grazing{} located at λ = {:.9g}: past it the orbits cross a switching "
            "surface (continue with ContinueAcrossSwitches)",
            first.point.label.empty() ? "" : " " + first.point.label, first.point.lambda);
      }
    }

    // 5. Closure.
    if ((cut == Cut::kNone || cut == Cut::kLambdaBound) && options.detect.closed_branches &&
        branch.points.size() >= 3 && current.piece == start_piece &&
        start_x.size() == next.point.x.size()) {
      const double h_from = start_tangent.dot(current.point.x - start_x);
      const double h_to = start_tangent.dot(next.point.x - start_x);
      if (h_from < 0.0 && h_to >= 0.0 &&
          (next.point.x - start_x).norm() <= 2.0 * sigma_end + options.closure_tolerance) {
        ArcFunction psi = [this](const CorrectedPoint& p, double& value) {
          value = start_tangent.dot(p.x - start_x);
          return true;
        };
        const ArcRoot root = LocateOnArc(sampler, psi, 0.0, h_from, sigma_end, h_to);
        const double tolerance =
            options.closure_tolerance * std::max(1.0, start_x.lpNorm<Eigen::Infinity>());
        if (root.found && (root.point.x - start_x).lpNorm<Eigen::Infinity>() <= tolerance &&
            root.point.tangent.dot(start_tangent) > 0.0) {
          cut = Cut::kClosed;
          next.point = root.point;
          sigma_end = root.sigma;
          FillEventsAndTests(next);
        }
      }
    }

    // 6. Stability at the new point, special points in the step, the point itself.
    ComputeStability(next);
    std::vector<Index> located_tests;
    for (const LocatedTest& t : grazing) located_tests.push_back(t.test);
    std::vector<SpecialPoint> special = Detect(sampler, current, next, sigma_end, located_tests);
    // A special point that cannot be located may also be a step that jumped to another branch
    // (its test function jumps between the branches): taken again shorter, as for events.
    if (!shortest && options.detect.locate &&
        std::any_of(special.begin(), special.end(),
                    [](const SpecialPoint& sp) { return !sp.converged; })) {
      left_branch = true;
      return StepResult::kContinue;
    }
    AppendPoint(next, sigma_end);
    ++branch.statistics.steps;
    for (SpecialPoint& sp : special) AddSpecialPoint(std::move(sp));
    for (LocatedTest& t : grazing) AddSpecialPoint(std::move(t.point));

    if (cut == Cut::kEvent) return SwitchAtEvent(event, event_root, next);
    previous_x = std::move(current.point.x);
    current = std::move(next);
    if (cut == Cut::kLambdaBound) {
      return End(BranchStatus::kReachedLambdaBound,
                 fmt::format("reached λ {} = {:.10g}",
                             bound == options.bounds.lambda_max ? "max" : "min", bound));
    }
    if (cut == Cut::kGrazing) return End(BranchStatus::kGrazing, grazing_end);
    if (cut == Cut::kClosed) {
      return End(BranchStatus::kClosed,
                 fmt::format("closed: returned to the start point after arclength {:.6g}",
                             branch.points.back().arclength));
    }
    if (branch.statistics.steps >= options.bounds.max_steps) {
      return End(BranchStatus::kMaxSteps,
                 fmt::format("reached the maximum of {} steps at λ = {:.10g}",
                             options.bounds.max_steps, LambdaOf(current.point.x)));
    }
    return StepResult::kContinue;
  }

  // ---- events ---------------------------------------------------------------------------------

  StepResult SwitchAtEvent(int event, const ArcRoot& root, const PointData& at) {
    RUBCONT_INVARIANT(event >= 0 && event < static_cast<int>(event_names.size()),
                      "event {} of {}", event, event_names.size());
    const std::string name = event_names[static_cast<size_t>(event)];
    SpecialPoint sp = MakeSpecialPoint(SpecialPointType::kEvent, at.point);
    sp.index = static_cast<Index>(branch.points.size()) - 2;
    sp.label = name;
    sp.piece = at.piece;
    sp.converged = root.converged;
    sp.iterations = root.evaluations;
    sp.test_value = root.value;
    sp.last_correction = root.last_step;
    if (!root.converged) sp.note = "not located to tolerance: a guess within the bracket";
    auto add_note = [&sp](const std::string& more) {
      sp.note += (sp.note.empty() ? "" : "; ") + more;
    };
    const Vector old_tangent = at.point.tangent;
    const Index old_n = system.n();
    Vector u = sp.u;
    const double lambda = sp.lambda;
    const std::string old_piece = at.piece;
    ++branch.statistics.switches;
    if (!problem.SwitchAt(event, u, lambda)) {
      add_note("the problem refused to switch (SwitchAt returned false)");
      branch.special_points.push_back(sp);
      return End(BranchStatus::kSwitchRefused,
                 fmt::format("event '{}' at λ = {:.10g} on piece '{}': the problem cannot "
                             "continue past it",
                             name, lambda, old_piece));
    }
    system.Refresh();
    corrector.Resize();
    ReadPieceNames();
    const Index n = system.n();
    if (u.size() != n) {
      throw std::invalid_argument(fmt::format(
          "Problem::SwitchAt left u with {} entries; the new Dimension() = {}", u.size(), n));
    }
    const std::string new_piece = problem.PieceLabel();
    auto dead_end = [&](const std::string& why) {
      add_note(why);
      branch.special_points.push_back(sp);
      return End(BranchStatus::kNoValidDirection,
                 fmt::format("event '{}' at λ = {:.10g}: {}", name, lambda, why));
    };

    // The switch point in the new formulation, corrected if needed, and its tangent: the null
    // vector of DF̂, oriented like the old tangent.
    PointData data;
    data.piece = new_piece;
    system.ToScaled(u, lambda, data.point.x);
    Matrix DF;
    if (!system.Jacobian(data.point.x, DF)) {
      return dead_end(fmt::format("non-finite Jacobian on the new piece '{}'", new_piece));
    }
    Vector tangent = SmallestSingularVectors(DF, 1).right.col(0);
    Vector F;
    const bool finite = system.Residual(data.point.x, F);
    if (!finite || F.lpNorm<Eigen::Infinity>() > options.corrector.residual_tolerance) {
      CorrectedPoint corrected;
      const CorrectorStatus status =
          corrector.Correct(data.point.x, tangent, 0.0, data.point.x, corrected);
      if (status != CorrectorStatus::kConverged) {
        return dead_end(fmt::format("the switch point does not solve the new piece '{}' ({})",
                                    new_piece, ToString(status)));
      }
      data.point.x = corrected.x;
      tangent = corrected.tangent;
    }
    const double by_lambda = tangent(n) * old_tangent(old_n);
    const double by_dot = n == old_n ? tangent.dot(old_tangent) : 0.0;
    const double orientation = std::abs(by_dot) > 1e-3 ? by_dot : by_lambda;
    if (orientation < 0.0) tangent = -tangent;
    if (!corrector.TangentAt(data.point.x, tangent, tangent, data.point.det)) {
      return dead_end(fmt::format("singular bordered Jacobian on the new piece '{}'", new_piece));
    }
    data.point.tangent = tangent;
    system.Residual(data.point.x, F);
    data.point.residual_norm = F.lpNorm<Eigen::Infinity>();
    data.point.iterations = 0;

    // Probe both ways: continue where the new margins that vanish here grow.
    const Vector g0 = EventsAt(data.point.x);
    const double h = options.events.probe_step;
    Vector g_probe[2];
    bool probed[2] = {false, false};
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? 1.0 : -1.0;
      CorrectedPoint probe;
      const Vector border = sign * tangent;
      if (corrector.Correct(data.point.x, border, h, data.point.x + h * border, probe) ==
          CorrectorStatus::kConverged) {
        g_probe[side] = EventsAt(probe.x);
        probed[side] = true;
      }
    }
    auto near_zero = [&](Index j) {
      double variation = 0.0;
      for (int side = 0; side < 2; ++side) {
        if (probed[side]) variation = std::max(variation, std::abs(g_probe[side](j) - g0(j)));
      }
      return std::abs(g0(j)) <= 1e-3 * variation;
    };
    auto valid = [&](int side) {
      if (!probed[side]) return false;
      for (Index j = 0; j < g0.size(); ++j) {
        if (g_probe[side](j) < 0.0) return false;
        if (near_zero(j) && !(g_probe[side](j) > g0(j))) return false;
      }
      return true;
    };
    const bool forward = valid(0);
    const bool backward = valid(1);
    int chosen = 0;
    if (!forward && !backward) {
      std::string violated;
      for (Index j = 0; j < g0.size(); ++j) {
        const bool bad = (probed[0] && g_probe[0](j) < 0.0) || (probed[1] && g_probe[1](j) < 0.0);
        if (bad) violated += (violated.empty() ? "'" : ", '") + event_names[j] + "'";
      }
      return dead_end(fmt::format(
          "the new piece '{}' is invalid both ways along its tangent{}", new_piece,
          violated.empty() ? "" : " (margins " + violated + " turn negative)"));
    }
    if (!forward) {
      chosen = 1;
      tangent = -tangent;
      data.point.det.sign = -data.point.det.sign;  // det [DF̂; −τᵀ] = −det [DF̂; τᵀ]
      data.point.tangent = tangent;
      add_note(fmt::format(
          "the new piece '{}' is valid only against the old tangent: the branch turns back "
          "into the region it came from",
          new_piece));
    }
    if (tangent(n) * old_tangent(old_n) < 0.0) {
      sp.nonsmooth_fold = true;
      sp.note += fmt::format("{}non-smooth fold: λ turns back here, the branch continues on '{}' "
                             "towards {} λ",
                             sp.note.empty() ? "" : "; ", new_piece,
                             tangent(n) < 0.0 ? "decreasing" : "increasing");
    }
    branch.special_points.push_back(sp);

    data.events = g_probe[chosen];
    data.events_sigma = h;
    data.tests = TestsAt(data.point.x);
    ComputeStability(data);
    current = data;
    previous_x.resize(0);
    AppendPoint(current, 0.0);
    if (branch.statistics.steps >= options.bounds.max_steps) {
      return End(BranchStatus::kMaxSteps,
                 fmt::format("reached the maximum of {} steps at λ = {:.10g}",
                             options.bounds.max_steps, lambda));
    }
    return StepResult::kContinue;
  }
};

Continuation::Continuation(Problem& problem, const ContinuationOptions& options) {
  Validate(options);
  impl_ = std::make_unique<Impl>(problem, options);
}

Continuation::~Continuation() = default;

StepResult Continuation::Start(const Vector& u0, double lambda0) {
  Impl& impl = *impl_;
  impl.CheckStartArguments(u0, lambda0);
  impl.Prepare();
  Vector x0;
  impl.system.ToScaled(u0, lambda0, x0);
  Vector border = Vector::Zero(x0.size());
  border(x0.size() - 1) = 1.0;
  return impl.CorrectStart(x0, border, impl.options.direction, true);
}

StepResult Continuation::StartWithTangent(const Vector& u0, double lambda0, const Vector& du,
                                          double dlambda) {
  Impl& impl = *impl_;
  impl.CheckStartArguments(u0, lambda0);
  if (du.size() != u0.size()) {
    throw std::invalid_argument(fmt::format(
        "Continuation::StartWithTangent: du has {} entries; u0 has {}", du.size(), u0.size()));
  }
  impl.Prepare();
  Vector x0;
  impl.system.ToScaled(u0, lambda0, x0);
  Vector border = impl.system.ScaledDirection(du, dlambda);
  const double norm = border.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) {
    throw std::invalid_argument(
        "Continuation::StartWithTangent: the direction (du, dlambda) is zero or not finite");
  }
  border /= norm;
  return impl.CorrectStart(x0, border, +1, false);
}

StepResult Continuation::StartFromBranchPoint(const SpecialPoint& branch_point, int side) {
  Impl& impl = *impl_;
  if (side != 1 && side != -1) {
    throw std::invalid_argument(fmt::format(
        "Continuation::StartFromBranchPoint: side = {}: must be +1 or -1", side));
  }
  impl.CheckStartArguments(branch_point.u, branch_point.lambda);
  impl.Prepare();
  const BranchSwitch change = ComputeBranchSwitch(impl.problem, branch_point);
  if (!change.ok) {
    return impl.End(BranchStatus::kStartFailed,
                    fmt::format("branch switching at λ = {:.10g} failed: {}",
                                branch_point.lambda, change.message));
  }
  PointData data;
  data.singular_start = true;
  impl.system.ToScaled(branch_point.u, branch_point.lambda, data.point.x);
  data.point.tangent = side * change.tangent;
  Vector F;
  impl.system.Residual(data.point.x, F);
  data.point.residual_norm = F.lpNorm<Eigen::Infinity>();
  return impl.FinishStart(data);
}

StepResult Continuation::Step() { return impl_->StepOnce(); }

void Continuation::Stop(const std::string& reason, BranchStatus status) {
  if (status == BranchStatus::kRunning) {
    throw std::invalid_argument(
        "Continuation::Stop: status = running: must be one that ends a branch");
  }
  if (impl_->branch.status == BranchStatus::kRunning) impl_->End(status, reason);
}

const Branch& Continuation::branch() const { return impl_->branch; }

Branch Continuation::TakeBranch() {
  if (impl_->branch.status == BranchStatus::kRunning) {
    impl_->End(BranchStatus::kStoppedByCaller, "taken before it ended");
  }
  return std::move(impl_->branch);
}

double Continuation::step_size() const { return impl_->ds; }

Branch RunToEnd(Continuation& continuation, const StepCallback& callback, const EndTest& end_test) {
  while (continuation.branch().status == BranchStatus::kRunning) {
    continuation.Step();
    if (callback && !callback(continuation.branch())) {
      continuation.Stop("stopped by the per-step callback");
    }
    if (end_test && continuation.branch().status == BranchStatus::kRunning) {
      if (const std::optional<BranchEnd> end = end_test(continuation.branch())) {
        continuation.Stop(end->message, end->status);
      }
    }
  }
  return continuation.TakeBranch();
}

Branch Continue(Problem& problem, const Vector& u0, double lambda0,
                const ContinuationOptions& options, const StepCallback& callback,
                const EndTest& end_test) {
  Continuation continuation(problem, options);
  continuation.Start(u0, lambda0);
  return RunToEnd(continuation, callback, end_test);
}

}  // namespace rubcont
