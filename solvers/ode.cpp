#include "solvers/ode.h"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include <fmt/core.h>

#include "solvers/ode_internal.h"

namespace rubcont {

const char* ToString(IntegrationMethod method) {
  switch (method) {
    case IntegrationMethod::kBdf: return "CVODES BDF";
    case IntegrationMethod::kAdams: return "CVODES Adams";
    case IntegrationMethod::kExplicitRungeKutta: return "ARKODE ERK";
    case IntegrationMethod::kDiagonallyImplicitRungeKutta: return "ARKODE DIRK";
    case IntegrationMethod::kGaussCollocation: return "Gauss collocation";
    case IntegrationMethod::kDormandPrince: return "Odeint Dormand-Prince";
  }
  return "unknown";
}

const char* ToString(IntegrationStatus status) {
  switch (status) {
    case IntegrationStatus::kSuccess: return "success";
    case IntegrationStatus::kTooMuchWork: return "too much work (max_steps reached)";
    case IntegrationStatus::kTooMuchAccuracy: return "tolerances too small";
    case IntegrationStatus::kErrorTestFailures: return "repeated error-test failures";
    case IntegrationStatus::kConvergenceFailures: return "repeated convergence failures";
    case IntegrationStatus::kLinearSolverFailure: return "linear solver failure";
    case IntegrationStatus::kRhsFailure: return "right-hand side failure";
    case IntegrationStatus::kNonFinite: return "non-finite right-hand side";
    case IntegrationStatus::kStateBound: return "state bound exceeded";
    case IntegrationStatus::kOther: return "integrator failure";
  }
  return "unknown";
}

void Validate(const IntegratorOptions& options) {
  auto fail = [](const char* field, double value, const char* rule) {
    throw std::invalid_argument(
        fmt::format("IntegratorOptions.{} = {}: {}", field, value, rule));
  };
  if (!(options.relative_tolerance > 0.0 && options.relative_tolerance < 1.0)) {
    fail("relative_tolerance", options.relative_tolerance, "must lie in (0, 1)");
  }
  if (!(options.absolute_tolerance > 0.0 && options.absolute_tolerance < 1.0)) {
    fail("absolute_tolerance", options.absolute_tolerance, "must lie in (0, 1)");
  }
  if (options.max_steps < 1) fail("max_steps", options.max_steps, "must be at least 1");
  if (!(options.max_step >= 0.0) || std::isinf(options.max_step)) {
    fail("max_step", options.max_step, "must be finite and non-negative (0: unlimited)");
  }
  if (!(options.initial_step >= 0.0) || std::isinf(options.initial_step)) {
    fail("initial_step", options.initial_step, "must be finite and non-negative (0: automatic)");
  }
  const int max_order_limit = options.method == IntegrationMethod::kAdams ? 12 : 5;
  if ((options.method == IntegrationMethod::kBdf || options.method == IntegrationMethod::kAdams) &&
      (options.max_order < 0 || options.max_order > max_order_limit)) {
    fail("max_order", options.max_order,
         options.method == IntegrationMethod::kAdams ? "must lie in [0, 12] for Adams"
                                                     : "must lie in [0, 5] for BDF");
  }
  const int e = options.explicit_order;
  if (e != 2 && e != 3 && e != 4 && e != 5 && e != 6 && e != 8) {
    fail("explicit_order", e, "must be 2, 3, 4, 5, 6 or 8");
  }
  if (options.implicit_order < 2 || options.implicit_order > 5) {
    fail("implicit_order", options.implicit_order, "must lie in [2, 5]");
  }
  if (options.collocation_stages < 1 || options.collocation_stages > 6) {
    fail("collocation_stages", options.collocation_stages, "must lie in [1, 6]");
  }
  if (options.collocation_steps < 1) {
    fail("collocation_steps", static_cast<double>(options.collocation_steps), "must be at least 1");
  }
  if (!(options.parameter_scale >= 0.0) || std::isinf(options.parameter_scale)) {
    fail("parameter_scale", options.parameter_scale,
         "must be finite and non-negative (0: max(|p|, 1))");
  }
  if (!(options.state_bound > 1.0)) fail("state_bound", options.state_bound, "must exceed 1");
}

void Accumulate(IntegrationStatistics& a, const IntegrationStatistics& b) {
  a.steps += b.steps;
  a.rhs_evaluations += b.rhs_evaluations;
  a.jacobian_evaluations += b.jacobian_evaluations;
  a.linear_solver_setups += b.linear_solver_setups;
  a.reduced_setups += b.reduced_setups;
  a.error_test_failures += b.error_test_failures;
  a.nonlinear_iterations += b.nonlinear_iterations;
  a.nonlinear_convergence_failures += b.nonlinear_convergence_failures;
  a.sensitivity_rhs_evaluations += b.sensitivity_rhs_evaluations;
  a.restarts += b.restarts;
  a.work += b.work;
}

long long WorkPerStep(IntegrationMethod method) {
  switch (method) {
    case IntegrationMethod::kExplicitRungeKutta:
    case IntegrationMethod::kDormandPrince:
      return 1;
    case IntegrationMethod::kBdf:
    case IntegrationMethod::kAdams:
    case IntegrationMethod::kDiagonallyImplicitRungeKutta:
      return 4;
    case IntegrationMethod::kGaussCollocation:
      return 100;
  }
  return 1;
}

namespace {
thread_local WorkAccount* current_work_account = nullptr;
}  // namespace

WorkAccount::WorkAccount() : outer_(current_work_account) {}

void WorkAccount::Add(long long work) {
  for (WorkAccount* account = this; account != nullptr; account = account->outer_) {
    account->work_.fetch_add(work, std::memory_order_relaxed);
  }
}

WorkScope::WorkScope(WorkAccount* account) : previous_(current_work_account) {
  current_work_account = account;
}

WorkScope::~WorkScope() { current_work_account = previous_; }

WorkAccount* CurrentWorkAccount() { return current_work_account; }

std::string IntegrationResult::BriefReport() const {
  std::string report = fmt::format("{} at t = {:.6g}: {} steps, {} f evaluations", ToString(status),
                                   t_reached, statistics.steps, statistics.rhs_evaluations);
  if (!Succeeded()) {
    report += fmt::format(" ({}: {})", flag_name, message);
  }
  return report;
}

namespace detail {

SunContextPtr MakeSunContext() {
  SUNContext context = nullptr;
  if (SUNContext_Create(nullptr, &context) != 0 || context == nullptr) {
    throw std::bad_alloc();
  }
  return SunContextPtr(context);
}

NVectorPtr MakeNVector(Index size, SUNContext context) {
  N_Vector v = N_VNew_Serial(static_cast<sunindextype>(size), context);
  if (v == nullptr) throw std::bad_alloc();
  return NVectorPtr(v);
}

void CallbackContext::BeginRun() {
  exception = nullptr;
  state_bound_exceeded = false;
  non_finite = false;
  error_message.clear();
  warnings = 0;
}

void CallbackContext::RethrowIfAny() {
  if (exception) {
    std::exception_ptr e = exception;
    exception = nullptr;
    std::rethrow_exception(e);
  }
}

int EvaluateRhs(CallbackContext& context, double t, const double* x, double* f) {
  const Index n = context.n;
  Eigen::Map<const Vector> x_map(x, n);
  Eigen::Map<Vector> f_map(f, n);
  // ‖x ./ scale‖∞, written so that NaN in x also trips it.
  const double size = x_map.cwiseProduct(context.inverse_scale).cwiseAbs().maxCoeff();
  if (!(size <= context.state_bound)) {
    if (std::isnan(size)) {
      context.non_finite = true;
      return 1;
    }
    context.state_bound_exceeded = true;
    return -1;
  }
  try {
    context.system->Rhs(t, x_map, f_map);
  } catch (...) {
    context.exception = std::current_exception();
    return -1;
  }
  if (!f_map.allFinite()) {
    context.non_finite = true;
    return 1;
  }
  return 0;
}

int EvaluateJacobian(CallbackContext& context, double t, const double* x, double* J) {
  const Index n = context.n;
  Eigen::Map<Matrix> J_map(J, n, n);
  try {
    context.system->JacobianX(t, Eigen::Map<const Vector>(x, n), J_map);
  } catch (...) {
    context.exception = std::current_exception();
    return -1;
  }
  if (!J_map.allFinite()) {
    context.non_finite = true;
    return 1;
  }
  return 0;
}

int EvaluateDfDparameter(CallbackContext& context, double t, const double* x) {
  try {
    context.system->DfDparameter(t, Eigen::Map<const Vector>(x, context.n), context.dfdp);
  } catch (...) {
    context.exception = std::current_exception();
    return -1;
  }
  if (!context.dfdp.allFinite()) {
    context.non_finite = true;
    return 1;
  }
  return 0;
}

int EvaluateEvents(CallbackContext& context, double t, const double* x, double* gout) {
  const int count = context.events->count;
  Eigen::Map<Vector> g(gout, count);
  try {
    context.events->function(t, Eigen::Map<const Vector>(x, context.n), g);
  } catch (...) {
    context.exception = std::current_exception();
    return -1;
  }
  return 0;
}

std::string StateBoundMessage(double state_bound, double t) {
  return fmt::format("‖x ./ scale‖∞ exceeded state_bound = {:g} near t = {:.9g}", state_bound, t);
}

void RecordError(int error_code, const char* /*module*/, const char* function, char* msg,
                 void* user_data) {
  auto& context = *static_cast<CallbackContext*>(user_data);
  if (error_code > 0) {  // CV_WARNING / ARK_WARNING
    ++context.warnings;
    return;
  }
  context.error_message = fmt::format("{}: {}", function ? function : "", msg ? msg : "");
}

std::string TakeFlagName(char* name) {
  std::string result = name != nullptr ? name : "";
  std::free(name);
  return result;
}

}  // namespace detail

class OdeIntegrator::Impl {
 public:
  Impl(OdeSystem& system, const IntegratorOptions& options) : options_(options) {
    Validate(options);
    const Index n = system.Dimension();
    if (n < 1) {
      throw std::invalid_argument(fmt::format("OdeIntegrator: system dimension {} < 1", n));
    }
    context_.system = &system;
    context_.n = n;
    context_.scale = system.StateScale();
    if (context_.scale.size() != n || !(context_.scale.array() > 0.0).all() ||
        !context_.scale.allFinite()) {
      throw std::invalid_argument(fmt::format(
          "OdeIntegrator: OdeSystem::StateScale() must have {} finite positive entries", n));
    }
    context_.inverse_scale = context_.scale.cwiseInverse();
    context_.state_bound = options.state_bound;
    context_.jacobian.resize(n, n);
    context_.dfdp.resize(n);
    if (options.method == IntegrationMethod::kBdf || options.method == IntegrationMethod::kAdams) {
      cvodes_ = std::make_unique<detail::CvodesBackend>(context_, options);
    } else if (options.method == IntegrationMethod::kGaussCollocation) {
      gauss_ = std::make_unique<detail::GaussBackend>(context_, options);
    } else if (options.method == IntegrationMethod::kDormandPrince) {
      odeint_ = std::make_unique<detail::OdeintBackend>(context_, options);
    } else {
      arkode_ = std::make_unique<detail::ArkodeBackend>(context_, options);
    }
  }

