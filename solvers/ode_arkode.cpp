// ARKODE backend: ERKStep (explicit) or ARKStep with an implicit table only (DIRK, dense LU).
// ARKODE has no forward-sensitivity module, so the state-transition matrix and ∂x/∂p come from the
// variational equations appended to the state, z = [x, Φ (column-major), q]:
//   ẋ = f(t, x),   Φ̇ = J(t, x) Φ,   q̇ = J(t, x) q + ∂f/∂p,   Φ(t0) = I, q(t0) = 0,
// integrated under one error control. For the DIRK the Newton matrix of the augmented system is
// approximated by blockdiag(J, …, J): it omits the ∂J/∂x·Φ coupling (second derivatives we do not
// have), which only slows the stage iteration of the lower block-triangular stage equations.
#include <algorithm>
#include <cmath>
#include <vector>

#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_erkstep.h>
#include <fmt/core.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "solvers/ode_internal.h"

namespace rubcont {
namespace detail {
namespace {

// user_data of one ARKODE memory: the shared context plus how many variational columns follow x.
struct ArkodeUserData {
  CallbackContext* context = nullptr;
  int columns = 0;  // 0, n (Φ), n + 1 (Φ and q) or the number of seeds (Φ·seeds)
};

int ArkodeRhs(sunrealtype t, N_Vector z, N_Vector zdot, void* user_data) {
  auto& data = *static_cast<ArkodeUserData*>(user_data);
  CallbackContext& context = *data.context;
  const Index n = context.n;
  const double* x = N_VGetArrayPointer(z);
  double* xdot = N_VGetArrayPointer(zdot);
  int flag = EvaluateRhs(context, t, x, xdot);
  if (flag != 0 || data.columns == 0) return flag;
  flag = EvaluateJacobian(context, t, x, context.jacobian.data());
  if (flag != 0) return flag;
  Eigen::Map<const Matrix> columns(x + n, n, data.columns);
  Eigen::Map<Matrix> columns_dot(xdot + n, n, data.columns);
  columns_dot.noalias() = context.jacobian * columns;
  if (data.columns > n) {
    flag = EvaluateDfDparameter(context, t, x);
    if (flag != 0) return flag;
    columns_dot.col(n) += context.dfdp;
  }
  return 0;
}

// Newton matrix of the DIRK: J for the plain system, blockdiag(J, …, J) for the augmented one.
int ArkodeJacobian(sunrealtype t, N_Vector z, N_Vector /*fz*/, SUNMatrix J, void* user_data,
                   N_Vector, N_Vector, N_Vector) {
  auto& data = *static_cast<ArkodeUserData*>(user_data);
  CallbackContext& context = *data.context;
  const Index n = context.n;
  const double* x = N_VGetArrayPointer(z);
  if (data.columns == 0) return EvaluateJacobian(context, t, x, SM_DATA_D(J));
  const int flag = EvaluateJacobian(context, t, x, context.jacobian.data());
  if (flag != 0) return flag;
  const Index m = n * (1 + data.columns);
  Eigen::Map<Matrix> full(SM_DATA_D(J), m, m);
  full.setZero();
  for (Index b = 0; b <= data.columns; ++b) full.block(b * n, b * n, n, n) = context.jacobian;
  return 0;
}

int ArkodeRoots(sunrealtype t, N_Vector z, sunrealtype* gout, void* user_data) {
  auto& data = *static_cast<ArkodeUserData*>(user_data);
  return EvaluateEvents(*data.context, t, N_VGetArrayPointer(z), gout);
}

IntegrationStatus StatusFromArkodeFlag(int flag, const CallbackContext& context) {
  if (context.state_bound_exceeded) return IntegrationStatus::kStateBound;
  switch (flag) {
    case ARK_TOO_MUCH_WORK: return IntegrationStatus::kTooMuchWork;
    case ARK_TOO_MUCH_ACC: return IntegrationStatus::kTooMuchAccuracy;
    case ARK_ERR_FAILURE: return IntegrationStatus::kErrorTestFailures;
    case ARK_CONV_FAILURE:
    case ARK_NLS_SETUP_FAIL:
    case ARK_NLS_OP_ERR: return IntegrationStatus::kConvergenceFailures;
    case ARK_LINIT_FAIL:
    case ARK_LSETUP_FAIL:
    case ARK_LSOLVE_FAIL: return IntegrationStatus::kLinearSolverFailure;
    case ARK_RHSFUNC_FAIL:
    case ARK_FIRST_RHSFUNC_ERR:
    case ARK_REPTD_RHSFUNC_ERR:
    case ARK_UNREC_RHSFUNC_ERR:
      return context.non_finite ? IntegrationStatus::kNonFinite : IntegrationStatus::kRhsFailure;
    default: return IntegrationStatus::kOther;
  }
}

ARKODE_ERKTableID ExplicitTable(int order) {
  switch (order) {
    case 2: return ARKODE_HEUN_EULER_2_1_2;
    case 3: return ARKODE_BOGACKI_SHAMPINE_4_2_3;
    case 4: return ARKODE_ZONNEVELD_5_3_4;
    case 5: return ARKODE_DORMAND_PRINCE_7_4_5;
    case 6: return ARKODE_VERNER_8_5_6;
    default: return ARKODE_FEHLBERG_13_7_8;
  }
}

}  // namespace

// One ARKODE memory for one augmented size. Member order: vectors, matrix, solver, memory, so that
// the memory is freed first.
class ArkodeBackend::Memory {
 public:
  Memory(CallbackContext& context, const IntegratorOptions& options, SUNContext ctx, int columns)
      : explicit_(options.method == IntegrationMethod::kExplicitRungeKutta), sun_context_(ctx) {
    const Index n = context.n;
    data_.context = &context;
    data_.columns = columns;
    m_ = n * (1 + columns);
    z_ = MakeNVector(m_, ctx);
    abstol_ = MakeNVector(m_, ctx);
    if (!explicit_) {
      matrix_.reset(SUNDenseMatrix(m_, m_, ctx));
      if (!matrix_) throw std::bad_alloc();
      solver_.reset(SUNLinSol_Dense(z_.get(), matrix_.get(), ctx));
      if (!solver_) throw std::bad_alloc();
    }
    options_ = options;
  }

