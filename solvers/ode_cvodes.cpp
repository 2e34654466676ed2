// CVODES backend: BDF or Adams with a dense direct linear solver, forward sensitivities for the
// state-transition matrix and ∂x/∂p, root finding, dense output. One CVODES memory per integrator,
// re-initialized for every call (CVodeReInit, CVodeSensReInit).
#include <algorithm>
#include <cmath>
#include <vector>

#include <cvodes/cvodes.h>
#include <fmt/core.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "solvers/ode_internal.h"

namespace rubcont {
namespace detail {
namespace {

CallbackContext& Context(void* user_data) { return *static_cast<CallbackContext*>(user_data); }

int CvodesRhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
  return EvaluateRhs(Context(user_data), t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

int CvodesJacobian(sunrealtype t, N_Vector y, N_Vector /*fy*/, SUNMatrix J, void* user_data,
                   N_Vector, N_Vector, N_Vector) {
  return EvaluateJacobian(Context(user_data), t, N_VGetArrayPointer(y), SM_DATA_D(J));
}

// All sensitivity right-hand sides at once: ṡ_j = J(t, x) s_j for the n initial-state directions
// and, when Ns = n + 1, q̇ = J q + ∂f/∂p. One Jacobian evaluation serves all Ns of them.
int CvodesSensitivityRhs(int Ns, sunrealtype t, N_Vector y, N_Vector /*ydot*/, N_Vector* yS,
                         N_Vector* ySdot, void* user_data, N_Vector, N_Vector) {
  CallbackContext& context = Context(user_data);
  const double* x = N_VGetArrayPointer(y);
  int flag = EvaluateJacobian(context, t, x, context.jacobian.data());
  if (flag != 0) return flag;
  const Index n = context.n;
  for (int j = 0; j < Ns; ++j) {
    MapVector(ySdot[j]).noalias() = context.jacobian * MapVector(yS[j]);
  }
  if (Ns > n) {
    flag = EvaluateDfDparameter(context, t, x);
    if (flag != 0) return flag;
    MapVector(ySdot[n]) += context.dfdp;
  }
  return 0;
}

int CvodesRoots(sunrealtype t, N_Vector y, sunrealtype* gout, void* user_data) {
  return EvaluateEvents(Context(user_data), t, N_VGetArrayPointer(y), gout);
}

IntegrationStatus StatusFromCvodesFlag(int flag, const CallbackContext& context) {
  if (context.state_bound_exceeded) return IntegrationStatus::kStateBound;
  switch (flag) {
    case CV_TOO_MUCH_WORK: return IntegrationStatus::kTooMuchWork;
    case CV_TOO_MUCH_ACC: return IntegrationStatus::kTooMuchAccuracy;
    case CV_ERR_FAILURE: return IntegrationStatus::kErrorTestFailures;
    case CV_CONV_FAILURE:
    case CV_NLS_FAIL:
    case CV_NLS_SETUP_FAIL: return IntegrationStatus::kConvergenceFailures;
    case CV_LINIT_FAIL:
    case CV_LSETUP_FAIL:
    case CV_LSOLVE_FAIL: return IntegrationStatus::kLinearSolverFailure;
    case CV_RHSFUNC_FAIL:
    case CV_FIRST_RHSFUNC_ERR:
    case CV_REPTD_RHSFUNC_ERR:
    case CV_UNREC_RHSFUNC_ERR:
    case CV_SRHSFUNC_FAIL:
    case CV_FIRST_SRHSFUNC_ERR:
    case CV_REPTD_SRHSFUNC_ERR:
    case CV_UNREC_SRHSFUNC_ERR:
      return context.non_finite ? IntegrationStatus::kNonFinite : IntegrationStatus::kRhsFailure;
    default: return IntegrationStatus::kOther;
  }
}

}  // namespace

// Declared in this order so that destruction runs memory → solver → matrix → vectors → context.
class CvodesBackend::State {
 public:
  State(CallbackContext& context, const IntegratorOptions& options)
      : context_(context), options_(options), sun_context_(MakeSunContext()) {
    const Index n = context.n;
    SUNContext ctx = sun_context_.get();
    y_ = MakeNVector(n, ctx);
    abstol_ = MakeNVector(n, ctx);
    MapVector(abstol_.get()) = options.absolute_tolerance * context.scale;
    for (Index j = 0; j <= n; ++j) {
      sensitivities_.push_back(MakeNVector(n, ctx));
      sensitivity_abstol_.push_back(MakeNVector(n, ctx));
    }
    for (auto& v : sensitivities_) raw_sensitivities_.push_back(v.get());
    for (auto& v : sensitivity_abstol_) raw_sensitivity_abstol_.push_back(v.get());
    matrix_.reset(SUNDenseMatrix(n, n, ctx));
    if (!matrix_) throw std::bad_alloc();
    solver_.reset(SUNLinSol_Dense(y_.get(), matrix_.get(), ctx));
    if (!solver_) throw std::bad_alloc();
    memory_ = CVodeCreate(options.method == IntegrationMethod::kAdams ? CV_ADAMS : CV_BDF, ctx);
    if (memory_ == nullptr) throw std::bad_alloc();
  }

