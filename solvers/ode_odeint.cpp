// Boost.Odeint backend: the Dormand–Prince 5(4) pair (runge_kutta_dopri5) under odeint's step
// control, with its dense output. For long time marching of small systems, where SUNDIALS' generic
// vector operations cost more than the method: on case A(a)'s 16 states ARKODE's ERKStep took
// 2.3–3.9× the CPU for the same steps (docs/studies/sweep_integrators.md). Plain integration and
// sampling only: no sensitivities, no events (OdeIntegrator refuses both with this method).
//
// The state is integrated as it is, with odeint's error test given an absolute tolerance per
// component, |e_i| ≤ atol·scale_i + rtol·|x_i| (WeightedErrorChecker, scale = OdeSystem::
// StateScale(), the maximum norm over i): the test IntegratorOptions documents for the scaled state
// x ./ scale, without scaling the state in and out at every evaluation (on A(a) the integrator's
// CPU per simulated second 7–11 % lower in two alternating pairs, bench/march_bench.cpp). A state
// beyond the state bound or a right-hand side that is not finite ends the call with a status
// (odeint would accept a step whose error estimate is NaN: it is never given one).
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <fmt/core.h>

#include "solvers/ode_internal.h"

namespace rubcont {
namespace detail {
namespace {

namespace odeint = boost::numeric::odeint;

// The state container: a fixed size (unrolled stage loops) for the two-point rotor's 16 states,
// std::vector otherwise.
constexpr Index kFixedSize = 16;
using FixedState = std::array<double, kFixedSize>;
using DynamicState = std::vector<double>;
void Resize(FixedState& /*state*/, Index /*n*/) {}
void Resize(DynamicState& state, Index n) { state.resize(static_cast<std::size_t>(n)); }

// Thrown by the right-hand side through odeint's frames (C++ all the way) and caught in Run.
struct RhsStop {
  IntegrationStatus status;
};

// Consecutive rejected steps before giving up (ARKODE's default for ERK is 7; odeint's own 500).
constexpr int kMaxConsecutiveFailures = 50;

// odeint's error test with an absolute tolerance per component: max_i |e_i| / (atol_i + rtol |x_i|),
// x the step's start (odeint's default_error_checker with a_x = 1, a_dxdt = 0 and one atol).
template <class Algebra>
class WeightedErrorChecker {
 public:
  using value_type = double;
  using algebra_type = Algebra;
  using operations_type = odeint::default_operations;
  WeightedErrorChecker(const double* atol, double rtol) : atol_(atol), rtol_(rtol) {}
  template <class State, class Deriv, class Err, class Time>
  double error(algebra_type& /*algebra*/, const State& x_old, const Deriv& /*dxdt_old*/, Err& x_err,
               Time /*dt*/) const {
    double e = 0.0;
    for (std::size_t i = 0; i < x_err.size(); ++i) {
      e = std::max(e, std::abs(x_err[i]) / (atol_[i] + rtol_ * std::abs(x_old[i])));
    }
    return e;
  }

 private:
  const double* atol_;
  double rtol_;
};

}  // namespace

class OdeintBackend::Stepper {
 public:
  virtual ~Stepper() = default;
  virtual IntegrationResult Run(const IntegrationRequest& request) = 0;
};

namespace {

template <class OdeintState>
class DormandPrince final : public OdeintBackend::Stepper {
  using Dopri5 = odeint::runge_kutta_dopri5<OdeintState>;
  using ErrorChecker = WeightedErrorChecker<typename Dopri5::algebra_type>;
  using Controlled = odeint::controlled_runge_kutta<Dopri5, ErrorChecker>;

 public:
  DormandPrince(CallbackContext& context, const IntegratorOptions& options)
      : context_(context),
        options_(options),
        atol_(context.scale * options.absolute_tolerance),
        controlled_(ErrorChecker(atol_.data(), options.relative_tolerance),
                    odeint::default_step_adjuster<double, double>(options.max_step)) {
    const Index n = context.n;
    switches_ = context.system->SwitchingCount();
    g_.resize(switches_);
    g_previous_.resize(switches_);
    g_ahead_.resize(switches_);
    bound_.resize(switches_);
    for (OdeintState* v : {&z_, &dz_, &z_new_, &dz_new_, &output_}) Resize(*v, n);
  }

