#include "continuation/event_curve.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "solvers/constants.h"
#include "solvers/finite_difference.h"

namespace rubcont {

namespace {

// Other margins within this of zero at the start vanish with m_k (simultaneous events): the inner
// problems' margins are scaled, and their location error is ~1e-10.
constexpr double kPartnerTolerance = 1e-7;

}  // namespace

EventCurveProblem::EventCurveProblem(Problem& inner, int event, const Vector& u, double lambda)
    : inner_(inner), event_(event), n_(inner.Dimension()) {
  if (!inner_.HasSecondParameter()) {
    throw std::invalid_argument(
        "EventCurveProblem: the inner problem has no second parameter (HasSecondParameter() is "
        "false)");
  }
  const std::vector<std::string> names = inner_.EventNames();
  if (event < 0 || event >= static_cast<int>(names.size())) {
    throw std::invalid_argument(fmt::format(
        "EventCurveProblem: event = {}: must index one of the inner problem's {} events", event,
        names.size()));
  }
  if (u.size() != n_) {
    throw std::invalid_argument(fmt::format(
        "EventCurveProblem: u has {} entries; the inner problem's Dimension() = {}", u.size(), n_));
  }
  event_name_ = names[event];
  s_ = inner_.Scale();
  s_lambda_ = inner_.LambdaScale();
  r_ = inner_.ResidualScale();
  const Vector margins = inner_.EventFunctions(u, lambda);
  for (int j = 0; j < margins.size(); ++j) {
    if (j == event) continue;
    if (std::abs(margins(j)) <= kPartnerTolerance) {
      partner_names_.push_back(names[j]);
    } else if (margins(j) > 0.0) {
      monitored_.push_back(j);
      monitored_names_.push_back(names[j]);
    }
  }
}

bool EventCurveProblem::SetEta(double eta) {
  if (inner_.SecondParameter() == eta) return true;
  try {
    inner_.SetSecondParameter(eta);
    return true;
  } catch (const std::invalid_argument&) {
    return false;  // outside the inner problem's range: the caller returns NaN
  }
}

double EventCurveProblem::Margin(const Vector& U, double eta) {
  if (!SetEta(eta)) return kNaN;
  return inner_.EventFunctions(U.head(n_), U(n_))(event_);
}

void EventCurveProblem::Residual(const Vector& U, double eta, Vector& G) {
  if (!SetEta(eta)) {
    G = Vector::Constant(n_ + 1, kNaN);
    return;
  }
  Vector F;
  inner_.Residual(U.head(n_), U(n_), F);
  G.resize(n_ + 1);
  G.head(n_) = F;
  G(n_) = inner_.EventFunctions(U.head(n_), U(n_))(event_);
}

void EventCurveProblem::Jacobian(const Vector& U, double eta, Matrix& DG) {
  if (!SetEta(eta)) {
    DG = Matrix::Constant(n_ + 1, n_ + 1, kNaN);
    return;
  }
  const Vector u = U.head(n_);
  const double lambda = U(n_);
  Matrix J;
  Vector dF;
  inner_.Jacobian(u, lambda, J);
  inner_.DfDlambda(u, lambda, dF);
  DG.setZero(n_ + 1, n_ + 1);
  DG.topLeftCorner(n_, n_) = J;
  DG.topRightCorner(n_, 1) = dF;
  // ∇m_k, component by component, with steps relative to the scaled point.
  const Vector scale = Scale();
  Vector V = U;
  for (Index i = 0; i <= n_; ++i) {
    const double h = CentralDifferenceStep(U(i) / scale(i), 1.0) * scale(i);
    V(i) = U(i) + h;
    const double plus = Margin(V, eta);
    V(i) = U(i) - h;
    const double minus = Margin(V, eta);
    V(i) = U(i);
    DG(n_, i) = (plus - minus) / (2.0 * h);
  }
}

void EventCurveProblem::DfDlambda(const Vector& U, double eta, Vector& dG) {
  dG = Vector::Constant(n_ + 1, kNaN);
  if (!SetEta(eta)) return;
  Vector dF;
  try {
    inner_.DfDeta(U.head(n_), U(n_), dF);  // differences in η may step out of range
  } catch (const std::invalid_argument&) {
    SetEta(eta);
    return;
  }
  const double h = CentralDifferenceStep(eta, inner_.SecondParameterScale());
  const double plus = Margin(U, eta + h);
  const double minus = Margin(U, eta - h);
  SetEta(eta);
  dG.resize(n_ + 1);
  dG.head(n_) = dF;
  dG(n_) = (plus - minus) / (2.0 * h);
}

Vector EventCurveProblem::Scale() const { return Joined(s_, s_lambda_); }

Vector EventCurveProblem::ResidualScale() const { return Joined(r_, 1.0); }

std::vector<std::string> EventCurveProblem::MeasureNames() const {
  std::vector<std::string> names{"lambda"};
  for (const std::string& name : inner_.MeasureNames()) names.push_back(name);
  return names;
}

Vector EventCurveProblem::Measures(const Vector& U, double eta) {
  if (!SetEta(eta)) {
    return Vector::Constant(static_cast<Index>(MeasureNames().size()), kNaN);
  }
  const Vector inner = inner_.Measures(U.head(n_), U(n_));
  Vector m(inner.size() + 1);
  m(0) = U(n_);
  m.tail(inner.size()) = inner;
  return m;
}

std::vector<std::string> EventCurveProblem::EventNames() const { return monitored_names_; }

Vector EventCurveProblem::EventFunctions(const Vector& U, double eta) {
  if (!SetEta(eta)) {
    return Vector::Constant(static_cast<Index>(monitored_.size()), kNaN);
  }
  const Vector all = inner_.EventFunctions(U.head(n_), U(n_));
  Vector g(monitored_.size());
  for (std::size_t j = 0; j < monitored_.size(); ++j) g(j) = all(monitored_[j]);
  return g;
}

void EventCurveProblem::PointAccepted(const Vector& U, double eta) {
  if (!SetEta(eta)) return;
  inner_.PointAccepted(U.head(n_), U(n_));
}

Branch ContinueEventCurve(Problem& problem, const SpecialPoint& event_point,
                          const ContinuationOptions& options) {
  if (!problem.HasSecondParameter()) {
    throw std::invalid_argument(
        "ContinueEventCurve: the problem has no second parameter (HasSecondParameter() is false)");
  }
  if (event_point.type != SpecialPointType::kEvent) {
    throw std::invalid_argument(fmt::format(
        "ContinueEventCurve: the special point is a {}, not an event", ToString(event_point.type)));
  }
  const std::vector<std::string> names = problem.EventNames();
  const auto it = std::find(names.begin(), names.end(), event_point.label);
  if (it == names.end()) {
    throw std::invalid_argument(fmt::format(
        "ContinueEventCurve: event \"{}\" is not an event of the problem's current piece ({})",
        event_point.label, problem.PieceLabel()));
  }
  const SecondParameterGuard restore(problem);  // the curve problem moves η
  const int event = static_cast<int>(it - names.begin());
  const Vector U0 = Joined(event_point.u, event_point.lambda);
  ContinuationOptions run = options;
  run.direction = -1;
  Branch backward;
  {
    EventCurveProblem curve(problem, event, event_point.u, event_point.lambda);
    backward = Continue(curve, U0, restore.eta(), run);
  }
  problem.SetSecondParameter(restore.eta());
  problem.PointAccepted(event_point.u, event_point.lambda);
  run.direction = +1;
  Branch forward;
  {
    EventCurveProblem curve(problem, event, event_point.u, event_point.lambda);
    forward = Continue(curve, U0, restore.eta(), run);
  }
  if (backward.points.empty()) return forward;
  if (forward.points.empty()) return backward;
  return JoinAtStart(backward, forward);
}

}  // namespace rubcont