  ~State() { CVodeFree(&memory_); }

  IntegrationResult Run(const IntegrationRequest& request, bool& events_changed) {
    const Index n = context_.n;
    const int Ns = static_cast<int>(request.StmColumns(n)) + (request.dxdp != nullptr ? 1 : 0);
    IntegrationResult result;
    result.t_reached = request.t0;
    restarted_ = IntegrationStatistics();
    MapVector(y_.get()) = Eigen::Map<const Vector>(request.x0, n);
    const double t_final = request.times[request.count - 1];

    if (t_final == request.t0) {  // nothing to integrate: the identity map
      CopyTrivial(request);
      return result;
    }

    int flag = Initialize(request.t0);
    if (flag == CV_SUCCESS && events_changed) {
      flag = InitializeEvents();
      if (flag == CV_SUCCESS) events_changed = false;
    }
    if (flag == CV_SUCCESS) flag = InitializeSensitivities(Ns, request);
    if (flag == CV_SUCCESS) flag = CVodeSetStopTime(memory_, t_final);
    if (flag != CV_SUCCESS) return Failure(flag, request.t0, result);

    double t = request.t0;
    for (Index k = 0; k < request.count; ++k) {
      const double t_out = request.times[k];
      while (t != t_out) {
        flag = CVode(memory_, t_out, y_.get(), &t, CV_NORMAL);
        if (flag < 0) {
          Statistics(result, Ns);
          return Failure(flag, t, result);
        }
        if (flag == CV_ROOT_RETURN) {
          RecordEvents(t, result);
          if (context_.events->terminal) {
            result.stopped_at_event = true;
            result.t_reached = t;
            FinishAt(t, request, Ns, k, result);
            return result;
          }
          if (context_.events->restart && t != t_final && (flag = Restart(t, Ns, result)) < 0) {
            return Failure(flag, t, result);
          }
        }
      }
      if (request.states != nullptr) {
        Eigen::Map<Vector>(request.states + k * n, n) = MapVector(y_.get());
      }
    }
    result.t_reached = t;
    FinishAt(t, request, Ns, request.count, result);
    return result;
  }

 private:
  // CVodeInit on the first call, CVodeReInit afterwards (keeps every option and the linear solver).
  int Initialize(double t0) {
    if (initialized_) return CVodeReInit(memory_, t0, y_.get());
    int flag = CVodeInit(memory_, CvodesRhs, t0, y_.get());
    if (flag != CV_SUCCESS) return flag;
    initialized_ = true;
    if ((flag = CVodeSetUserData(memory_, &context_)) != CV_SUCCESS) return flag;
    if ((flag = CVodeSetErrHandlerFn(memory_, RecordError, &context_)) != CV_SUCCESS) return flag;
    if ((flag = CVodeSVtolerances(memory_, options_.relative_tolerance, abstol_.get())) !=
        CV_SUCCESS) {
      return flag;
    }
    if ((flag = CVodeSetLinearSolver(memory_, solver_.get(), matrix_.get())) != CV_SUCCESS) {
      return flag;
    }
    if (context_.system->HasJacobian()) {
      if ((flag = CVodeSetJacFn(memory_, CvodesJacobian)) != CV_SUCCESS) return flag;
    }  // else CVODES' internal difference-quotient Jacobian
    if ((flag = CVodeSetMaxNumSteps(memory_, options_.max_steps)) != CV_SUCCESS) return flag;
    if (options_.max_step > 0.0 &&
        (flag = CVodeSetMaxStep(memory_, options_.max_step)) != CV_SUCCESS) {
      return flag;
    }
    if (options_.initial_step > 0.0 &&
        (flag = CVodeSetInitStep(memory_, options_.initial_step)) != CV_SUCCESS) {
      return flag;
    }
    if (options_.max_order > 0 &&
        (flag = CVodeSetMaxOrd(memory_, options_.max_order)) != CV_SUCCESS) {
      return flag;
    }
    if (options_.stability_limit_detection && options_.method == IntegrationMethod::kBdf &&
        (flag = CVodeSetStabLimDet(memory_, SUNTRUE)) != CV_SUCCESS) {
      return flag;
    }
    return CV_SUCCESS;
  }