  ~Memory() {
    if (memory_ != nullptr) {
      if (explicit_) {
        ERKStepFree(&memory_);
      } else {
        ARKStepFree(&memory_);
      }
    }
  }

  int columns() const { return data_.columns; }

  IntegrationResult Run(const IntegrationRequest& request, bool& events_changed) {
    CallbackContext& context = *data_.context;
    const Index n = context.n;
    IntegrationResult result;
    result.t_reached = request.t0;
    auto z = MapVector(z_.get());
    z.head(n) = Eigen::Map<const Vector>(request.x0, n);
    // Tolerances: atol ⊙ scale for x; ⊙ scale · ‖v ./ scale‖₂ for the column started at v (e_j:
    // / scale_j); / parameter scale for q.
    auto abstol = MapVector(abstol_.get());
    abstol.head(n) = options_.absolute_tolerance * context.scale;
    const Index stm_columns = request.StmColumns(n);
    for (Index j = 0; j < data_.columns; ++j) {
      auto column = z.segment(n * (1 + j), n);
      if (j < stm_columns) {
        column = request.InitialColumn(j, n);
        abstol.segment(n * (1 + j), n) =
            options_.absolute_tolerance * context.scale * column.cwiseQuotient(context.scale).norm();
      } else {
        column.setZero();
        abstol.segment(n * (1 + j), n) = options_.absolute_tolerance * context.scale / request.parameter_scale;
      }
    }
    const double t_final = request.times[request.count - 1];
    if (t_final == request.t0) {
      Finish(request, 0, result);
      return result;
    }

    int flag = Initialize(request.t0);
    if (flag == ARK_SUCCESS && events_changed) {
      flag = InitializeEvents();
      if (flag == ARK_SUCCESS) events_changed = false;
    }
    if (flag == ARK_SUCCESS) {
      flag = explicit_ ? ERKStepSVtolerances(memory_, options_.relative_tolerance, abstol_.get())
                       : ARKStepSVtolerances(memory_, options_.relative_tolerance, abstol_.get());
    }
    if (flag == ARK_SUCCESS) {
      flag = explicit_ ? ERKStepSetStopTime(memory_, t_final)
                       : ARKStepSetStopTime(memory_, t_final);
    }
    if (flag != ARK_SUCCESS) return Failure(flag, request.t0, result);

    double t = request.t0;
    for (Index k = 0; k < request.count; ++k) {
      const double t_out = request.times[k];
      while (t != t_out) {
        flag = explicit_ ? ERKStepEvolve(memory_, t_out, z_.get(), &t, ARK_NORMAL)
                         : ARKStepEvolve(memory_, t_out, z_.get(), &t, ARK_NORMAL);
        if (flag < 0) {
          Statistics(result);
          return Failure(flag, t, result);
        }
        if (flag == ARK_ROOT_RETURN) {
          RecordEvents(t, result);
          if (context.events->terminal) {
            result.stopped_at_event = true;
            result.t_reached = t;
            Finish(request, k, result);
            return result;
          }
        }
      }
      if (request.states != nullptr) {
        Eigen::Map<Vector>(request.states + k * n, n) = z.head(n);
      }
    }
    result.t_reached = t;
    Finish(request, request.count, result);
    return result;
  }

