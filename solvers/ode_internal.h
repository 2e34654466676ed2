// Private to solvers/ode*.cpp: what the SUNDIALS C callbacks share, and the backends.
#pragma once

#include <exception>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/LU>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include "solvers/ode.h"

namespace rubcont {
namespace detail {

// RAII for SUNDIALS objects. Members that hold them are declared context first, so that they are
// destroyed in the reverse order (integrator memory, solver, matrix, vectors, then the context).
struct SunContextDeleter {
  void operator()(SUNContext context) const { SUNContext_Free(&context); }
};
struct NVectorDeleter {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
struct SunMatrixDeleter {
  void operator()(SUNMatrix m) const { SUNMatDestroy(m); }
};
struct SunLinearSolverDeleter {
  void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
};
using SunContextPtr = std::unique_ptr<std::remove_pointer_t<SUNContext>, SunContextDeleter>;
using NVectorPtr = std::unique_ptr<std::remove_pointer_t<N_Vector>, NVectorDeleter>;
using SunMatrixPtr = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, SunMatrixDeleter>;
using SunLinearSolverPtr =
    std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, SunLinearSolverDeleter>;

SunContextPtr MakeSunContext();
NVectorPtr MakeNVector(Index size, SUNContext context);

inline Eigen::Map<Vector> MapVector(N_Vector v) {
  return Eigen::Map<Vector>(N_VGetArrayPointer(v), N_VGetLength_Serial(v));
}

// Everything a callback needs: the system, workspaces sized once, and what went wrong. The
// integrator owns one; SUNDIALS sees it as user_data.
struct CallbackContext {
  OdeSystem* system = nullptr;
  Index n = 0;
  Vector scale;          // OdeSystem::StateScale()
  Vector inverse_scale;  // 1 ./ scale
  double state_bound = 0.0;
  Matrix jacobian;       // n × n, for sensitivity right-hand sides
  Vector dfdp;           // n
  Vector event_values;   // events->count
  const EventOptions* events = nullptr;  // null: no events

  // Set by callbacks during one integration call; cleared by BeginRun().
  std::exception_ptr exception;  // thrown by the system inside a callback: rethrown after the call
  bool state_bound_exceeded = false;
  bool non_finite = false;
  std::string error_message;     // the last message of SUNDIALS' error handler
  int warnings = 0;

  void BeginRun();
  // Rethrows a stored exception (after the SUNDIALS call has returned: never through C frames).
  void RethrowIfAny();
};

// f = Rhs(t, x) with the checks: 0 on success, +1 (recoverable: the integrator retries with a
// smaller step) when f is not finite, −1 (unrecoverable) when x is beyond the state bound or the
// system threw.
int EvaluateRhs(CallbackContext& context, double t, const double* x, double* f);
// J = JacobianX(t, x) into an n × n column-major array (leading dimension n).
int EvaluateJacobian(CallbackContext& context, double t, const double* x, double* J);
// ∂f/∂p at (t, x) into context.dfdp.
int EvaluateDfDparameter(CallbackContext& context, double t, const double* x);
// g(t, x) into gout (events->count entries).
int EvaluateEvents(CallbackContext& context, double t, const double* x, double* gout);

// The message of IntegrationStatus::kStateBound, reached near time t.
std::string StateBoundMessage(double state_bound, double t);

// CVODES / ARKODE error handler: records the message, prints nothing.
void RecordError(int error_code, const char* module, const char* function, char* msg,
                 void* user_data);

// A flag name from SUNDIALS' *GetReturnFlagName (which mallocs; freed here).
std::string TakeFlagName(char* name);

// What one call asks for. Output times are monotone; the last one is the final time.
struct IntegrationRequest {
  double t0 = 0.0;
  const double* x0 = nullptr;     // n
  const double* times = nullptr;  // count output times
  Index count = 0;
  double* states = nullptr;       // n × count, column-major, or null
  double* x_final = nullptr;      // n
  double* stm = nullptr;          // n × columns (below), column-major, or null
  double* dxdp = nullptr;         // n, or null (only with stm and without seeds)
  // ∂x(t1)/∂t1 of the method's own map, n, or null (only with stm and without seeds; Gauss only:
  // OdeIntegrator computes f(t1, x1) for the others).
  double* dxdt1 = nullptr;
  // The sensitivities' initial columns: null for the identity (stm is then Φ, n × n), otherwise
  // n × seed_count (1 ≤ seed_count ≤ n) and stm receives Φ·seeds, n × seed_count.
  const double* seeds = nullptr;
  Index seed_count = 0;
  double parameter_scale = 1.0;   // for the tolerance on ∂x/∂p