  // ż = f(t, z). The state bound and finiteness are checked once per step, on
  // the step's new state (Accept), not at every stage as EvaluateRhs does: a stage that leaves the
  // bound or is not finite makes the new state so (a NaN or Inf stage derivative reaches it through
  // the stages that follow; DP5's b₂ = 0 multiplies k₂ only after k₃ … k₆ have taken it in). On A(a)
  // the per-stage checks cost 11 % of the integration (bench/march_bench.cpp). An exception of the
  // system leaves odeint's frames as it is (C++ all the way) and reaches OdeIntegrator's caller.
  void operator()(const OdeintState& z, OdeintState& dz, double t) {
    context_.system->Rhs(t, Eigen::Map<const Vector>(z.data(), context_.n),
                         Eigen::Map<Vector>(dz.data(), context_.n));
    ++evaluations_;
  }

  // Whether a step's new state z and its derivative are finite and z ./ scale within the state
  // bound; otherwise throws RhsStop with the status (kNonFinite, kStateBound).
  void Accept(const OdeintState& z, const OdeintState& dz) const {
    double size = 0.0, z_nan = 0.0, dz_nan = 0.0;  // NaN or Inf times 0 is NaN
    for (std::size_t i = 0; i < z.size(); ++i) {
      size = std::max(size, std::abs(z[i]) * context_.inverse_scale(static_cast<Index>(i)));
      z_nan += z[i] * 0.0;
      dz_nan += dz[i] * 0.0;
    }
    if (!(z_nan == 0.0)) throw RhsStop{IntegrationStatus::kNonFinite};
    if (!(size <= context_.state_bound)) throw RhsStop{IntegrationStatus::kStateBound};
    if (!(dz_nan == 0.0)) throw RhsStop{IntegrationStatus::kNonFinite};
  }

  IntegrationResult Run(const IntegrationRequest& request) override {
    const IntegratorOptions& options = options_;
    const Index n = context_.n;
    IntegrationResult result;
    result.t_reached = request.t0;
    evaluations_ = 0;
    for (Index i = 0; i < n; ++i) z_[static_cast<std::size_t>(i)] = request.x0[i];
    double t = request.t0;
    const double t_final = request.times[request.count - 1];
    IntegrationStatistics& statistics = result.statistics;
    Index filled = 0;
    try {
      if (t_final != t) {
        const double direction = t_final > t ? 1.0 : -1.0;
        (*this)(z_, dz_, t);
        Accept(z_, dz_);
        double dt = direction * (options.initial_step > 0.0 ? options.initial_step : InitialStep(t_final - t));
        long steps_since_output = 0;
        const bool land = switches_ > 0 && options.land_on_switches;
        if (land) {
          Switches(t, z_, g_);
          g_previous_ = g_;
          t_previous_ = t;
        }
        while (t != t_final) {
          if (steps_since_output >= options.max_steps) {
            return Failure(IntegrationStatus::kTooMuchWork, t, result,
                           fmt::format("{} steps taken before the next output time", options.max_steps));
          }
          if (land) dt = LandOnSwitch(t, dt);
          // The last step ends on t_final exactly; outputs before it are interpolated to.
          const bool last = direction * (t + dt - t_final) >= 0.0;
          if (last) dt = t_final - t;
          double t_try = t;
          double used = dt;  // the step of the attempt (try_step replaces dt by the next one)
          int failures = 0;
          while (controlled_.try_step(std::ref(*this), z_, dz_, t_try, z_new_, dz_new_, dt) ==
                 odeint::fail) {
            used = dt;
            ++statistics.error_test_failures;
            if (++failures >= kMaxConsecutiveFailures || std::abs(dt) <= 1e-14 * std::max(std::abs(t), 1e-300)) {
              return Failure(IntegrationStatus::kErrorTestFailures, t, result,
                             fmt::format("{} consecutive error-test failures, h = {:.3g}", failures, dt));
            }
          }
          Accept(z_new_, dz_new_);
          ++statistics.steps;
          ++steps_since_output;
          const bool at_end = last && used == t_final - t;
          if (at_end) t_try = t_final;  // no rounding past the final time
          // Outputs inside (t, t_try], by the method's dense output.
          while (filled < request.count - 1 && direction * (request.times[filled] - t_try) <= 0.0) {
            controlled_.stepper().calc_state(request.times[filled], output_, z_, dz_, t, z_new_,
                                             dz_new_, t_try);
            if (request.states != nullptr) Output(output_, request.states + filled * n);
            ++filled;
            steps_since_output = 0;
          }
          std::swap(z_, z_new_);
          std::swap(dz_, dz_new_);
          if (land) {
            g_previous_.swap(g_);
            t_previous_ = t;
            context_.system->SwitchingFunctions(t_try, Eigen::Map<const Vector>(z_.data(), n), g_);
          }
          t = t_try;
        }
      }
    } catch (const RhsStop& stop) {
      return Failure(stop.status, t, result, "");
    }
    Output(z_, request.x_final);
    if (request.states != nullptr) {
      for (Index k = filled; k < request.count; ++k) Output(z_, request.states + k * n);
    }
    result.t_reached = t;
    statistics.rhs_evaluations = evaluations_;
    result.warnings = context_.warnings;
    return result;
  }