  int InitializeEvents() {
    const EventOptions* events = context_.events;
    if (events == nullptr) return CVodeRootInit(memory_, 0, nullptr);
    int flag = CVodeRootInit(memory_, events->count, CvodesRoots);
    if (flag != CV_SUCCESS) return flag;
    root_directions_.assign(events->count, 0);
    root_found_.assign(events->count, 0);
    if (!events->directions.empty()) root_directions_ = events->directions;
    if ((flag = CVodeSetRootDirection(memory_, root_directions_.data())) != CV_SUCCESS) {
      return flag;
    }
    return CVodeSetNoInactiveRootWarn(memory_);
  }

  // Ns = 0: sensitivities off. Otherwise s_j(t0) = e_j (j < n) and q(t0) = 0 (j = n), or
  // s_j(t0) = the request's seeds.
  int InitializeSensitivities(int Ns, const IntegrationRequest& request) {
    const Index n = context_.n;
    if (Ns == 0) {
      if (sensitivities_active_) {
        sensitivities_active_ = false;
        return CVodeSensToggleOff(memory_);
      }
      return CV_SUCCESS;
    }
    const Index columns = request.StmColumns(n);
    for (Index j = 0; j < columns; ++j) {
      const Vector seed = request.InitialColumn(j, n);
      MapVector(sensitivities_[j].get()) = seed;
      // A perturbation of x0 by the seed v moves x by s·1, to be resolved to the state's absolute
      // tolerance when v has the typical size of the state: atol(s) = atol ⊙ scale · ‖v ./ scale‖₂
      // (for v = e_j: atol ⊙ scale / scale_j).
      MapVector(sensitivity_abstol_[j].get()) = options_.absolute_tolerance * context_.scale *
                                                seed.cwiseQuotient(context_.scale).norm();
    }
    if (request.dxdp != nullptr) {
      MapVector(sensitivities_[n].get()).setZero();
      MapVector(sensitivity_abstol_[n].get()) =
          options_.absolute_tolerance * context_.scale / request.parameter_scale;
    }
    const int method = SensitivityMethodFlag();
    int flag;
    if (sensitivity_count_ == Ns) {
      flag = CVodeSensReInit(memory_, method, raw_sensitivities_.data());
    } else {
      if (sensitivity_count_ > 0) CVodeSensFree(memory_);
      sensitivity_count_ = 0;
      flag = CVodeSensInit(memory_, Ns, method, CvodesSensitivityRhs, raw_sensitivities_.data());
      if (flag != CV_SUCCESS) return flag;
      sensitivity_count_ = Ns;
      flag = CVodeSetSensErrCon(memory_, options_.sensitivity_error_control ? SUNTRUE : SUNFALSE);
    }
    if (flag != CV_SUCCESS) return flag;
    sensitivities_active_ = true;
    return CVodeSensSVtolerances(memory_, options_.relative_tolerance,
                                 raw_sensitivity_abstol_.data());
  }

  int SensitivityMethodFlag() const {
    return options_.sensitivity_method == SensitivityMethod::kStaggered ? CV_STAGGERED
                                                                         : CV_SIMULTANEOUS;
  }

  // CVodeReInit at t from the current state (and CVodeSensReInit from the current sensitivities):
  // the next step starts at order 1 with no history before t. The counters restart at 0, so the
  // ones so far are kept in result.statistics and Statistics adds the new ones.
  int Restart(double t, int Ns, IntegrationResult& result) {
    Statistics(result, Ns);
    ++result.statistics.restarts;
    restarted_ = result.statistics;
    double t_sensitivity = t;
    int flag = CV_SUCCESS;
    if (Ns > 0) flag = CVodeGetSens(memory_, &t_sensitivity, raw_sensitivities_.data());
    if (flag == CV_SUCCESS) flag = CVodeReInit(memory_, t, y_.get());
    if (flag == CV_SUCCESS && Ns > 0) {
      flag = CVodeSensReInit(memory_, SensitivityMethodFlag(), raw_sensitivities_.data());
    }
    return flag;
  }

  void RecordEvents(double t, IntegrationResult& result) {
    CVodeGetRootInfo(memory_, root_found_.data());
    for (int i = 0; i < static_cast<int>(root_found_.size()); ++i) {
      if (root_found_[i] != 0) {
        result.events.push_back({i, root_found_[i], t, MapVector(y_.get())});
      }
    }
  }