  // How many columns stm has (0 without stm).
  Index StmColumns(Index n) const { return stm == nullptr ? 0 : (seeds != nullptr ? seed_count : n); }
  // The initial value of stm's column j: the seed, or e_j.
  Vector InitialColumn(Index j, Index n) const {
    if (seeds != nullptr) return Eigen::Map<const Vector>(seeds + j * n, n);
    return Vector::Unit(n, j);
  }
};

class CvodesBackend {
 public:
  CvodesBackend(CallbackContext& context, const IntegratorOptions& options);
  ~CvodesBackend();
  CvodesBackend(const CvodesBackend&) = delete;
  CvodesBackend& operator=(const CvodesBackend&) = delete;
  IntegrationResult Run(const IntegrationRequest& request);
  void EventsChanged() { events_changed_ = true; }

 private:
  class State;
  std::unique_ptr<State> state_;
  bool events_changed_ = true;
};

class ArkodeBackend {
 public:
  ArkodeBackend(CallbackContext& context, const IntegratorOptions& options);
  ~ArkodeBackend();
  ArkodeBackend(const ArkodeBackend&) = delete;
  ArkodeBackend& operator=(const ArkodeBackend&) = delete;
  IntegrationResult Run(const IntegrationRequest& request);
  void EventsChanged();

 private:
  class Memory;
  CallbackContext& context_;
  IntegratorOptions options_;
  SunContextPtr sun_context_;
  // One memory per augmented size: plain (n), with STM (n + n²), with STM and ∂x/∂p (n + n² + n).
  std::unique_ptr<Memory> memories_[4];  // plain, Φ, Φ and q, Φ·seeds
};

// Boost.Odeint's Dormand–Prince 5(4) (ode_odeint.cpp): the state only, no events.
class OdeintBackend {
 public:
  OdeintBackend(CallbackContext& context, const IntegratorOptions& options);
  ~OdeintBackend();
  OdeintBackend(const OdeintBackend&) = delete;
  OdeintBackend& operator=(const OdeintBackend&) = delete;
  IntegrationResult Run(const IntegrationRequest& request);
  class Stepper;  // one per state container (ode_odeint.cpp)

 private:
  std::unique_ptr<Stepper> stepper_;
};

// The s-stage Gauss–Legendre collocation method on [0, 1] (ode_gauss.cpp).
struct GaussCoefficients {
  Vector c, b;      // nodes and weights
  Matrix A;         // A_ij = ∫₀^{c_i} ℓ_j
  Matrix A_inverse;
  Vector d;         // dᵀ = bᵀ A⁻¹: x_{n+1} = x_n + Σ d_i Z_i
  Matrix vandermonde_inverse;
  static GaussCoefficients Make(int stages);
  // γ(θ): the collocation polynomial u(t_n + θh) = x_n + Σ_j γ_j(θ) Z_j (θ = 1 + c_i extrapolates).
  Vector Interpolation(double theta) const;
};

class GaussBackend {
 public:
  GaussBackend(CallbackContext& context, const IntegratorOptions& options);
  IntegrationResult Run(const IntegrationRequest& request);
  void SetMesh(std::vector<double> fractions);
  const Matrix& Derivatives() const { return step_derivatives_; }

 private:
  bool SolveStages(double t, const Vector& x, double h, std::string& failure);
  void FactorNewtonMatrix(double h);
  void SolveWithNewtonMatrix(double h, const Matrix& rhs, Matrix& out);
  void SolveWithNewtonMatrix(double h, const Vector& rhs, Vector& out);
  void SolveScalarOscillator(double h, const Matrix& rhs, Matrix& out);
  IntegrationResult Fail(IntegrationStatus status, double t, std::string message);

  CallbackContext& context_;
  IntegratorOptions options_;
  GaussCoefficients coefficients_;
  IntegrationStatistics statistics_;
  Vector x_, previous_x_, stage_state_, later_, earlier_;
  Matrix stages_, previous_stages_, derivatives_;  // n × s: Z, Z of the previous step, F
  std::vector<Matrix> jacobians_;                   // J at each stage
  std::vector<Vector> extrapolation_;               // γ(1 + c_i)
  Vector output_weights_, guess_weights_;
  std::vector<double> mesh_;   // fractions of the span; empty: uniform collocation_steps
  Vector derivative_weights_;  // u^(s) = Z·derivative_weights_ / h^s on a step
  Matrix step_derivatives_;    // n × steps: u^(s) on each step of the last Run
  Matrix newton_matrix_;
  Eigen::PartialPivLU<Matrix> lu_;
  // Whether the last evaluation's stages are a second-order system's, and whether the last
  // factorisation is the Schur complement M_V (its matrix, factors and work space below).
  bool second_order_ = false;
  bool reduced_ = false;
  Matrix reduced_matrix_, reduced_rhs_, reduced_products_, vector_rhs_, vector_out_;
  Eigen::PartialPivLU<Matrix> reduced_lu_;
  Vector residual_, increment_;
  Matrix sensitivity_rhs_, blocks_;
};

}  // namespace detail
}  // namespace rubcont