 private:
  int Initialize(double t0) {
    if (memory_ != nullptr) {
      return explicit_ ? ERKStepReInit(memory_, ArkodeRhs, t0, z_.get())
                       : ARKStepReInit(memory_, nullptr, ArkodeRhs, t0, z_.get());
    }
    CallbackContext& context = *data_.context;
    memory_ = explicit_ ? ERKStepCreate(ArkodeRhs, t0, z_.get(), sun_context_)
                        : ARKStepCreate(nullptr, ArkodeRhs, t0, z_.get(), sun_context_);
    if (memory_ == nullptr) throw std::bad_alloc();
    int flag;
    if (explicit_) {
      if ((flag = ERKStepSetUserData(memory_, &data_)) != ARK_SUCCESS) return flag;
      if ((flag = ERKStepSetErrHandlerFn(memory_, RecordError, &context)) != ARK_SUCCESS) {
        return flag;
      }
      if ((flag = ERKStepSetTableNum(memory_, ExplicitTable(options_.explicit_order))) !=
          ARK_SUCCESS) {
        return flag;
      }
      if ((flag = ERKStepSetMaxNumSteps(memory_, options_.max_steps)) != ARK_SUCCESS) return flag;
      if (options_.max_step > 0.0 &&
          (flag = ERKStepSetMaxStep(memory_, options_.max_step)) != ARK_SUCCESS) {
        return flag;
      }
      if (options_.initial_step > 0.0 &&
          (flag = ERKStepSetInitStep(memory_, options_.initial_step)) != ARK_SUCCESS) {
        return flag;
      }
      return ARK_SUCCESS;
    }
    if ((flag = ARKStepSetUserData(memory_, &data_)) != ARK_SUCCESS) return flag;
    if ((flag = ARKStepSetErrHandlerFn(memory_, RecordError, &context)) != ARK_SUCCESS) {
      return flag;
    }
    if ((flag = ARKStepSetOrder(memory_, options_.implicit_order)) != ARK_SUCCESS) return flag;
    if ((flag = ARKStepSetLinearSolver(memory_, solver_.get(), matrix_.get())) != ARK_SUCCESS) {
      return flag;
    }
    if (data_.columns > 0 || context.system->HasJacobian()) {
      if ((flag = ARKStepSetJacFn(memory_, ArkodeJacobian)) != ARK_SUCCESS) return flag;
    }  // else ARKODE's difference-quotient Jacobian
    if ((flag = ARKStepSetMaxNumSteps(memory_, options_.max_steps)) != ARK_SUCCESS) return flag;
    if (options_.max_step > 0.0 &&
        (flag = ARKStepSetMaxStep(memory_, options_.max_step)) != ARK_SUCCESS) {
      return flag;
    }
    if (options_.initial_step > 0.0 &&
        (flag = ARKStepSetInitStep(memory_, options_.initial_step)) != ARK_SUCCESS) {
      return flag;
    }
    return ARK_SUCCESS;
  }

  int InitializeEvents() {
    const EventOptions* events = data_.context->events;
    if (events == nullptr) {
      return explicit_ ? ERKStepRootInit(memory_, 0, nullptr)
                       : ARKStepRootInit(memory_, 0, nullptr);
    }
    int flag = explicit_ ? ERKStepRootInit(memory_, events->count, ArkodeRoots)
                         : ARKStepRootInit(memory_, events->count, ArkodeRoots);
    if (flag != ARK_SUCCESS) return flag;
    root_directions_.assign(events->count, 0);
    root_found_.assign(events->count, 0);
    if (!events->directions.empty()) root_directions_ = events->directions;
    flag = explicit_ ? ERKStepSetRootDirection(memory_, root_directions_.data())
                     : ARKStepSetRootDirection(memory_, root_directions_.data());
    if (flag != ARK_SUCCESS) return flag;
    return explicit_ ? ERKStepSetNoInactiveRootWarn(memory_)
                     : ARKStepSetNoInactiveRootWarn(memory_);
  }

  void RecordEvents(double t, IntegrationResult& result) {
    const Index n = data_.context->n;
    if (explicit_) {
      ERKStepGetRootInfo(memory_, root_found_.data());
    } else {
      ARKStepGetRootInfo(memory_, root_found_.data());
    }
    for (int i = 0; i < static_cast<int>(root_found_.size()); ++i) {
      if (root_found_[i] != 0) {
        result.events.push_back({i, root_found_[i], t, MapVector(z_.get()).head(n)});
      }
    }
  }