  // Outputs at the final time t (or at a terminal event before output index `filled`).
  void FinishAt(double t, const IntegrationRequest& request, int Ns, Index filled,
                IntegrationResult& result) {
    const Index n = context_.n;
    Eigen::Map<Vector>(request.x_final, n) = MapVector(y_.get());
    if (request.states != nullptr) {
      for (Index k = filled; k < request.count; ++k) {
        Eigen::Map<Vector>(request.states + k * n, n) = MapVector(y_.get());
      }
    }
    if (Ns > 0) {
      double t_sensitivity = t;
      CVodeGetSens(memory_, &t_sensitivity, raw_sensitivities_.data());
      const Index columns = request.StmColumns(n);
      Eigen::Map<Matrix> stm(request.stm, n, columns);
      for (Index j = 0; j < columns; ++j) stm.col(j) = MapVector(sensitivities_[j].get());
      if (request.dxdp != nullptr) {
        Eigen::Map<Vector>(request.dxdp, n) = MapVector(sensitivities_[n].get());
      }
    }
    Statistics(result, Ns);
    result.warnings = context_.warnings;
  }

  void CopyTrivial(const IntegrationRequest& request) {
    const Index n = context_.n;
    Eigen::Map<Vector>(request.x_final, n) = Eigen::Map<const Vector>(request.x0, n);
    if (request.states != nullptr) {
      for (Index k = 0; k < request.count; ++k) {
        Eigen::Map<Vector>(request.states + k * n, n) = Eigen::Map<const Vector>(request.x0, n);
      }
    }
    for (Index j = 0; j < request.StmColumns(n); ++j) {
      Eigen::Map<Vector>(request.stm + j * n, n) = request.InitialColumn(j, n);
    }
    if (request.dxdp != nullptr) Eigen::Map<Vector>(request.dxdp, n).setZero();
  }

  // The counters since the last (re-)initialization, plus restarted_ (the run's counts before
  // its last restart).
  void Statistics(IntegrationResult& result, int Ns) {
    IntegrationStatistics& s = result.statistics;
    CVodeGetNumSteps(memory_, &s.steps);
    CVodeGetNumRhsEvals(memory_, &s.rhs_evaluations);
    CVodeGetNumJacEvals(memory_, &s.jacobian_evaluations);
    CVodeGetNumLinSolvSetups(memory_, &s.linear_solver_setups);
    CVodeGetNumErrTestFails(memory_, &s.error_test_failures);
    CVodeGetNumNonlinSolvIters(memory_, &s.nonlinear_iterations);
    CVodeGetNumNonlinSolvConvFails(memory_, &s.nonlinear_convergence_failures);
    s.sensitivity_rhs_evaluations = 0;
    if (Ns > 0) CVodeGetSensNumRhsEvals(memory_, &s.sensitivity_rhs_evaluations);
    s.restarts = 0;
    Accumulate(s, restarted_);
  }

  IntegrationResult& Failure(int flag, double t, IntegrationResult& result) {
    result.status = StatusFromCvodesFlag(flag, context_);
    result.flag = flag;
    result.flag_name = TakeFlagName(CVodeGetReturnFlagName(flag));
    result.t_reached = t;
    result.warnings = context_.warnings;
    if (context_.state_bound_exceeded) {
      result.message = StateBoundMessage(options_.state_bound, t);
    } else if (context_.non_finite && context_.error_message.empty()) {
      result.message = "the right-hand side returned NaN or Inf";
    } else {
      result.message = context_.error_message;
    }
    return result;
  }

  CallbackContext& context_;
  IntegratorOptions options_;
  SunContextPtr sun_context_;
  NVectorPtr y_;
  NVectorPtr abstol_;
  std::vector<NVectorPtr> sensitivities_;       // n + 1: s_1 … s_n, q
  std::vector<NVectorPtr> sensitivity_abstol_;  // n + 1
  std::vector<N_Vector> raw_sensitivities_;
  std::vector<N_Vector> raw_sensitivity_abstol_;
  SunMatrixPtr matrix_;
  SunLinearSolverPtr solver_;
  void* memory_ = nullptr;
  bool initialized_ = false;
  int sensitivity_count_ = 0;  // Ns of the last CVodeSensInit
  bool sensitivities_active_ = false;
  std::vector<int> root_directions_;
  std::vector<int> root_found_;
  IntegrationStatistics restarted_;  // this run's counters before its last Restart
};

CvodesBackend::CvodesBackend(CallbackContext& context, const IntegratorOptions& options)
    : state_(std::make_unique<State>(context, options)) {}
CvodesBackend::~CvodesBackend() = default;

IntegrationResult CvodesBackend::Run(const IntegrationRequest& request) {
  return state_->Run(request, events_changed_);
}

}  // namespace detail
}  // namespace rubcont