  IntegrationResult Run(const detail::IntegrationRequest& request) {
    context_.BeginRun();
    IntegrationResult result = cvodes_   ? cvodes_->Run(request)
                               : gauss_  ? gauss_->Run(request)
                               : odeint_ ? odeint_->Run(request)
                                         : arkode_->Run(request);
    result.statistics.work = result.statistics.steps * WorkPerStep(options_.method) * context_.n;
    if (current_work_account != nullptr) current_work_account->Add(result.statistics.work);
    context_.RethrowIfAny();
    return result;
  }

  void SetEvents(const EventOptions& events) {
    if (gauss_ || odeint_) {
      throw std::invalid_argument(fmt::format(
          "OdeIntegrator: events need an integrator with root finding (CVODES or ARKODE), not {}",
          ToString(options_.method)));
    }
    if (!events.function || events.count < 1) {
      throw std::invalid_argument(fmt::format(
          "EventOptions: count = {} and function {}: need count ≥ 1 and a function", events.count,
          events.function ? "set" : "empty"));
    }
    if (!events.directions.empty() &&
        static_cast<int>(events.directions.size()) != events.count) {
      throw std::invalid_argument(
          fmt::format("EventOptions.directions has {} entries: must be empty or count = {}",
                      events.directions.size(), events.count));
    }
    events_ = events;
    context_.events = &events_;
    context_.event_values.resize(events.count);
    NotifyEvents();
  }