  // Copies outputs from the current z: x_final, states from index `filled` on, Φ and q.
  void Finish(const IntegrationRequest& request, Index filled, IntegrationResult& result) {
    const Index n = data_.context->n;
    const auto z = MapVector(z_.get());
    Eigen::Map<Vector>(request.x_final, n) = z.head(n);
    if (request.states != nullptr) {
      for (Index k = filled; k < request.count; ++k) {
        Eigen::Map<Vector>(request.states + k * n, n) = z.head(n);
      }
    }
    const Index stm_columns = request.StmColumns(n);
    if (stm_columns > 0) {
      Eigen::Map<Matrix>(request.stm, n, stm_columns) =
          Eigen::Map<const Matrix>(z.data() + n, n, stm_columns);
    }
    if (request.dxdp != nullptr) {
      Eigen::Map<Vector>(request.dxdp, n) = z.segment(n * (1 + n), n);
    }
    if (memory_ != nullptr && request.times[request.count - 1] != request.t0) Statistics(result);
    result.warnings = data_.context->warnings;
  }

  void Statistics(IntegrationResult& result) {
    IntegrationStatistics& s = result.statistics;
    if (explicit_) {
      ERKStepGetNumSteps(memory_, &s.steps);
      ERKStepGetNumRhsEvals(memory_, &s.rhs_evaluations);
      ERKStepGetNumErrTestFails(memory_, &s.error_test_failures);
      return;
    }
    long explicit_evaluations = 0;
    ARKStepGetNumSteps(memory_, &s.steps);
    ARKStepGetNumRhsEvals(memory_, &explicit_evaluations, &s.rhs_evaluations);
    ARKStepGetNumJacEvals(memory_, &s.jacobian_evaluations);
    ARKStepGetNumLinSolvSetups(memory_, &s.linear_solver_setups);
    ARKStepGetNumErrTestFails(memory_, &s.error_test_failures);
    ARKStepGetNumNonlinSolvIters(memory_, &s.nonlinear_iterations);
    ARKStepGetNumNonlinSolvConvFails(memory_, &s.nonlinear_convergence_failures);
  }

  IntegrationResult& Failure(int flag, double t, IntegrationResult& result) {
    CallbackContext& context = *data_.context;
    result.status = StatusFromArkodeFlag(flag, context);
    result.flag = flag;
    result.flag_name = TakeFlagName(explicit_ ? ERKStepGetReturnFlagName(flag)
                                              : ARKStepGetReturnFlagName(flag));
    result.t_reached = t;
    result.warnings = context.warnings;
    if (context.state_bound_exceeded) {
      result.message = StateBoundMessage(options_.state_bound, t);
    } else if (context.non_finite && context.error_message.empty()) {
      result.message = "the right-hand side returned NaN or Inf";
    } else {
      result.message = context.error_message;
    }
    return result;
  }

  bool explicit_;
  SUNContext sun_context_;  // owned by ArkodeBackend
  IntegratorOptions options_;
  ArkodeUserData data_;
  Index m_ = 0;
  NVectorPtr z_;
  NVectorPtr abstol_;
  SunMatrixPtr matrix_;
  SunLinearSolverPtr solver_;
  void* memory_ = nullptr;
  std::vector<int> root_directions_;
  std::vector<int> root_found_;

 public:
  bool events_changed = true;
};

ArkodeBackend::ArkodeBackend(CallbackContext& context, const IntegratorOptions& options)
    : context_(context), options_(options), sun_context_(MakeSunContext()) {}

ArkodeBackend::~ArkodeBackend() {
  for (auto& memory : memories_) memory.reset();  // before the SUNContext member goes
}

void ArkodeBackend::EventsChanged() {
  for (auto& memory : memories_) {
    if (memory) memory->events_changed = true;
  }
}

IntegrationResult ArkodeBackend::Run(const IntegrationRequest& request) {
  const int slot = request.stm == nullptr ? 0
                   : request.seeds != nullptr ? 3
                   : request.dxdp == nullptr  ? 1
                                              : 2;
  const int columns = static_cast<int>(request.StmColumns(context_.n)) + (request.dxdp != nullptr ? 1 : 0);
  if (memories_[slot] && memories_[slot]->columns() != columns) memories_[slot].reset();
  if (!memories_[slot]) {
    memories_[slot] = std::make_unique<Memory>(context_, options_, sun_context_.get(), columns);
  }
  return memories_[slot]->Run(request, memories_[slot]->events_changed);
}

}  // namespace detail
}  // namespace rubcont