 private:
  // Hairer, Nørsett & Wanner's first guess: 1 % of ‖z‖/‖ż‖ (maximum norms, scaled), at most the span.
  double InitialStep(double span) const {
    double z = 0.0, dz = 0.0;
    for (std::size_t i = 0; i < z_.size(); ++i) {
      z = std::max(z, std::abs(z_[i]) * context_.inverse_scale(static_cast<Index>(i)));
      dz = std::max(dz, std::abs(dz_[i]) * context_.inverse_scale(static_cast<Index>(i)));
    }
    const double guess = z > 1e-5 && dz > 1e-5 ? 0.01 * z / dz : 1e-6 * std::abs(span);
    return std::min(guess, std::abs(span));
  }

  // g(t, z) into g.
  void Switches(double t, const OdeintState& z, Vector& g) {
    context_.system->SwitchingFunctions(t, Eigen::Map<const Vector>(z.data(), context_.n), g);
  }

  // The step `dt`, shortened to end where a switching function is predicted to vanish (a contact
  // closing or opening: a kink of f that an explicit step straddles only with a tiny step and
  // rejections). Each g is extrapolated by the parabola through g(t_previous), g(t) and ġ(t) (ġ a
  // difference quotient along f); a zero in the first 2 % of the step is left to the step (a kink
  // near its start costs it little).
  //
  // Where the system bounds how far each g can move along the extrapolation (OdeSystem::
  // SwitchingIncrementBounds) and every |g| exceeds twice what the parabola could cover within the
  // step, the prediction is skipped: it could find no root there (|p(τ)| ≥ |g|/2 for |τ| ≤ |dt|,
  // the computed roots beyond it with their rounding), so the step is the one it would give, bit
  // for bit, without the extrapolated evaluation. Contacts that stay closed (A(a)'s whirl and
  // full-contact whip) take this path at every step.
  double LandOnSwitch(double t, double dt) {
    const double h = t - t_previous_;
    if (h == 0.0) return dt;
    const double epsilon = 1e-3 * h;
    if (FarFromSwitches(t, epsilon, h, std::abs(dt))) return dt;
    for (std::size_t i = 0; i < z_.size(); ++i) output_[i] = z_[i] + epsilon * dz_[i];
    Switches(t + epsilon, output_, g_ahead_);
    double land = std::abs(dt);
    for (Index k = 0; k < switches_; ++k) {
      const double g = g_(k);
      const double rate = (g_ahead_(k) - g) / epsilon;
      const double curvature = (g_previous_(k) - g + rate * h) / (h * h);  // p(τ) = g + rate τ + c τ²
      const double sign = dt > 0.0 ? 1.0 : -1.0;
      double roots[2];
      const int count = QuadraticRoots(curvature, rate, g, roots);
      for (int r = 0; r < count; ++r) {
        const double ahead = sign * roots[r];
        if (ahead > 0.02 * std::abs(dt) && ahead < land) land = ahead;
      }
    }
    return dt > 0.0 ? land : -land;
  }