  void ClearEvents() {
    context_.events = nullptr;
    NotifyEvents();
  }

  detail::GaussBackend& Gauss(const char* caller) const {
    if (!gauss_) {
      throw std::invalid_argument(fmt::format("OdeIntegrator::{}: Gauss collocation only, not {}",
                                              caller, ToString(options_.method)));
    }
    return *gauss_;
  }

  const IntegratorOptions& options() const { return options_; }
  OdeSystem& system() { return *context_.system; }
  Index n() const { return context_.n; }
  // Workspaces: the initial state is copied (x0 and x1 may alias), and Sample needs an end state.
  Vector& x0_buffer() { return x0_buffer_; }
  Vector& x_final_buffer() { return x_final_buffer_; }

 private:
  void NotifyEvents() {
    if (cvodes_) cvodes_->EventsChanged();
    if (arkode_) arkode_->EventsChanged();
  }

  IntegratorOptions options_;
  detail::CallbackContext context_;
  EventOptions events_;
  Vector x0_buffer_;
  Vector x_final_buffer_;
  std::unique_ptr<detail::CvodesBackend> cvodes_;
  std::unique_ptr<detail::ArkodeBackend> arkode_;
  std::unique_ptr<detail::GaussBackend> gauss_;
  std::unique_ptr<detail::OdeintBackend> odeint_;
};

OdeIntegrator::OdeIntegrator(OdeSystem& system, const IntegratorOptions& options)
    : impl_(std::make_unique<Impl>(system, options)) {}
OdeIntegrator::~OdeIntegrator() = default;
OdeIntegrator::OdeIntegrator(OdeIntegrator&&) noexcept = default;
OdeIntegrator& OdeIntegrator::operator=(OdeIntegrator&&) noexcept = default;

const IntegratorOptions& OdeIntegrator::options() const { return impl_->options(); }
OdeSystem& OdeIntegrator::system() { return impl_->system(); }
void OdeIntegrator::SetEvents(const EventOptions& events) { impl_->SetEvents(events); }
void OdeIntegrator::ClearEvents() { impl_->ClearEvents(); }

namespace {

void CheckSize(const char* what, Index size, Index n) {
  if (size != n) {
    throw std::invalid_argument(
        fmt::format("OdeIntegrator: {} has {} entries, the system has dimension {}", what, size, n));
  }
}

void CheckTime(const char* what, double t) {
  if (!std::isfinite(t)) {
    throw std::invalid_argument(fmt::format("OdeIntegrator: {} = {} must be finite", what, t));
  }
}

// Output times: finite and monotone from t0 in `direction` (+1 or −1).
void CheckOutputTimes(const char* caller, double t0, double direction, const Vector& times) {
  double previous = t0;
  for (Index k = 0; k < times.size(); ++k) {
    CheckTime("times(k)", times(k));
    if (direction * (times(k) - previous) < 0.0) {
      throw std::invalid_argument(fmt::format(
          "OdeIntegrator::{}: times({}) = {} is out of order (previous {}, t0 = {}): times must "
          "be monotone in the direction of integration",
          caller, k, times(k), previous, t0));
    }
    previous = times(k);
  }
}

double ParameterScale(const IntegratorOptions& options, double p) {
  return options.parameter_scale > 0.0 ? options.parameter_scale : std::max(std::abs(p), 1.0);
}

}  // namespace

IntegrationResult OdeIntegrator::Integrate(double t0, ConstVectorRef x0, double t1, VectorRef x1,
                                           Matrix* stm, Vector* dxdp, Vector* dxdt1) {
  const Index n = impl_->n();
  CheckSize("x0", x0.size(), n);
  CheckSize("x1", x1.size(), n);
  CheckTime("t0", t0);
  CheckTime("t1", t1);
  if (dxdp != nullptr && stm == nullptr) {
    throw std::invalid_argument("OdeIntegrator::Integrate: dxdp requires stm as well");
  }
  if (dxdt1 != nullptr && stm == nullptr) {
    throw std::invalid_argument("OdeIntegrator::Integrate: dxdt1 requires stm as well");
  }
  if (stm != nullptr) stm->resize(n, n);
  if (dxdp != nullptr) dxdp->resize(n);
  if (dxdt1 != nullptr) dxdt1->resize(n);
  const bool gauss = impl_->options().method == IntegrationMethod::kGaussCollocation;
  Vector& x0_copy = impl_->x0_buffer();
  x0_copy = x0;
  detail::IntegrationRequest request;
  request.t0 = t0;
  request.x0 = x0_copy.data();
  request.times = &t1;
  request.count = 1;
  request.x_final = x1.data();
  request.stm = stm != nullptr ? stm->data() : nullptr;
  request.dxdp = dxdp != nullptr ? dxdp->data() : nullptr;
  request.dxdt1 = dxdt1 != nullptr && gauss ? dxdt1->data() : nullptr;
  request.parameter_scale = ParameterScale(impl_->options(), impl_->system().Parameter());
  IntegrationResult result = impl_->Run(request);
  if (dxdt1 != nullptr && !gauss && result.Succeeded()) impl_->system().Rhs(t1, x1, *dxdt1);
  return result;
}

IntegrationResult OdeIntegrator::IntegrateTangents(double t0, ConstVectorRef x0, double t1,
                                                    VectorRef x1, const Matrix& directions,
                                                    Matrix& images, const Vector& times,
                                                    Matrix* samples) {
  const Index n = impl_->n();
  CheckSize("x0", x0.size(), n);
  CheckSize("x1", x1.size(), n);
  CheckSize("directions' rows", directions.rows(), n);
  CheckTime("t0", t0);
  CheckTime("t1", t1);
  if (directions.cols() < 1 || directions.cols() > n) {
    throw std::invalid_argument(fmt::format(
        "OdeIntegrator::IntegrateTangents: {} directions: must be 1 … {} (the dimension)",
        directions.cols(), n));
  }
  // The output times: the samples, then t1.
  const Index m = samples != nullptr ? times.size() : 0;
  Vector outputs(m + 1);
  outputs.head(m) = times.head(m);
  outputs(m) = t1;
  if (m > 0 && (t1 >= t0 ? times(m - 1) > t1 : times(m - 1) < t1)) {
    throw std::invalid_argument(fmt::format(
        "OdeIntegrator::IntegrateTangents: times({}) = {}: the sample times must be monotone "
        "within [t0, t1] = [{}, {}]", m - 1, times(m - 1), t0, t1));
  }
  CheckOutputTimes("IntegrateTangents", t0, t1 >= t0 ? 1.0 : -1.0, outputs);  // t1 last
  Matrix states(n, m + 1);
  const Matrix seeds = directions;  // images may alias directions
  images.resize(n, seeds.cols());
  Vector& x0_copy = impl_->x0_buffer();
  x0_copy = x0;
  detail::IntegrationRequest request;
  request.t0 = t0;
  request.x0 = x0_copy.data();
  request.times = outputs.data();
  request.count = outputs.size();
  request.states = states.data();
  request.x_final = x1.data();
  request.stm = images.data();
  request.seeds = seeds.data();
  request.seed_count = seeds.cols();
  request.parameter_scale = ParameterScale(impl_->options(), impl_->system().Parameter());
  IntegrationResult result = impl_->Run(request);
  if (samples != nullptr) *samples = states.leftCols(m);
  return result;
}

void OdeIntegrator::SetCollocationMesh(std::vector<double> fractions) {
  impl_->Gauss("SetCollocationMesh").SetMesh(std::move(fractions));
}

const Matrix& OdeIntegrator::CollocationDerivatives() const {
  return impl_->Gauss("CollocationDerivatives").Derivatives();
}

Vector CollocationMonitor(const Vector& times, const Matrix& derivatives, int stages) {
  const Index steps = times.size() - 1;
  if (steps < 1 || derivatives.cols() != steps || stages < 1) {
    throw std::invalid_argument(fmt::format(
        "CollocationMonitor: {} times, {} derivative columns, {} stages: need N + 1 ≥ 2 times, "
        "N columns and stages ≥ 1",
        times.size(), derivatives.cols(), stages));
  }
  Vector density = Vector::Zero(steps);
  if (steps == 1) return density;
  // |u^(s+1)|^(1/(s+1)) at the boundary between steps k and k + 1 from the jump of u^(s) across
  // it over the distance between the steps' midpoints; each step takes the mean of its two.
  const double power = 1.0 / (stages + 1.0);
  Vector at_boundary(steps - 1);
  for (Index k = 0; k + 1 < steps; ++k) {
    const double distance = 0.5 * (times(k + 2) - times(k));
    at_boundary(k) = std::pow(
        (derivatives.col(k + 1) - derivatives.col(k)).cwiseAbs().maxCoeff() / distance, power);
  }
  for (Index k = 0; k < steps; ++k) {
    const double left = k > 0 ? at_boundary(k - 1) : at_boundary(k);
    const double right = k + 1 < steps ? at_boundary(k) : at_boundary(k - 1);
    density(k) = 0.5 * (left + right);
  }
  return density;
}

std::vector<double> EquidistributedMesh(const Vector& times, const Vector& density, double a,
                                        double b, long steps) {
  const Index old_steps = times.size() - 1;
  if (steps < 1 || old_steps < 1 || density.size() != old_steps || !(a < b) || a < times(0) ||
      b > times(old_steps)) {
    throw std::invalid_argument(fmt::format(
        "EquidistributedMesh: {} steps on [{}, {}] from {} times and {} densities: need steps ≥ 1, "
        "a < b within [{}, {}] and one density per old step",
        steps, a, b, times.size(), density.size(), times(0), times(old_steps)));
  }
  // The cumulative integral I(t) of the density from a, piecewise linear on the old mesh cut to
  // [a, b]; the new points are where I reaches k/N of I(b).
  std::vector<double> knots{a}, integral{0.0};
  for (Index k = 0; k < old_steps; ++k) {
    const double lo = std::max(times(k), a), hi = std::min(times(k + 1), b);
    if (!(hi > lo)) continue;
    if (!(density(k) > 0.0) || !std::isfinite(density(k))) {
      throw std::invalid_argument(fmt::format(
          "EquidistributedMesh: density({}) = {}: must be positive and finite", k, density(k)));
    }
    knots.push_back(hi);
    integral.push_back(integral.back() + density(k) * (hi - lo));
  }
  std::vector<double> fractions(static_cast<std::size_t>(steps) + 1);
  fractions.front() = 0.0;
  fractions.back() = 1.0;
  std::size_t piece = 1;
  for (long j = 1; j < steps; ++j) {
    const double target = integral.back() * static_cast<double>(j) / static_cast<double>(steps);
    while (piece + 1 < knots.size() && integral[piece] < target) ++piece;
    const double weight = (target - integral[piece - 1]) / (integral[piece] - integral[piece - 1]);
    const double t = knots[piece - 1] + weight * (knots[piece] - knots[piece - 1]);
    fractions[static_cast<std::size_t>(j)] = (t - a) / (b - a);
  }
  return fractions;
}

IntegrationResult OdeIntegrator::Sample(double t0, ConstVectorRef x0, const Vector& times,
                                        Matrix& states) {
  const Index n = impl_->n();
  CheckSize("x0", x0.size(), n);
  CheckTime("t0", t0);
  if (times.size() < 1) {
    throw std::invalid_argument("OdeIntegrator::Sample: times is empty");
  }
  CheckOutputTimes("Sample", t0, times(times.size() - 1) >= t0 ? 1.0 : -1.0, times);
  states.resize(n, times.size());
  Vector& x_final = impl_->x_final_buffer();
  x_final.resize(n);
  Vector& x0_copy = impl_->x0_buffer();
  x0_copy = x0;
  detail::IntegrationRequest request;
  request.t0 = t0;
  request.x0 = x0_copy.data();
  request.times = times.data();
  request.count = times.size();
  request.states = states.data();
  request.x_final = x_final.data();
  request.parameter_scale = ParameterScale(impl_->options(), impl_->system().Parameter());
  return impl_->Run(request);
}

}  // namespace rubcont
