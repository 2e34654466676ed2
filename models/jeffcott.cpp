#include "models/jeffcott.h"

#include <cmath>

#include "models/units.h"

namespace rubcont {

RubStructure JeffcottStructure(const JeffcottParams& p) {
  RubStructure s;
  s.mass = Eigen::Vector2d(p.m_r, p.m_s).asDiagonal();
  s.stiffness = Eigen::Vector2d(p.k_r, p.k_s).asDiagonal();
  s.damping = Eigen::Vector2d(p.c_r, p.c_s).asDiagonal();
  s.imbalance_weights = Eigen::Vector2d(1.0, 0.0);
  s.imbalance = p.imbalance;
  s.law = ContactLawOf(p);
  s.contacts = {RubContact{0, 1, {p.C, p.R}, "contact"}};
  s.coordinate_names = {"rotor", "stator"};
  s.Validate();
  return s;
}

std::complex<double> JeffcottContactForce(const JeffcottParams& p, double W) {
  using Complex = std::complex<double>;
  const Complex D_r(p.k_r - W * W * p.m_r, -W * p.c_r);
  const Complex D_s(p.k_s - W * W * p.m_s, -W * p.c_s);
  const Complex H = 1.0 / D_r + 1.0 / D_s;
  return -p.C / H;
}

JeffcottFrequencies JeffcottNaturalFrequencies(const JeffcottParams& p) {
  JeffcottFrequencies f;
  f.rotor_hz = RadPerSecondToHz(std::sqrt(p.k_r / p.m_r));
  f.stator_hz = RadPerSecondToHz(std::sqrt(p.k_s / p.m_s));
  f.combined_hz = RadPerSecondToHz(std::sqrt((p.k_r + p.k_s) / (p.m_r + p.m_s)));
  return f;
}

AnalyticCurve ComputeJeffcottCurve(const JeffcottParams& params, const AnalyticOptions& options) {
  return ComputeClosedFormCurve(
      [&](double precession) {
        return ComplexVector2(JeffcottContactForce(params, precession), 0.0);
      },
      1, params.friction, CircularMode::kSingleContact, options);
}

}  // namespace rubcont