  // Whether no switching function can vanish in the parabola of LandOnSwitch within `span` (> 0)
  // of t: |g| > 2 (B span + C span²) for every g, B ≥ |ġ| bounding its difference quotient over
  // `epsilon` and C ≥ |curvature| the curvature's with it. z_ and dz_ are the state at t and its
  // derivative (the step's FSAL evaluation). False where the system gives no bounds.
  bool FarFromSwitches(double t, double epsilon, double h, double span) {
    if (!context_.system->SwitchingIncrementBounds(t, Eigen::Map<const Vector>(z_.data(), context_.n),
                                                   Eigen::Map<const Vector>(dz_.data(), context_.n),
                                                   std::abs(epsilon), bound_)) return false;
    for (Index k = 0; k < switches_; ++k) {
      const double rate = bound_(k) / std::abs(epsilon);
      const double curvature = (std::abs(g_previous_(k) - g_(k)) + rate * std::abs(h)) / (h * h);
      if (!(std::abs(g_(k)) > 2.0 * (rate * span + curvature * span * span))) return false;
    }
    return true;
  }

  // The real roots of c τ² + b τ + a into roots (stably); returns how many (0, 1 or 2).
  static int QuadraticRoots(double c, double b, double a, double (&roots)[2]) {
    if (c == 0.0) {
      if (b == 0.0) return 0;
      roots[0] = -a / b;
      return 1;
    }
    const double discriminant = b * b - 4.0 * c * a;
    if (discriminant < 0.0) return 0;
    const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
    if (q == 0.0) {
      roots[0] = 0.0;
      return 1;
    }
    roots[0] = q / c;
    roots[1] = a / q;
    return 2;
  }

  void Output(const OdeintState& z, double* x) const { std::copy(z.begin(), z.end(), x); }

  IntegrationResult& Failure(IntegrationStatus status, double t, IntegrationResult& result,
                             std::string message) {
    result.status = status;
    result.flag_name = "odeint";
    result.t_reached = t;
    result.statistics.rhs_evaluations = evaluations_;
    result.warnings = context_.warnings;
    if (status == IntegrationStatus::kStateBound) {
      message = StateBoundMessage(context_.state_bound, t);
    } else if (status == IntegrationStatus::kNonFinite) {
      message = "the right-hand side returned NaN or Inf";
    }
    result.message = std::move(message);
    return result;
  }

  CallbackContext& context_;
  IntegratorOptions options_;
  Vector atol_;  // the absolute tolerance per component: atol · scale
  Controlled controlled_;
  OdeintState z_, dz_, z_new_, dz_new_, output_;
  Index switches_ = 0;                  // OdeSystem::SwitchingCount()
  Vector g_, g_previous_, g_ahead_;     // at t, at the previous step's start, at t + ε
  Vector bound_;                        // OdeSystem::SwitchingIncrementBounds over ε
  double t_previous_ = 0.0;
  long evaluations_ = 0;
};

}  // namespace

OdeintBackend::OdeintBackend(CallbackContext& context, const IntegratorOptions& options) {
  if (context.n == kFixedSize) {
    stepper_ = std::make_unique<DormandPrince<FixedState>>(context, options);
  } else {
    stepper_ = std::make_unique<DormandPrince<DynamicState>>(context, options);
  }
}

OdeintBackend::~OdeintBackend() = default;

IntegrationResult OdeintBackend::Run(const IntegrationRequest& request) {
  if (request.stm != nullptr) {
    throw std::invalid_argument(
        "OdeIntegrator: Boost.Odeint Dormand–Prince integrates the state only: sensitivities need "
        "CVODES, ARKODE or Gauss collocation");
  }
  return stepper_->Run(request);
}

}  // namespace detail
}  // namespace rubcont
