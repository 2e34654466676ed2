#include "shooting/shooting.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>
#include <fmt/core.h>

#include "solvers/constants.h"
#include "solvers/finite_difference.h"

namespace rubcont {

const char* ToString(OrbitKind kind) {
  switch (kind) {
    case OrbitKind::kAutonomous: return "autonomous periodic orbit";
    case OrbitKind::kForced: return "forced periodic orbit";
    case OrbitKind::kRelative: return "relative periodic orbit";
  }
  return "unknown";
}

long CollocationStepsPerSegment(long intervals_per_period, int segments) {
  return (intervals_per_period + segments - 1) / segments;
}

IntegratorOptions JoinedIntegrator(IntegratorOptions span, long pieces) {
  span.collocation_steps *= pieces;
  return span;
}

void Validate(const ShootingOptions& options) {
  if (options.segments < 1) {
    throw std::invalid_argument(
        fmt::format("ShootingOptions.segments = {}: must be at least 1", options.segments));
  }
  if (!options.mesh.empty()) {
    const std::size_t expected = static_cast<std::size_t>(options.segments) + 1;
    if (options.mesh.size() != expected) {
      throw std::invalid_argument(
          fmt::format("ShootingOptions.mesh has {} entries: must be empty or segments + 1 = {}",
                      options.mesh.size(), expected));
    }
    if (options.mesh.front() != 0.0 || options.mesh.back() != 1.0) {
      throw std::invalid_argument(fmt::format(
          "ShootingOptions.mesh runs from {} to {}: must run from 0 to 1", options.mesh.front(),
          options.mesh.back()));
    }
    for (std::size_t i = 1; i < options.mesh.size(); ++i) {
      if (!(options.mesh[i] > options.mesh[i - 1])) {
        throw std::invalid_argument(fmt::format(
            "ShootingOptions.mesh[{}] = {} ≤ mesh[{}] = {}: must increase strictly", i,
            options.mesh[i], i - 1, options.mesh[i - 1]));
      }
    }
  }
  if (options.adapt_mesh_every < 0 ||
      (options.adapt_mesh_every > 0 &&
       options.integrator.method != IntegrationMethod::kGaussCollocation)) {
    throw std::invalid_argument(fmt::format(
        "ShootingOptions.adapt_mesh_every = {}: must be ≥ 0, and 0 unless the integrator is Gauss "
        "collocation (it is {})",
        options.adapt_mesh_every, ToString(options.integrator.method)));
  }
  if (!(options.adapt_mesh_floor > 0.0) || !std::isfinite(options.adapt_mesh_floor)) {
    throw std::invalid_argument(fmt::format(
        "ShootingOptions.adapt_mesh_floor = {}: must be positive and finite",
        options.adapt_mesh_floor));
  }
  for (std::size_t j = 0; j < options.event_boundaries.size(); ++j) {
    const ShootingOptions::EventBoundary& event = options.event_boundaries[j];
    if (event.boundary < 1 || event.boundary >= options.segments) {
      throw std::invalid_argument(fmt::format(
          "ShootingOptions.event_boundaries[{}].boundary = {}: must lie in [1, segments − 1 = {}]",
          j, event.boundary, options.segments - 1));
    }
    if (event.surface < 0) {
      throw std::invalid_argument(fmt::format(
          "ShootingOptions.event_boundaries[{}].surface = {}: must be non-negative", j,
          event.surface));
    }
    for (std::size_t i = 0; i < j; ++i) {
      if (options.event_boundaries[i].boundary == event.boundary) {
        throw std::invalid_argument(fmt::format(
            "ShootingOptions.event_boundaries[{}].boundary = {}: already event_boundaries[{}]'s",
            j, event.boundary, i));
      }
    }
  }
  Validate(options.integrator);
  if (!(options.period_scale >= 0.0) || std::isinf(options.period_scale)) {
    throw std::invalid_argument(fmt::format(
        "ShootingOptions.period_scale = {}: must be finite and non-negative (0: automatic)",
        options.period_scale));
  }
  if (!(options.lambda_scale >= 0.0) || std::isinf(options.lambda_scale)) {
    throw std::invalid_argument(fmt::format(
        "ShootingOptions.lambda_scale = {}: must be finite and non-negative (0: automatic)",
        options.lambda_scale));
  }
  if (options.samples_per_segment < 2) {
    throw std::invalid_argument(fmt::format(
        "ShootingOptions.samples_per_segment = {}: must be at least 2",
        options.samples_per_segment));
  }
}

// ---------------------------------------------------------------------------------------------
// Measures

namespace {

// Value at the extremum of the parabola through samples k−1, k, k+1 of `values` (one per sample
// of `orbit`), when the extremum lies between them (sign = +1: maximum, −1: minimum); otherwise
// the sample itself. When `closed` (x(T) = x(0), or the values are invariant under the rotation
// of a relative orbit) the neighbours wrap around the period.
double RefinedExtremum(const OrbitSamples& orbit, const Eigen::Ref<const Vector>& values,
                       double sign, bool closed) {
  const Index m = values.size();
  Index k = 0;
  (sign * values.array()).maxCoeff(&k);
  const double b = values(k);
  closed = closed && m >= 3;
  Index left = k - 1, right = k + 1;
  double t_left = 0.0, t_right = 0.0;
  if (k == 0 || k == m - 1) {
    if (!closed) return b;
    // Samples 0 and m−1 are the same point of a closed orbit, at t = 0 and t = T.
    left = m - 2;
    right = 1;
    t_left = orbit.times(m - 2) - orbit.period;
    t_right = orbit.times(1);
    if (k == m - 1) {
      t_left = orbit.times(m - 2) - orbit.times(m - 1);
      t_right = orbit.times(1) + orbit.period - orbit.times(m - 1);
    }
  } else {
    t_left = orbit.times(left) - orbit.times(k);
    t_right = orbit.times(right) - orbit.times(k);
  }
  const double a = values(left), c = values(right);
  // p(t) = b + B t + A t² through (t_left, a), (0, b), (t_right, c).
  const double slope_left = (a - b) / t_left, slope_right = (c - b) / t_right;
  const double A = (slope_left - slope_right) / (t_left - t_right);
  const double B = slope_left - A * t_left;
  if (!(sign * A < 0.0)) return b;
  const double t_star = -B / (2.0 * A);
  if (t_star < t_left || t_star > t_right) return b;
  return b - B * B / (4.0 * A);
}

double RefinedExtremum(const OrbitSamples& orbit, Index state, double sign) {
  return RefinedExtremum(orbit, orbit.states.row(state).transpose(), sign,
                         orbit.rotation == 0.0);
}

}  // namespace

OrbitMeasure StateMaximum(Index state, std::string name) {
  return {std::move(name),
          [state](const OrbitSamples& orbit) { return RefinedExtremum(orbit, state, +1.0); }};
}

OrbitMeasure StateMinimum(Index state, std::string name) {
  return {std::move(name),
          [state](const OrbitSamples& orbit) { return RefinedExtremum(orbit, state, -1.0); }};
}

OrbitTestFunction Grazing(std::function<double(ConstVectorRef)> surface, GrazingSide side,
                          std::string name) {
  const double sign = side == GrazingSide::kTouchdown ? +1.0 : -1.0;
  OrbitMeasure measure{std::move(name), [surface = std::move(surface), sign](
                                            const OrbitSamples& orbit) {
                         Vector h(orbit.states.cols());
                         for (Index j = 0; j < h.size(); ++j) h(j) = surface(orbit.states.col(j));
                         return RefinedExtremum(orbit, h, sign, true);
                       }};
  return {std::move(measure), SpecialPointType::kGrazing};
}

OrbitMeasure StateAmplitude(Index state, std::string name) {
  return {std::move(name), [state](const OrbitSamples& orbit) {
            return 0.5 * (RefinedExtremum(orbit, state, +1.0) -
                          RefinedExtremum(orbit, state, -1.0));
          }};
}

OrbitMeasure StateMean(Index state, std::string name) {
  return {std::move(name), [state](const OrbitSamples& orbit) {
            const Index m = orbit.times.size();
            double integral = 0.0;
            for (Index k = 1; k < m; ++k) {
              integral += 0.5 * (orbit.times(k) - orbit.times(k - 1)) *
                          (orbit.states(state, k) + orbit.states(state, k - 1));
            }
            return integral / (orbit.times(m - 1) - orbit.times(0));
          }};
}

OrbitMeasure MeanRadius(std::string name) {
  return {std::move(name), [](const OrbitSamples& orbit) {
            const Index m = orbit.times.size();
            double integral = 0.0;
            for (Index j = 0; j + 1 < m; ++j) {
              const double r0 = orbit.states.col(j).head(2).norm();
              const double r1 = orbit.states.col(j + 1).head(2).norm();
              integral += 0.5 * (r0 + r1) * (orbit.times(j + 1) - orbit.times(j));
            }
            return integral / (orbit.times(m - 1) - orbit.times(0));
          }};
}

OrbitMeasure PeriodicityDefect(std::shared_ptr<OdeSystem> system, const IntegratorOptions& options,
                               std::string name) {
  auto integrator = std::make_shared<OdeIntegrator>(*system, options);
  return {std::move(name), [system, integrator](const OrbitSamples& orbit) {
            if (!orbit.valid) return kNaN;
            system->SetParameter(orbit.parameter);
            const Vector x0 = orbit.states.col(0);
            Vector end(x0.size());
            if (!integrator->Integrate(orbit.times(0), x0, orbit.times(0) + orbit.period, end)
                     .Succeeded()) {
              return kNaN;
            }
            Vector start = x0;
            if (orbit.rotation != 0.0) system->Rotate(orbit.rotation, start);
            return (end - start).cwiseQuotient(system->StateScale()).cwiseAbs().maxCoeff();
          }};
}

OrbitMeasure MirrorAsymmetry(std::shared_ptr<const OdeSystem> system, std::string name) {
  if (!system->HasMirrorSymmetry()) {
    throw std::invalid_argument("MirrorAsymmetry: the system has no mirror symmetry");
  }
  return {std::move(name), [system](const OrbitSamples& orbit) {
            return orbit.valid ? MirrorAsymmetryOf(*system, orbit.states) : kNaN;
          }};
}

double MirrorAsymmetryOf(const OdeSystem& system, const Eigen::Ref<const Matrix>& states) {
  const Vector inverse_scale = system.StateScale().cwiseInverse();
  double difference = 0.0, size = 0.0;
  Vector mirrored;
  for (Index j = 0; j < states.cols(); ++j) {
    mirrored = states.col(j);
    system.Mirror(mirrored);
    difference = std::max(difference, (mirrored - states.col(j))
                                          .cwiseProduct(inverse_scale)
                                          .lpNorm<Eigen::Infinity>());
    size = std::max(size, states.col(j).cwiseProduct(inverse_scale).lpNorm<Eigen::Infinity>());
  }
  return size > 0.0 ? difference / size : 0.0;
}

OrbitMeasure UnresolvedMultiplier(std::shared_ptr<OdeSystem> system, int stages,
                                  long steps_per_period, std::string name) {
  // Absolute below 1, relative above: a growing frozen mode (Re λ > 0, A(a)'s doubled whip at its
  // first sample: e^{Re λ T} up to 2e14) that the mesh resolves differs from e^{Re λ T} only by
  // the round-off of the power, which exceeds any absolute bound.
  constexpr double kMisplaced = 1e-3;
  return {std::move(name), [system, stages, steps_per_period](const OrbitSamples& orbit) {
            if (!orbit.valid) return kNaN;
            system->SetParameter(orbit.parameter);
            const Index n = system->Dimension();
            Matrix J(n, n);
            system->JacobianX(orbit.times(0), orbit.states.col(0), J);
            const auto N = static_cast<double>(steps_per_period);
            const double h = orbit.period / N;
            const Vector steps = orbit.period * orbit.collocation_steps;
            double largest = 0.0;
            for (const std::complex<double>& lambda : J.eigenvalues()) {
              const double discrete =
                  steps.size() > 0
                      ? std::exp(GaussLogGrowth(stages, lambda, steps))
                      : std::pow(std::abs(GaussStabilityFunction(stages, lambda * h)), N);
              const double exact = std::exp(lambda.real() * orbit.period);
              if (std::abs(discrete - exact) > kMisplaced * std::max(1.0, exact)) {
                largest = std::max(largest, discrete);
              }
            }
            return largest;
          }};
}

// ---------------------------------------------------------------------------------------------
// Construction

namespace {

const ShootingOptions& Validated(const ShootingOptions& options) {
  Validate(options);
  return options;
}

}  // namespace

ShootingProblem::ShootingProblem(OdeSystem& system, OrbitKind kind, const ShootingOptions& options)
    : system_(system),
      kind_(kind),
      options_(Validated(options)),
      integrator_(system, options.integrator),
      n_(system.Dimension()),
      segments_(options.segments) {
  if (kind == OrbitKind::kForced) {
    const double T = system.ForcingPeriod();
    if (!(T > 0.0) || !std::isfinite(T)) {
      throw std::invalid_argument(fmt::format(
          "ShootingProblem: kind kForced needs OdeSystem::ForcingPeriod() > 0, got {}", T));
    }
    period_scale_ = options.period_scale > 0.0 ? options.period_scale : T;
  } else {
    if (system.ForcingPeriod() != 0.0) {
      throw std::invalid_argument(fmt::format(
          "ShootingProblem: kind {} needs an autonomous system, but ForcingPeriod() = {}",
          ToString(kind), system.ForcingPeriod()));
    }
    period_scale_ = options.period_scale;  // 0 until the first phase reference
  }
  if (kind == OrbitKind::kRelative && !system.HasRotationSymmetry()) {
    throw std::invalid_argument(
        "ShootingProblem: kind kRelative needs a system with HasRotationSymmetry()");
  }
  if (!options.event_boundaries.empty() && kind == OrbitKind::kForced) {
    throw std::invalid_argument(
        "ShootingProblem: event_boundaries need kind kAutonomous or kRelative, not kForced");
  }
  for (const ShootingOptions::EventBoundary& event : options.event_boundaries) {
    if (event.surface >= system.SwitchingCount()) {
      throw std::invalid_argument(fmt::format(
          "ShootingProblem: event boundary {} is on surface {}, but the system has {} switching "
          "functions",
          event.boundary, event.surface, system.SwitchingCount()));
    }
  }
  h_work_.resize(system.SwitchingCount());
  event_scale_ = Vector::Ones(static_cast<Index>(options.event_boundaries.size()));
  mesh_ = options.mesh;
  if (mesh_.empty()) {
    for (Index i = 0; i <= segments_; ++i) {
      mesh_.push_back(static_cast<double>(i) / static_cast<double>(segments_));
    }
    mesh_.back() = 1.0;
  }
  base_mesh_ = mesh_;
  // Event boundaries, and the anchors that place the others (nearest event boundary or end on
  // each side, and the fraction of the way between them on the base mesh).
  event_at_.assign(segments_ + 1, -1);
  for (std::size_t j = 0; j < options.event_boundaries.size(); ++j) {
    event_at_[options.event_boundaries[j].boundary] = static_cast<int>(j);
  }
  anchor_left_.assign(segments_ + 1, 0);
  anchor_right_.assign(segments_ + 1, segments_);
  anchor_alpha_.assign(segments_ + 1, 0.0);
  for (Index i = 1; i < segments_; ++i) {
    Index left = i - 1, right = i + 1;
    while (left > 0 && event_at_[left] < 0) --left;
    while (right < segments_ && event_at_[right] < 0) ++right;
    anchor_left_[i] = left;
    anchor_right_[i] = right;
    anchor_alpha_[i] = (base_mesh_[i] - base_mesh_[left]) / (base_mesh_[right] - base_mesh_[left]);
  }
  state_scale_ = system.StateScale();
  lambda_scale_ = options.lambda_scale > 0.0 ? options.lambda_scale
                                             : std::max(std::abs(system.Parameter()), 1.0);
  for (Index i = 0; i < n_; ++i) {
    measures_.push_back(StateMaximum(i, "max_" + system.StateName(i)));
    measures_.push_back(StateMinimum(i, "min_" + system.StateName(i)));
  }
  f_work_.resize(n_);
  g_work_.resize(n_);
  x_work_.resize(n_);
  if (!options.integrator.sensitivity_error_control && options.accurate_stability) {
    IntegratorOptions accurate = options.integrator;
    accurate.sensitivity_error_control = true;
    stability_integrator_ = std::make_unique<OdeIntegrator>(system, accurate);
  }
  if (options.restart_at_switches && system.SwitchingCount() > 0 &&
      options.integrator.method != IntegrationMethod::kGaussCollocation) {
    EventOptions events;
    events.count = system.SwitchingCount();
    events.restart = true;
    events.function = [&system](double t, ConstVectorRef x, VectorRef h) {
      system.SwitchingFunctions(t, x, h);
    };
    integrator_.SetEvents(events);
    if (stability_integrator_) stability_integrator_->SetEvents(events);
  }
  for (SegmentData* data : {&cache_, &scratch_, &stability_}) {
    data->ends.assign(segments_, Vector::Zero(n_));
    data->stm.assign(segments_, Matrix::Zero(n_, n_));
    data->dxdp.assign(segments_, Vector::Zero(n_));
    if (options.adapt_mesh_every > 0) data->derivatives.assign(segments_, Matrix());
    data->dxdt1.assign(segments_, Vector::Zero(n_));
  }
}

Index ShootingProblem::EventOffset() const {
  const Index extra = kind_ == OrbitKind::kForced ? 0 : (kind_ == OrbitKind::kAutonomous ? 1 : 2);
  return segments_ * n_ + extra;
}

Index ShootingProblem::Dimension() const {
  return EventOffset() + static_cast<Index>(options_.event_boundaries.size());
}

std::vector<double> ShootingProblem::Mesh(const Vector& u) const {
  CheckUnknowns(u, "Mesh");
  std::vector<double> mesh = base_mesh_;
  for (std::size_t j = 0; j < options_.event_boundaries.size(); ++j) {
    mesh[options_.event_boundaries[j].boundary] = u(EventOffset() + static_cast<Index>(j));
  }
  // The other boundaries keep their places between their anchors.
  for (Index i = 1; i < segments_; ++i) {
    if (event_at_[i] >= 0 || options_.event_boundaries.empty()) continue;
    const double left = mesh[anchor_left_[i]], right = mesh[anchor_right_[i]];
    mesh[i] = left + anchor_alpha_[i] * (right - left);
  }
  return mesh;
}

double ShootingProblem::MeshWeight(Index boundary, int event) const {
  if (event_at_[boundary] >= 0) return event_at_[boundary] == event ? 1.0 : 0.0;
  if (boundary == 0 || boundary == segments_) return 0.0;
  double weight = 0.0;
  if (event_at_[anchor_left_[boundary]] == event) weight += 1.0 - anchor_alpha_[boundary];
  if (event_at_[anchor_right_[boundary]] == event) weight += anchor_alpha_[boundary];
  return weight;
}

bool ShootingProblem::UseMesh(const Vector& u) {
  if (options_.event_boundaries.empty()) return true;
  mesh_ = Mesh(u);
  for (Index i = 0; i < segments_; ++i) {
    if (InPhase(i)) continue;  // may shrink past 0: see EventNames
    if (!(mesh_[i + 1] > mesh_[i])) {
      last_failure_ = IntegrationResult();
      last_failure_.status = IntegrationStatus::kOther;
      last_failure_.message = fmt::format(
          "the segment boundaries {} = {} and {} = {} are out of order (an event boundary moved "
          "past the start of the period)",
          i, mesh_[i], i + 1, mesh_[i + 1]);
      return false;
    }
  }
  return true;
}

bool ShootingProblem::InPhase(Index segment) const {
  const Index right = event_at_[segment + 1] >= 0 ? segment + 1 : anchor_right_[segment + 1];
  const Index left = event_at_[segment] >= 0 ? segment : anchor_left_[segment];
  return event_at_[left] >= 0 && event_at_[right] >= 0;
}

std::vector<std::pair<Index, Index>> ShootingProblem::Phases() const {
  std::vector<std::pair<Index, Index>> phases;
  Index previous = -1;
  for (Index i = 1; i < segments_; ++i) {
    if (event_at_[i] < 0) continue;
    if (previous >= 0) phases.emplace_back(previous, i);
    previous = i;
  }
  return phases;
}

std::vector<std::string> ShootingProblem::EventNames() const {
  std::vector<std::string> names;
  for (const auto& [from, to] : Phases()) names.push_back(fmt::format("switches_{}_{}", from, to));
  return names;
}

Vector ShootingProblem::EventFunctions(const Vector& u, double /*lambda*/) {
  CheckUnknowns(u, "EventFunctions");
  const std::vector<double> mesh = Mesh(u);
  const std::vector<std::pair<Index, Index>> phases = Phases();
  Vector margins(static_cast<Index>(phases.size()));
  for (std::size_t k = 0; k < phases.size(); ++k) {
    margins(static_cast<Index>(k)) = mesh[phases[k].second] - mesh[phases[k].first];
  }
  return margins;
}

Vector ShootingProblem::SwitchingGradient(int surface, ConstVectorRef x) {
  Vector gradient(n_);
  x_work_ = x;
  for (Index k = 0; k < n_; ++k) {
    const double h = CentralDifferenceStep(x(k), state_scale_(k));
    x_work_(k) = x(k) + h;
    system_.SwitchingFunctions(0.0, x_work_, h_work_);
    const double plus = h_work_(surface);
    x_work_(k) = x(k) - h;
    system_.SwitchingFunctions(0.0, x_work_, h_work_);
    gradient(k) = (plus - h_work_(surface)) / (2.0 * h);
    x_work_(k) = x(k);
  }
  return gradient;
}

void ShootingProblem::CheckUnknowns(const Vector& u, const char* where) const {
  if (u.size() != Dimension()) {
    throw std::invalid_argument(fmt::format(
        "ShootingProblem::{}: u has {} entries; this problem ({}, {} segments of {} states) has {}",
        where, u.size(), ToString(kind_), segments_, n_, Dimension()));
  }
}

Vector ShootingProblem::Pack(const Matrix& starts, double period, double rotation) const {
  if (starts.rows() != n_ || starts.cols() != segments_) {
    throw std::invalid_argument(fmt::format(
        "ShootingProblem::Pack: starts is {}×{}, must be {}×{} (states × segments)", starts.rows(),
        starts.cols(), n_, segments_));
  }
  Vector u(Dimension());
  for (Index i = 0; i < segments_; ++i) u.segment(i * n_, n_) = starts.col(i);
  if (kind_ != OrbitKind::kForced) u(segments_ * n_) = period;
  if (kind_ == OrbitKind::kRelative) u(segments_ * n_ + 1) = rotation;
  for (std::size_t j = 0; j < options_.event_boundaries.size(); ++j) {
    u(EventOffset() + static_cast<Index>(j)) = base_mesh_[options_.event_boundaries[j].boundary];
  }
  return u;
}

Eigen::VectorBlock<const Vector> ShootingProblem::SegmentStart(const Vector& u,
                                                               Index segment) const {
  CheckUnknowns(u, "SegmentStart");
  if (segment < 0 || segment >= segments_) {
    throw std::invalid_argument(fmt::format(
        "ShootingProblem::SegmentStart: segment {} outside [0, {})", segment, segments_));
  }
  return u.segment(segment * n_, n_);
}

double ShootingProblem::Period(const Vector& u, double lambda) {
  CheckUnknowns(u, "Period");
  return kind_ == OrbitKind::kForced ? ForcingPeriodAt(lambda) : u(segments_ * n_);
}

double ShootingProblem::Rotation(const Vector& u) const {
  CheckUnknowns(u, "Rotation");
  return kind_ == OrbitKind::kRelative ? u(segments_ * n_ + 1) : 0.0;
}

double ShootingProblem::ForcingPeriodAt(double lambda) {
  system_.SetParameter(lambda);
  return system_.ForcingPeriod();
}

double ShootingProblem::ForcingPeriodDerivative(double lambda) {
  const double h = CentralDifferenceStep(lambda, lambda_scale_);
  const double plus = ForcingPeriodAt(lambda + h);
  const double minus = ForcingPeriodAt(lambda - h);
  system_.SetParameter(lambda);
  return (plus - minus) / (2.0 * h);
}

void ShootingProblem::RotationMatrix(double phi, Matrix& R) const {
  R.setIdentity(n_, n_);
  for (Index j = 0; j < n_; ++j) system_.Rotate(phi, R.col(j));
}

void ShootingProblem::SetPhaseReference(const Vector& u, double lambda) {
  CheckUnknowns(u, "SetPhaseReference");
  if (kind_ == OrbitKind::kForced) return;  // no phase condition
  const Vector x_ref = u.head(n_);
  system_.SetParameter(lambda);
  system_.Rhs(0.0, x_ref, f_work_);
  const Vector scaled_f = f_work_.cwiseQuotient(state_scale_);
  if (!(scaled_f.norm() > 0.0) || !scaled_f.allFinite()) {
    throw std::invalid_argument(fmt::format(
        "ShootingProblem::SetPhaseReference: f(x_ref) has norm {}: the reference must be a "
        "regular point of an orbit, not an equilibrium",
        scaled_f.norm()));
  }
  reference_ = x_ref;
  time_normal_ = (scaled_f / scaled_f.norm()).cwiseQuotient(state_scale_);
  if (kind_ == OrbitKind::kRelative) {
    system_.RotationGenerator(x_ref, g_work_);
    const Vector scaled_g = g_work_.cwiseQuotient(state_scale_);
    if (!(scaled_g.norm() > 0.0) || !scaled_g.allFinite()) {
      throw std::invalid_argument(fmt::format(
          "ShootingProblem::SetPhaseReference: the rotation generator at x_ref has norm {}: the "
          "reference must not be fixed by the rotation",
          scaled_g.norm()));
    }
    rotation_normal_ = (scaled_g / scaled_g.norm()).cwiseQuotient(state_scale_);
  }
  if (!has_reference_) {
    // h measured per unit of scaled state: |∇h_k| S at the boundary's start.
    for (std::size_t j = 0; j < options_.event_boundaries.size(); ++j) {
      const ShootingOptions::EventBoundary& event = options_.event_boundaries[j];
      const double size = SwitchingGradient(event.surface, u.segment(event.boundary * n_, n_))
                              .cwiseProduct(state_scale_)
                              .norm();
      event_scale_(static_cast<Index>(j)) = size > 0.0 && std::isfinite(size) ? size : 1.0;
    }
  }
  has_reference_ = true;
  if (period_scale_ == 0.0) {
    const double T = std::abs(u(segments_ * n_));
    period_scale_ = T > 0.0 && std::isfinite(T) ? T : 1.0;
  }
  // The phase rows changed: a cached residual is stale (the integrations are not).
  residual_ready_ = false;
}

void ShootingProblem::PointAccepted(const Vector& u, double lambda) {
  if (options_.refresh_phase_reference && kind_ != OrbitKind::kForced) SetPhaseReference(u, lambda);
  ++accepted_points_;
  if (options_.adapt_mesh_every > 0 && accepted_points_ % options_.adapt_mesh_every == 0) {
    AdaptCollocationMeshes(u, lambda);
  }
}

void ShootingProblem::UseCollocationMesh(OdeIntegrator& integrator, Index segment) {
  if (!collocation_meshes_.empty()) {
    integrator.SetCollocationMesh(collocation_meshes_[static_cast<std::size_t>(segment)]);
  }
}

void ShootingProblem::AdaptCollocationMeshes(const Vector& u, double lambda) {
  const bool cached = SameKey(u, lambda);
  if (!cached && !IntegrateSegments(u, lambda, Need::kState, scratch_, integrator_)) return;
  const SegmentData& data = cached ? cache_ : scratch_;
  // The whole period's mesh and u^(s) in scaled units, segment after segment.
  const double T = Period(u, lambda);
  const Vector times = CollocationTimes(T);
  const Index total = times.size() - 1;
  Matrix derivatives(n_, total);
  Index at = 0;
  for (const Matrix& d : data.derivatives) {
    derivatives.middleCols(at, d.cols()) = state_scale_.cwiseInverse().asDiagonal() * d;
    at += d.cols();
  }
  Vector density = CollocationMonitor(times, derivatives, options_.integrator.collocation_stages);
  const double mean = density.dot((times.tail(total) - times.head(total))) / (times(total) - times(0));
  if (!(mean > 0.0) || !std::isfinite(mean)) return;  // nothing to equidistribute
  density.array() += options_.adapt_mesh_floor * mean;
  std::vector<std::vector<double>> meshes;
  for (Index i = 0; i < segments_; ++i) {
    meshes.push_back(EquidistributedMesh(times, density, SegmentTime(T, i), SegmentTime(T, i + 1),
                                         data.derivatives[static_cast<std::size_t>(i)].cols()));
  }
  collocation_meshes_ = std::move(meshes);
  // Another discrete map: nothing computed on the old meshes holds.
  cache_valid_ = false;
  residual_ready_ = false;
  samples_.valid = false;
  test_samples_.valid = false;
}

Vector ShootingProblem::CollocationTimes(double period) const {
  const long uniform = options_.integrator.collocation_steps;
  std::vector<double> times;
  for (Index i = 0; i < segments_; ++i) {
    const double t0 = SegmentTime(period, i), t1 = SegmentTime(period, i + 1);
    if (collocation_meshes_.empty()) {
      for (long k = 0; k < uniform; ++k) {
        times.push_back(t0 + static_cast<double>(k) / static_cast<double>(uniform) * (t1 - t0));
      }
      continue;
    }
    const std::vector<double>& mesh = collocation_meshes_[static_cast<std::size_t>(i)];
    for (std::size_t k = 0; k + 1 < mesh.size(); ++k) times.push_back(t0 + mesh[k] * (t1 - t0));
  }
  times.push_back(SegmentTime(period, segments_));
  return Eigen::Map<const Vector>(times.data(), static_cast<Index>(times.size()));
}

Vector ShootingProblem::CollocationStepFractions() const {
  const Vector times = CollocationTimes(1.0);
  const Index steps = times.size() - 1;
  return times.tail(steps) - times.head(steps);
}

void ShootingProblem::SetMeasures(std::vector<OrbitMeasure> measures) {
  for (const OrbitMeasure& measure : measures) {
    if (measure.name.empty() || !measure.evaluate) {
      throw std::invalid_argument(
          "ShootingProblem::SetMeasures: every measure needs a name and a function");
    }
  }
  measures_ = std::move(measures);
  samples_measures_.resize(0);
}

Vector ShootingProblem::Scale() const {
  Vector scale(Dimension());
  for (Index i = 0; i < segments_; ++i) scale.segment(i * n_, n_) = state_scale_;
  if (kind_ != OrbitKind::kForced) scale(segments_ * n_) = period_scale_ > 0.0 ? period_scale_ : 1.0;
  if (kind_ == OrbitKind::kRelative) scale(segments_ * n_ + 1) = 1.0;  // radians
  scale.tail(event_scale_.size()).setConstant(1.0 / static_cast<double>(segments_));
  return scale;
}

Vector ShootingProblem::ResidualScale() const {
  Vector scale = Vector::Ones(Dimension());
  for (Index i = 0; i < segments_; ++i) scale.segment(i * n_, n_) = state_scale_;
  scale.tail(event_scale_.size()) = event_scale_;
  return scale;  // the phase conditions are dimensionless already
}

// ---------------------------------------------------------------------------------------------
// Integration and the cache

bool ShootingProblem::SameKey(const Vector& u, double lambda) const {
  return cache_valid_ && lambda == cache_lambda_ && u.size() == cache_u_.size() &&
         u == cache_u_;
}

bool ShootingProblem::IntegrateSegments(const Vector& u, double lambda, Need need,
                                        SegmentData& data, OdeIntegrator& integrator) {
  data.has_stm = data.has_dxdp = false;
  if (!u.allFinite() || !std::isfinite(lambda)) {
    last_failure_ = IntegrationResult();
    last_failure_.status = IntegrationStatus::kOther;
    last_failure_.message = "the unknowns or λ are not finite";
    return false;
  }
  system_.SetParameter(lambda);
  const double T = kind_ == OrbitKind::kForced ? system_.ForcingPeriod() : u(segments_ * n_);
  if (!(T > 0.0) || !std::isfinite(T)) {
    last_failure_ = IntegrationResult();
    last_failure_.status = IntegrationStatus::kOther;
    last_failure_.message = fmt::format("the period T = {} is not positive and finite", T);
    return false;
  }
  if (!UseMesh(u)) return false;
  const bool events = !options_.event_boundaries.empty();
  for (Index i = 0; i < segments_; ++i) {
    Matrix* stm = need == Need::kState ? nullptr : &data.stm[i];
    Vector* dxdp = need == Need::kStmAndParameter ? &data.dxdp[i] : nullptr;
    Vector* dxdt1 = events && stm != nullptr ? &data.dxdt1[i] : nullptr;
    UseCollocationMesh(integrator, i);
    const IntegrationResult result =
        integrator.Integrate(SegmentTime(T, i), u.segment(i * n_, n_), SegmentTime(T, i + 1),
                             data.ends[i], stm, dxdp, dxdt1);
    if (options_.adapt_mesh_every > 0 && result.Succeeded()) {
      data.derivatives[static_cast<std::size_t>(i)] = integrator.CollocationDerivatives();
    }
    statistics_.steps += result.statistics.steps;
    statistics_.nonlinear_iterations += result.statistics.nonlinear_iterations;
    statistics_.linear_solver_setups += result.statistics.linear_solver_setups;
    if (stm == nullptr) {
      ++statistics_.residual_integrations;
    } else {
      ++statistics_.sensitivity_integrations;
    }
    if (!result.Succeeded()) {
      last_failure_ = result;
      last_failure_.message =
          fmt::format("segment {} of {}: {}", i, segments_, last_failure_.message);
      return false;
    }
  }
  data.has_stm = need != Need::kState;
  data.has_dxdp = need == Need::kStmAndParameter;
  return true;
}

bool ShootingProblem::Ensure(const Vector& u, double lambda, Need need) {
  if (!SameKey(u, lambda)) {
    cache_valid_ = false;
    residual_ready_ = false;
    cache_.has_stm = cache_.has_dxdp = false;
  }
  const bool have = cache_valid_ && (need == Need::kState  ? true
                                     : need == Need::kStm ? cache_.has_stm
                                                          : cache_.has_dxdp);
  if (have) {
    ++statistics_.cache_hits;
  } else {
    if (!has_reference_ && kind_ != OrbitKind::kForced) SetPhaseReference(u, lambda);
    // A Jacobian is followed by ∂F/∂λ in a continuation corrector: compute both from one
    // integration. A residual-only request stays cheap unless asked otherwise.
    Need actual = need;
    const bool parameter_sensitivity =
        options_.lambda_derivative == LambdaDerivative::kSensitivity;
    if (need == Need::kStm && parameter_sensitivity) actual = Need::kStmAndParameter;
    if (need == Need::kState && options_.sensitivities_in_residual) {
      actual = parameter_sensitivity ? Need::kStmAndParameter : Need::kStm;
    }
    cache_valid_ = false;
    if (!IntegrateSegments(u, lambda, actual, cache_, integrator_)) return false;
    cache_u_ = u;
    cache_lambda_ = lambda;
    cache_valid_ = true;
  }
  // The residual at a point is assembled from its first integration and then kept, so that F(u)
  // does not change by integration noise when a Jacobian later integrates again with
  // sensitivities (a different step sequence).
  if (!residual_ready_) {
    AssembleResidual(u, cache_, cache_F_);
    residual_ready_ = true;
  }
  return true;
}

void ShootingProblem::AssembleResidual(const Vector& u, const SegmentData& data, Vector& F) {
  F.resize(Dimension());
  for (Index i = 0; i + 1 < segments_; ++i) {
    F.segment(i * n_, n_) = data.ends[i] - u.segment((i + 1) * n_, n_);
  }
  x_work_ = u.head(n_);
  if (kind_ == OrbitKind::kRelative) system_.Rotate(u(segments_ * n_ + 1), x_work_);
  F.segment((segments_ - 1) * n_, n_) = data.ends[segments_ - 1] - x_work_;
  if (kind_ != OrbitKind::kForced) {
    F(segments_ * n_) = time_normal_.dot(u.head(n_) - reference_);
  }
  if (kind_ == OrbitKind::kRelative) {
    F(segments_ * n_ + 1) = rotation_normal_.dot(u.head(n_) - reference_);
  }
  for (std::size_t j = 0; j < options_.event_boundaries.size(); ++j) {
    const ShootingOptions::EventBoundary& event = options_.event_boundaries[j];
    system_.SwitchingFunctions(0.0, u.segment(event.boundary * n_, n_), h_work_);
    F(EventOffset() + static_cast<Index>(j)) = h_work_(event.surface);
  }
}

// ---------------------------------------------------------------------------------------------
// Problem interface

void ShootingProblem::Residual(const Vector& u, double lambda, Vector& F) {
  CheckUnknowns(u, "Residual");
  if (!Ensure(u, lambda, Need::kState)) {
    F = Vector::Constant(Dimension(), kNaN);
    return;
  }
  F = cache_F_;
}

void ShootingProblem::Jacobian(const Vector& u, double lambda, Matrix& J) {
  CheckUnknowns(u, "Jacobian");
  const Index dimension = Dimension();
  if (!Ensure(u, lambda, Need::kStm)) {
    J = Matrix::Constant(dimension, dimension, kNaN);
    return;
  }
  J.setZero(dimension, dimension);
  const Index N = segments_, n = n_;
  for (Index i = 0; i < N; ++i) {
    J.block(i * n, i * n, n, n) = cache_.stm[i];
    if (i + 1 < N) J.block(i * n, (i + 1) * n, n, n).diagonal().setConstant(-1.0);
  }
  if (kind_ == OrbitKind::kRelative) {
    RotationMatrix(u(N * n + 1), rotation_work_);
    J.block((N - 1) * n, 0, n, n) -= rotation_work_;
  } else {
    J.block((N - 1) * n, 0, n, n).diagonal().array() -= 1.0;
  }
  if (kind_ == OrbitKind::kForced) return;
  const double T = u(N * n);
  system_.SetParameter(lambda);
  UseMesh(u);  // in order: the integration above succeeded
  const bool events = !options_.event_boundaries.empty();
  for (Index i = 0; i < N; ++i) {
    if (events) {
      f_work_ = cache_.dxdt1[i];
    } else {
      system_.Rhs(SegmentTime(T, i + 1), cache_.ends[i], f_work_);
    }
    J.block(i * n, N * n, n, 1) = f_work_ * (mesh_[i + 1] - mesh_[i]);
  }
  for (std::size_t j = 0; j < options_.event_boundaries.size(); ++j) {
    const ShootingOptions::EventBoundary& event = options_.event_boundaries[j];
    const Index b = event.boundary, column = EventOffset() + static_cast<Index>(j);
    // Segment i lasts T (τ_{i+1} − τ_i); τ_b moves the boundaries anchored to it too.
    for (Index i = 0; i < N; ++i) {
      const int e = static_cast<int>(j);
      const double weight = MeshWeight(i + 1, e) - MeshWeight(i, e);
      if (weight != 0.0) J.block(i * n, column, n, 1) = weight * T * cache_.dxdt1[i];
    }
    J.block(column, b * n, 1, n) =
        SwitchingGradient(event.surface, u.segment(b * n, n)).transpose();
  }
  J.block(N * n, 0, 1, n) = time_normal_.transpose();
  if (kind_ == OrbitKind::kRelative) {
    x_work_ = u.head(n);
    system_.Rotate(u(N * n + 1), x_work_);
    system_.RotationGenerator(x_work_, g_work_);
    J.block((N - 1) * n, N * n + 1, n, 1) = -g_work_;
    J.block(N * n + 1, 0, 1, n) = rotation_normal_.transpose();
  }
}

void ShootingProblem::DfDlambda(const Vector& u, double lambda, Vector& dF) {
  CheckUnknowns(u, "DfDlambda");
  const Index dimension = Dimension();
  const Index N = segments_, n = n_;
  if (options_.lambda_derivative == LambdaDerivative::kFiniteDifference) {
    // Central differences; the scratch data keep the cache at (u, λ) intact.
    const double h = CentralDifferenceStep(lambda, lambda_scale_);
    Vector F_plus, F_minus;
    if (!has_reference_ && kind_ != OrbitKind::kForced) SetPhaseReference(u, lambda);
    const bool ok = IntegrateSegments(u, lambda + h, Need::kState, scratch_, integrator_);
    if (ok) AssembleResidual(u, scratch_, F_plus);
    const bool ok_minus =
        ok && IntegrateSegments(u, lambda - h, Need::kState, scratch_, integrator_);
    if (ok_minus) AssembleResidual(u, scratch_, F_minus);
    system_.SetParameter(lambda);
    if (!ok_minus) {
      dF = Vector::Constant(dimension, kNaN);
      return;
    }
    dF = (F_plus - F_minus) / (2.0 * h);
    return;
  }
  if (!Ensure(u, lambda, Need::kStmAndParameter)) {
    dF = Vector::Constant(dimension, kNaN);
    return;
  }
  dF.setZero(dimension);
  for (Index i = 0; i < N; ++i) dF.segment(i * n, n) = cache_.dxdp[i];
  if (kind_ == OrbitKind::kForced) {
    // The segment ends t_i = T(λ) τ_i move with λ: d y_i = f(t_{i+1}, y_i) dt_{i+1} − M_i f(t_i, x_i) dt_i.
    const double T = ForcingPeriodAt(lambda);
    const double dT = ForcingPeriodDerivative(lambda);
    for (Index i = 0; i < N; ++i) {
      system_.Rhs(SegmentTime(T, i + 1), cache_.ends[i], f_work_);
      dF.segment(i * n, n) += dT * mesh_[i + 1] * f_work_;
      if (i > 0) {
        system_.Rhs(SegmentTime(T, i), u.segment(i * n, n), f_work_);
        dF.segment(i * n, n) -= dT * mesh_[i] * (cache_.stm[i] * f_work_);
      }
    }
  }
}

const std::vector<Matrix>* ShootingProblem::StabilityMonodromies(const Vector& u, double lambda) {
  if (!stability_integrator_) return Ensure(u, lambda, Need::kStm) ? &cache_.stm : nullptr;
  if (stability_valid_ && lambda == stability_lambda_ && u == stability_u_) {
    ++statistics_.cache_hits;
    return &stability_.stm;
  }
  stability_valid_ = false;
  if (!IntegrateSegments(u, lambda, Need::kStm, stability_, *stability_integrator_)) {
    return nullptr;
  }
  stability_u_ = u;
  stability_lambda_ = lambda;
  stability_valid_ = true;
  return &stability_.stm;
}

const std::vector<Matrix>& ShootingProblem::SegmentMonodromies(const Vector& u, double lambda) {
  CheckUnknowns(u, "SegmentMonodromies");
  static const std::vector<Matrix> kEmpty;
  const std::vector<Matrix>* stm = StabilityMonodromies(u, lambda);
  return stm != nullptr ? *stm : kEmpty;
}

FloquetResult ShootingProblem::Floquet(const Vector& u, double lambda) {
  CheckUnknowns(u, "Floquet");
  FloquetResult result;
  const std::vector<Matrix>* stm = StabilityMonodromies(u, lambda);
  if (stm == nullptr) {
    const Index k = kind_ == OrbitKind::kForced ? 0 : (kind_ == OrbitKind::kAutonomous ? 1 : 2);
    result.multipliers = ComplexVector::Constant(n_ - k, std::complex<double>(kNaN, kNaN));
    return result;
  }
  const Index N = segments_, n = n_;
  UseMesh(u);  // in order: the integration above succeeded
  // Factors in scaled coordinates S⁻¹ M_i S (a similarity: the multipliers do not change, the
  // blocks are balanced when states have different units).
  std::vector<Matrix> factors(N);
  for (Index i = 0; i < N; ++i) {
    factors[i] = state_scale_.cwiseInverse().asDiagonal() * (*stm)[i] * state_scale_.asDiagonal();
  }
  const double phi = Rotation(u);
  if (kind_ == OrbitKind::kRelative) {
    // The return map of a relative periodic orbit is x ↦ R_{−φ} x(T; x): last factor R_{−φ} M.
    RotationMatrix(-phi, rotation_work_);
    factors[N - 1] = state_scale_.cwiseInverse().asDiagonal() * rotation_work_ *
                     (*stm)[N - 1] * state_scale_.asDiagonal();
  }
  // Trivial directions at every segment start, scaled: f(t_i, x_i) and g(x_i).
  std::vector<Matrix> bases;
  if (kind_ != OrbitKind::kForced) {
    const double T = u(N * n);
    system_.SetParameter(lambda);
    const Index k = kind_ == OrbitKind::kAutonomous ? 1 : 2;
    bases.assign(N, Matrix(n, k));
    for (Index i = 0; i < N; ++i) {
      system_.Rhs(SegmentTime(T, i), u.segment(i * n, n), f_work_);
      bases[i].col(0) = f_work_.cwiseQuotient(state_scale_);
      if (k == 2) {
        system_.RotationGenerator(u.segment(i * n, n), g_work_);
        bases[i].col(1) = g_work_.cwiseQuotient(state_scale_);
      }
    }
  }
  return FloquetMultipliers(factors, bases, options_.floquet_method);
}

Spectrum ShootingProblem::Stability(const Vector& u, double lambda) {
  const FloquetResult floquet = Floquet(u, lambda);
  Spectrum spectrum;
  spectrum.kind = SpectrumKind::kFloquetMultipliers;
  spectrum.values = floquet.multipliers;
  spectrum.trivial_removed =
      kind_ == OrbitKind::kForced ? 0 : (kind_ == OrbitKind::kAutonomous ? 1 : 2);
  spectrum.valid = floquet.valid;
  return spectrum;
}

const OrbitSamples& ShootingProblem::Orbit(const Vector& u, double lambda) {
  CheckUnknowns(u, "Orbit");
  const bool held = samples_.valid && lambda == samples_.lambda && u == samples_.u;
  if (!held) samples_measures_.resize(0);
  return Sampled(samples_, u, lambda, options_.samples_per_segment);
}

Index ShootingProblem::TestSamplesPerSegment() const {
  if (options_.integrator.method != IntegrationMethod::kGaussCollocation) {
    return options_.samples_per_segment;
  }
  return std::max<Index>(options_.samples_per_segment,
                         kTestSamplesPerCollocationStep * options_.integrator.collocation_steps);
}

const OrbitSamples& ShootingProblem::TestOrbit(const Vector& u, double lambda) {
  const Index s = TestSamplesPerSegment();
  if (s == options_.samples_per_segment) return Orbit(u, lambda);
  return Sampled(test_samples_, u, lambda, s);
}

const OrbitSamples& ShootingProblem::Sampled(SampleCache& cache, const Vector& u, double lambda,
                                             Index s) {
  if (cache.valid && lambda == cache.lambda && u == cache.u) return cache.orbit;
  cache.valid = true;
  cache.u = u;
  cache.lambda = lambda;
  OrbitSamples& orbit = cache.orbit;
  orbit = OrbitSamples();
  orbit.parameter = lambda;
  orbit.rotation = Rotation(u);
  system_.SetParameter(lambda);
  const double T = Period(u, lambda);
  orbit.period = T;
  const Index m = segments_ * s + 1;
  orbit.times.resize(m);
  orbit.states.resize(n_, m);
  if (!u.allFinite() || !(T > 0.0) || !std::isfinite(T) || !UseMesh(u)) {
    orbit.states.setConstant(kNaN);
    return orbit;
  }
  Matrix segment_states;
  for (Index i = 0; i < segments_; ++i) {
    const double t0 = SegmentTime(T, i), t1 = SegmentTime(T, i + 1);
    const Vector times = Vector::LinSpaced(s + 1, t0, t1);
    UseCollocationMesh(integrator_, i);
    const IntegrationResult result =
        integrator_.Sample(t0, u.segment(i * n_, n_), times, segment_states);
    statistics_.steps += result.statistics.steps;
    statistics_.nonlinear_iterations += result.statistics.nonlinear_iterations;
    statistics_.linear_solver_setups += result.statistics.linear_solver_setups;
    ++statistics_.residual_integrations;
    if (!result.Succeeded()) {
      last_failure_ = result;
      orbit.states.setConstant(kNaN);
      return orbit;
    }
    const Index count = i + 1 == segments_ ? s + 1 : s;
    orbit.times.segment(i * s, count) = times.head(count);
    orbit.states.middleCols(i * s, count) = segment_states.leftCols(count);
  }
  if (!collocation_meshes_.empty()) orbit.collocation_steps = CollocationStepFractions();
  orbit.valid = true;
  return orbit;
}

std::vector<std::string> ShootingProblem::MeasureNames() const {
  std::vector<std::string> names = {"period"};
  if (kind_ == OrbitKind::kRelative) names.push_back("rotation");
  for (const OrbitMeasure& measure : measures_) names.push_back(measure.name);
  return names;
}

Vector ShootingProblem::Measures(const Vector& u, double lambda) {
  CheckUnknowns(u, "Measures");
  const OrbitSamples& orbit = Orbit(u, lambda);
  // The same orbit asked again (a special point where another lies: a symmetric rotor's two
  // contacts grazing together) is not measured again (the BDF check of RubOrbitMeasures).
  if (samples_measures_.size() != 0) return samples_measures_;
  Vector values(MeasureNames().size());
  Index k = 0;
  values(k++) = orbit.period;
  if (kind_ == OrbitKind::kRelative) values(k++) = orbit.rotation;
  for (const OrbitMeasure& measure : measures_) {
    values(k++) = orbit.valid ? measure.evaluate(orbit) : kNaN;
  }
  samples_measures_ = values;
  return values;
}

void ShootingProblem::SetTestFunctions(std::vector<OrbitTestFunction> tests) {
  for (const OrbitTestFunction& test : tests) {
    if (test.measure.name.empty() || !test.measure.evaluate) {
      throw std::invalid_argument(
          "ShootingProblem::SetTestFunctions: every test function needs a name and a function");
    }
  }
  tests_ = std::move(tests);
}

std::vector<std::string> ShootingProblem::TestFunctionNames() const {
  std::vector<std::string> names;
  for (const OrbitTestFunction& test : tests_) names.push_back(test.measure.name);
  return names;
}

Vector ShootingProblem::TestFunctions(const Vector& u, double lambda) {
  CheckUnknowns(u, "TestFunctions");
  Vector values(static_cast<Index>(tests_.size()));
  if (tests_.empty()) return values;
  const OrbitSamples& orbit = TestOrbit(u, lambda);
  for (std::size_t k = 0; k < tests_.size(); ++k) {
    values(static_cast<Index>(k)) = orbit.valid ? tests_[k].measure.evaluate(orbit) : kNaN;
  }
  return values;
}

SpecialPointType ShootingProblem::TestFunctionType(int k) const {
  return tests_.at(static_cast<std::size_t>(k)).type;
}

Vector ShootingProblem::InitialGuess(ConstVectorRef x0, double period, double lambda,
                                     double rotation) {
  if (x0.size() != n_) {
    throw std::invalid_argument(fmt::format(
        "ShootingProblem::InitialGuess: x0 has {} entries, the system has {}", x0.size(), n_));
  }
  system_.SetParameter(lambda);
  const double T = kind_ == OrbitKind::kForced ? system_.ForcingPeriod() : period;
  if (!(T > 0.0) || !std::isfinite(T)) {
    throw std::invalid_argument(fmt::format(
        "ShootingProblem::InitialGuess: period = {} must be positive and finite", T));
  }
  mesh_ = base_mesh_;
  Matrix starts(n_, segments_);
  starts.col(0) = x0;
  for (Index i = 1; i < segments_; ++i) {
    UseCollocationMesh(integrator_, i - 1);
    const IntegrationResult result = integrator_.Integrate(
        SegmentTime(T, i - 1), starts.col(i - 1), SegmentTime(T, i), starts.col(i));
    statistics_.steps += result.statistics.steps;
    statistics_.nonlinear_iterations += result.statistics.nonlinear_iterations;
    statistics_.linear_solver_setups += result.statistics.linear_solver_setups;
    ++statistics_.residual_integrations;
    if (!result.Succeeded()) {
      last_failure_ = result;
      starts.rightCols(segments_ - i).setConstant(kNaN);
      break;
    }
  }
  Vector u = Pack(starts, T, rotation);
  if (kind_ != OrbitKind::kForced) SetPhaseReference(u, lambda);
  return u;
}

EventMesh WithEventBoundaries(OdeSystem& system, OrbitKind kind, const ShootingOptions& options,
                              const Vector& u, double lambda, int samples, double min_gap,
                              double coincide) {
  EventMesh result;
  result.options = options;
  if (!options.event_boundaries.empty()) {
    throw std::invalid_argument(
        "WithEventBoundaries: the options have event boundaries already; pass the orbit's "
        "options without them");
  }
  std::string failure;
  const OrbitSamples orbit = SampleOrbit(system, kind, options, u, lambda, samples, &failure);
  if (!orbit.valid) {
    result.message = "the orbit could not be sampled: " + failure;
    return result;
  }
  return EventMeshOf(system, options, orbit, 0.0, min_gap, coincide);
}

OrbitSamples SampleOrbit(OdeSystem& system, OrbitKind kind, const ShootingOptions& options,
                         const Vector& u, double lambda, int samples, std::string* failure) {
  ShootingOptions sampling = options;
  sampling.samples_per_segment = std::max(2, samples / options.segments);
  ShootingProblem problem(system, kind, sampling);
  OrbitSamples orbit = problem.Orbit(u, lambda);
  if (!orbit.valid) *failure = problem.LastFailure().BriefReport();
  return orbit;
}

std::vector<SurfaceCrossing> SurfaceCrossings(const OdeSystem& system, const OrbitSamples& orbit) {
  const int surfaces = system.SwitchingCount();
  const Index m = orbit.times.size();
  Matrix h(surfaces, m);
  for (Index j = 0; j < m; ++j) {
    system.SwitchingFunctions(orbit.times(j), orbit.states.col(j), h.col(j));
  }
  std::vector<SurfaceCrossing> crossings;
  for (int k = 0; k < surfaces; ++k) {
    for (Index j = 1; j < m; ++j) {
      const double a = h(k, j - 1), b = h(k, j);
      if ((a > 0.0) == (b > 0.0)) continue;
      const double t = orbit.times(j - 1) + a / (a - b) * (orbit.times(j) - orbit.times(j - 1));
      crossings.push_back({t / orbit.period, k, j});
    }
  }
  return crossings;
}

EventMesh EventMeshOf(const OdeSystem& system, const ShootingOptions& options,
                      const OrbitSamples& orbit, double start, double min_gap, double coincide) {
  EventMesh result;
  result.options = options;
  // Zeros of every switching function between neighbouring samples, as fractions of the period
  // from `start`.
  std::vector<std::pair<double, int>> zeros;  // (τ, surface)
  for (const SurfaceCrossing& crossing : SurfaceCrossings(system, orbit)) {
    const double tau = crossing.tau - start;
    zeros.emplace_back(tau - std::floor(tau), crossing.surface);
  }
  result.zeros = static_cast<int>(zeros.size());
  std::sort(zeros.begin(), zeros.end());
  for (const auto& [tau, surface] : zeros) {
    if (tau < min_gap || tau > 1.0 - min_gap) {
      result.message = fmt::format(
          "surface {} switches at {:.6g} of the period, within {} of the start: the phase "
          "condition's boundary cannot be an event boundary (start the orbit elsewhere)",
          surface, tau, min_gap);
      return result;
    }
  }
  // The new mesh: the events (zeros of different surfaces that coincide share one), then the old
  // boundaries clear of them.
  std::vector<std::pair<double, int>> boundaries;  // (τ, surface or −1)
  for (const auto& zero : zeros) {
    if (boundaries.empty() || zero.first - boundaries.back().first > coincide) {
      boundaries.push_back(zero);
    }
  }
  const std::size_t events = boundaries.size();
  std::vector<double> mesh = options.mesh;
  if (mesh.empty()) {
    for (int i = 0; i <= options.segments; ++i) mesh.push_back(double(i) / options.segments);
  }
  for (std::size_t i = 1; i + 1 < mesh.size(); ++i) {
    bool clear = true;
    for (std::size_t e = 0; e < events; ++e)
      clear = clear && std::abs(mesh[i] - boundaries[e].first) >= min_gap;
    if (clear) boundaries.emplace_back(mesh[i], -1);
  }
  std::sort(boundaries.begin(), boundaries.end());
  ShootingOptions& out = result.options;
  out.segments = static_cast<int>(boundaries.size()) + 1;
  out.mesh = {0.0};
  out.event_boundaries.clear();
  for (const auto& [tau, surface] : boundaries) {
    out.mesh.push_back(tau);
    if (surface >= 0)
      out.event_boundaries.push_back({static_cast<int>(out.mesh.size()) - 1, surface});
  }
  out.mesh.push_back(1.0);
  result.ok = true;
  return result;
}

}  // namespace rubcont
