#include "models/textbook.h"
#include "models/units.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

namespace rubcont {
namespace {

void RequireFinite(const char* type, const char* field, double value) {
  if (!std::isfinite(value)) {
    throw std::invalid_argument(fmt::format("{}.{} = {}: must be finite", type, field, value));
  }
}

// ∂f/∂x of ẍ = μ (1 − x²) ẋ − x (+ forcing), state (x, ẋ).
void VanDerPolJacobian(double mu, ConstVectorRef x, MatrixRef J) {
  J(0, 0) = 0.0;
  J(0, 1) = 1.0;
  J(1, 0) = -2.0 * mu * x(0) * x(1) - 1.0;
  J(1, 1) = mu * (1.0 - x(0) * x(0));
}

// The cycle's amplitude ≈ 2 and its largest |ẋ| ≈ 4|μ|/3 in the fast jumps (μ ≫ 1).
Vector VanDerPolScale(double mu) {
  Vector scale(2);
  scale << 2.0, std::max(2.0, 4.0 * std::abs(mu) / 3.0);
  return scale;
}

}  // namespace

void Validate(const DuffingParams& params) {
  RequireFinite("DuffingParams", "damping", params.damping);
  RequireFinite("DuffingParams", "stiffness", params.stiffness);
  RequireFinite("DuffingParams", "cubic", params.cubic);
  RequireFinite("DuffingParams", "force", params.force);
  RequireFinite("DuffingParams", "frequency", params.frequency);
  if (params.damping < 0.0) {
    throw std::invalid_argument(
        fmt::format("DuffingParams.damping = {}: must be non-negative", params.damping));
  }
  if (!(params.frequency > 0.0)) {
    throw std::invalid_argument(
        fmt::format("DuffingParams.frequency = {}: must be positive", params.frequency));
  }
}

DuffingOscillator::DuffingOscillator(const DuffingParams& params) : params_(params) {
  Validate(params);
}

void DuffingOscillator::Rhs(double t, ConstVectorRef x, VectorRef f) {
  const DuffingParams& p = params_;
  f(0) = x(1);
  f(1) = -p.damping * x(1) - p.stiffness * x(0) - p.cubic * x(0) * x(0) * x(0) +
         p.force * std::cos(p.frequency * t);
}

void DuffingOscillator::JacobianX(double /*t*/, ConstVectorRef x, MatrixRef J) {
  const DuffingParams& p = params_;
  J(0, 0) = 0.0;
  J(0, 1) = 1.0;
  J(1, 0) = -p.stiffness - 3.0 * p.cubic * x(0) * x(0);
  J(1, 1) = -p.damping;
}

void DuffingOscillator::DfDparameter(double t, ConstVectorRef /*x*/, VectorRef df) {
  df(0) = 0.0;
  df(1) = -params_.force * t * std::sin(params_.frequency * t);
}

double DuffingOscillator::ForcingPeriod() const { return kTwoPi / params_.frequency; }

void Validate(const StuartLandauParams& params) {
  RequireFinite("StuartLandauParams", "lambda", params.lambda);
  RequireFinite("StuartLandauParams", "omega", params.omega);
  RequireFinite("StuartLandauParams", "gamma", params.gamma);
}

StuartLandauOscillator::StuartLandauOscillator(const StuartLandauParams& params)
    : params_(params) {
  Validate(params);
}

void StuartLandauOscillator::Rhs(double /*t*/, ConstVectorRef x, VectorRef f) {
  const StuartLandauParams& p = params_;
  const double r2 = x(0) * x(0) + x(1) * x(1);
  f(0) = p.lambda * x(0) - p.omega * x(1) - r2 * (x(0) - p.gamma * x(1));
  f(1) = p.omega * x(0) + p.lambda * x(1) - r2 * (p.gamma * x(0) + x(1));
}

void StuartLandauOscillator::JacobianX(double /*t*/, ConstVectorRef x, MatrixRef J) {
  const StuartLandauParams& p = params_;
  const double r2 = x(0) * x(0) + x(1) * x(1);
  const double a = x(0) - p.gamma * x(1);  // f0 = λx − ωy − r² a
  const double b = p.gamma * x(0) + x(1);  // f1 = ωx + λy − r² b
  J(0, 0) = p.lambda - 2.0 * x(0) * a - r2;
  J(0, 1) = -p.omega - 2.0 * x(1) * a + r2 * p.gamma;
  J(1, 0) = p.omega - 2.0 * x(0) * b - r2 * p.gamma;
  J(1, 1) = p.lambda - 2.0 * x(1) * b - r2;
}

void StuartLandauOscillator::DfDparameter(double /*t*/, ConstVectorRef x, VectorRef df) {
  df = x;
}

void StuartLandauOscillator::Rotate(double phi, VectorRef x) const {
  const double c = std::cos(phi), s = std::sin(phi);
  const double x0 = x(0);
  x(0) = c * x0 - s * x(1);
  x(1) = s * x0 + c * x(1);
}

void StuartLandauOscillator::RotationGenerator(ConstVectorRef x, VectorRef g) const {
  g(0) = -x(1);
  g(1) = x(0);
}

double StuartLandauOscillator::OrbitRadius() const { return std::sqrt(params_.lambda); }
double StuartLandauOscillator::AngularVelocity() const {
  return params_.omega - params_.gamma * params_.lambda;
}
double StuartLandauOscillator::Period() const { return kTwoPi / std::abs(AngularVelocity()); }
double StuartLandauOscillator::NontrivialMultiplier() const {
  return std::exp(-2.0 * params_.lambda * Period());
}

void Validate(const VanDerPolParams& params) {
  RequireFinite("VanDerPolParams", "mu", params.mu);
}

VanDerPolOscillator::VanDerPolOscillator(const VanDerPolParams& params) : params_(params) {
  Validate(params);
}

void VanDerPolOscillator::Rhs(double /*t*/, ConstVectorRef x, VectorRef f) {
  f(0) = x(1);
  f(1) = params_.mu * (1.0 - x(0) * x(0)) * x(1) - x(0);
}

void VanDerPolOscillator::JacobianX(double /*t*/, ConstVectorRef x, MatrixRef J) {
  VanDerPolJacobian(params_.mu, x, J);
}

void VanDerPolOscillator::DfDparameter(double /*t*/, ConstVectorRef x, VectorRef df) {
  df(0) = 0.0;
  df(1) = (1.0 - x(0) * x(0)) * x(1);
}

Vector VanDerPolOscillator::StateScale() const { return VanDerPolScale(params_.mu); }

void Validate(const ForcedVanDerPolParams& params) {
  RequireFinite("ForcedVanDerPolParams", "mu", params.mu);
  RequireFinite("ForcedVanDerPolParams", "force", params.force);
  RequireFinite("ForcedVanDerPolParams", "frequency", params.frequency);
  if (!(params.frequency > 0.0)) {
    throw std::invalid_argument(
        fmt::format("ForcedVanDerPolParams.frequency = {}: must be positive", params.frequency));
  }
}

ForcedVanDerPolOscillator::ForcedVanDerPolOscillator(const ForcedVanDerPolParams& params)
    : params_(params) {
  Validate(params);
}

void ForcedVanDerPolOscillator::Rhs(double t, ConstVectorRef x, VectorRef f) {
  f(0) = x(1);
  f(1) = params_.mu * (1.0 - x(0) * x(0)) * x(1) - x(0) +
         params_.force * std::cos(params_.frequency * t);
}

void ForcedVanDerPolOscillator::JacobianX(double /*t*/, ConstVectorRef x, MatrixRef J) {
  VanDerPolJacobian(params_.mu, x, J);  // the forcing does not depend on the state
}

void ForcedVanDerPolOscillator::DfDparameter(double t, ConstVectorRef /*x*/, VectorRef df) {
  df(0) = 0.0;
  df(1) = -params_.force * t * std::sin(params_.frequency * t);
}

double ForcedVanDerPolOscillator::ForcingPeriod() const { return kTwoPi / params_.frequency; }

Vector ForcedVanDerPolOscillator::StateScale() const { return VanDerPolScale(params_.mu); }

void Validate(const LorenzParams& params) {
  RequireFinite("LorenzParams", "sigma", params.sigma);
  RequireFinite("LorenzParams", "rho", params.rho);
  RequireFinite("LorenzParams", "beta", params.beta);
}

LorenzSystem::LorenzSystem(const LorenzParams& params) : params_(params) { Validate(params); }

void LorenzSystem::Rhs(double /*t*/, ConstVectorRef x, VectorRef f) {
  f(0) = params_.sigma * (x(1) - x(0));
  f(1) = x(0) * (params_.rho - x(2)) - x(1);
  f(2) = x(0) * x(1) - params_.beta * x(2);
}

void LorenzSystem::JacobianX(double /*t*/, ConstVectorRef x, MatrixRef J) {
  J << -params_.sigma, params_.sigma, 0.0,
       params_.rho - x(2), -1.0, -x(0),
       x(1), x(0), -params_.beta;
}

void LorenzSystem::DfDparameter(double /*t*/, ConstVectorRef x, VectorRef df) {
  df << 0.0, x(0), 0.0;
}

Vector LorenzSystem::StateScale() const { return (Vector(3) << 10.0, 10.0, 20.0).finished(); }

void Validate(const SoftImpactParams& params) {
  RequireFinite("SoftImpactParams", "damping", params.damping);
  RequireFinite("SoftImpactParams", "stiffness", params.stiffness);
  RequireFinite("SoftImpactParams", "gap", params.gap);
  RequireFinite("SoftImpactParams", "force", params.force);
  RequireFinite("SoftImpactParams", "frequency", params.frequency);
  const auto require = [](bool ok, const char* field, double value, const char* rule) {
    if (!ok) {
      throw std::invalid_argument(
          fmt::format("SoftImpactParams.{} = {}: {}", field, value, rule));
    }
  };
  require(params.damping >= 0.0, "damping", params.damping, "must be non-negative");
  require(params.stiffness >= 0.0, "stiffness", params.stiffness, "must be non-negative");
  require(params.gap > 0.0, "gap", params.gap, "must be positive");
  require(params.frequency > 0.0, "frequency", params.frequency, "must be positive");
}

SoftImpactOscillator::SoftImpactOscillator(const SoftImpactParams& params) : params_(params) {
  Validate(params);
}

void SoftImpactOscillator::Rhs(double t, ConstVectorRef x, VectorRef f) {
  const SoftImpactParams& p = params_;
  f(0) = x(1);
  f(1) = -p.damping * x(1) - x(0) - p.stiffness * std::max(0.0, x(0) - p.gap) +
         p.force * std::cos(p.frequency * t);
}

void SoftImpactOscillator::JacobianX(double /*t*/, ConstVectorRef x, MatrixRef J) {
  const SoftImpactParams& p = params_;
  J(0, 0) = 0.0;
  J(0, 1) = 1.0;
  J(1, 0) = -1.0 - (x(0) > p.gap ? p.stiffness : 0.0);
  J(1, 1) = -p.damping;
}

void SoftImpactOscillator::DfDparameter(double t, ConstVectorRef /*x*/, VectorRef df) {
  df(0) = 0.0;
  df(1) = -params_.force * t * std::sin(params_.frequency * t);
}

double SoftImpactOscillator::ForcingPeriod() const { return kTwoPi / params_.frequency; }

Vector SoftImpactOscillator::StateScale() const {
  return Vector::Constant(2, params_.gap);
}

void SoftImpactOscillator::SwitchingFunctions(double /*t*/, ConstVectorRef x, VectorRef h) const {
  h(0) = x(0) - params_.gap;
}

double SoftImpactOscillator::FreeAmplitude() const {
  const SoftImpactParams& p = params_;
  const double w = p.frequency;
  return std::abs(p.force) / std::hypot(1.0 - w * w, p.damping * w);
}

Vector SoftImpactOscillator::FreeState() const {
  const SoftImpactParams& p = params_;
  const double w = p.frequency;
  const double a = p.force / std::hypot(1.0 - w * w, p.damping * w);
  const double psi = std::atan2(p.damping * w, 1.0 - w * w);
  return (Vector(2) << a * std::cos(psi), a * w * std::sin(psi)).finished();
}

std::vector<double> SoftImpactOscillator::GrazingFrequencies() const {
  const SoftImpactParams& p = params_;
  const double ratio = p.force / p.gap;
  // s = w²: s² − (2 − c²) s + 1 − (F/g)² = 0.
  const double b = 2.0 - p.damping * p.damping, c = 1.0 - ratio * ratio;
  const double discriminant = b * b - 4.0 * c;
  std::vector<double> result;
  if (discriminant < 0.0) return result;
  const double root = std::sqrt(discriminant);
  for (const double s : {0.5 * (b - root), 0.5 * (b + root)}) {
    if (s > 0.0) result.push_back(std::sqrt(s));
  }
  return result;
}

AutonomousSoftImpactOscillator::AutonomousSoftImpactOscillator(const SoftImpactParams& params)
    : params_(params) {
  Validate(params);
}

void AutonomousSoftImpactOscillator::Rhs(double /*t*/, ConstVectorRef x, VectorRef f) {
  const SoftImpactParams& p = params_;
  const double r = 1.0 - x(2) * x(2) - x(3) * x(3);
  f(0) = x(1);
  f(1) = -p.damping * x(1) - x(0) - p.stiffness * std::max(0.0, x(0) - p.gap) + p.force * x(2);
  f(2) = x(2) * r - p.frequency * x(3);
  f(3) = x(3) * r + p.frequency * x(2);
}

void AutonomousSoftImpactOscillator::JacobianX(double /*t*/, ConstVectorRef x, MatrixRef J) {
  const SoftImpactParams& p = params_;
  const double r = 1.0 - x(2) * x(2) - x(3) * x(3);
  J.setZero();
  J(0, 1) = 1.0;
  J(1, 0) = -1.0 - (x(0) > p.gap ? p.stiffness : 0.0);
  J(1, 1) = -p.damping;
  J(1, 2) = p.force;
  J(2, 2) = r - 2.0 * x(2) * x(2);
  J(2, 3) = -2.0 * x(2) * x(3) - p.frequency;
  J(3, 2) = -2.0 * x(2) * x(3) + p.frequency;
  J(3, 3) = r - 2.0 * x(3) * x(3);
}

Vector AutonomousSoftImpactOscillator::StateScale() const {
  return (Vector(4) << params_.gap, params_.gap, 1.0, 1.0).finished();
}

void AutonomousSoftImpactOscillator::SwitchingFunctions(double /*t*/, ConstVectorRef x,
                                                        VectorRef h) const {
  h(0) = x(0) - params_.gap;
}

std::string AutonomousSoftImpactOscillator::StateName(Index i) const {
  static const char* const kNames[] = {"x", "v", "p", "q"};
  return kNames[i];
}

ForcedStart DuffingStart(const DuffingParams& p) {
  const double w = p.frequency;
  const double d = p.stiffness - w * w, cw = p.damping * w;
  const double A = p.force / std::max(std::hypot(d, cw), 1e-12), psi = std::atan2(cw, d);
  ForcedStart start;
  start.x0 = (Vector(2) << A * std::cos(psi), A * w * std::sin(psi)).finished();
  const double T = kTwoPi / w;
  start.periods =
      p.damping > 0.0 ? static_cast<int>(std::min(2000.0, std::ceil(20.0 / (p.damping * T)))) : 0;
  return start;
}

CycleStart StuartLandauStart(const StuartLandauParams& p) {
  const double turn = std::max(std::abs(p.omega), 1e-3);
  return {(Vector(2) << 1.0, 0.0).finished(), 20.0 / p.lambda + 40.0 * kTwoPi / turn};
}

CycleStart VanDerPolStart(const VanDerPolParams& p) {
  const double period = std::max(kTwoPi, (3.0 - 2.0 * std::log(2.0)) * p.mu);
  return {(Vector(2) << 2.0, 0.0).finished(), 40.0 * period + 20.0 / p.mu};
}

ForcedStart ForcedVanDerPolStart(const ForcedVanDerPolParams& p) {
  const double T = kTwoPi / p.frequency;
  const int periods = static_cast<int>(
      std::min(2000.0, std::ceil(40.0 / (std::max(std::abs(p.mu), 1e-3) * T))));
  return {(Vector(2) << 2.0, 0.0).finished(), periods};
}

}  // namespace rubcont

