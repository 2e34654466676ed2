#include "models/beam.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "models/units.h"

namespace rubcont {
namespace {

[[noreturn]] void RejectBeam(const std::string& key, double value, const std::string& rule) {
  std::ostringstream message;
  message << key << " = " << value << ": " << rule;
  throw std::invalid_argument(message.str());
}

void CheckFinite(const std::string& key, double value) {
  if (!std::isfinite(value)) RejectBeam(key, value, "must be finite");
}
void CheckPositive(const std::string& key, double value, const char* unit) {
  CheckFinite(key, value);
  if (value <= 0.0) RejectBeam(key, value, std::string("must be positive (") + unit + ")");
}
void CheckNonNegative(const std::string& key, double value, const char* unit) {
  CheckFinite(key, value);
  if (value < 0.0) RejectBeam(key, value, std::string("must be non-negative (") + unit + ")");
}

void CheckNode(const std::string& key, int node, const BeamModel& model, int shaft) {
  const int nodes = model.shafts[static_cast<std::size_t>(shaft)].Nodes();
  if (node < 0 || node >= nodes) {
    RejectBeam(key, node, "must name a node of shafts[" + std::to_string(shaft) + "] (0 to " +
                          std::to_string(nodes - 1) + ")");
  }
}

}  // namespace

double ShaftElement::Area() const {
  return kPi * (outer_diameter * outer_diameter - inner_diameter * inner_diameter) / 4.0;
}

double ShaftElement::AreaMoment() const {
  return kPi * (std::pow(outer_diameter, 4) - std::pow(inner_diameter, 4)) / 64.0;
}

double ShaftElement::ShearCoefficient() const {
  const double nu = Poisson();
  const double m = inner_diameter / outer_diameter;
  const double p = (1.0 + m * m) * (1.0 + m * m);
  return 6.0 * (1.0 + nu) * p / ((7.0 + 6.0 * nu) * p + (20.0 + 12.0 * nu) * m * m);
}

double ShaftElement::ShearParameter() const {
  return 12.0 * youngs_modulus * AreaMoment() /
         (ShearCoefficient() * shear_modulus * Area() * length * length);
}

BeamElementMatrices TimoshenkoElement(const ShaftElement& e) {
  const double L = e.length, L2 = L * L;
  const double phi = e.ShearParameter(), phi2 = phi * phi;
  const double s = 1.0 + phi;
  BeamElementMatrices out;

  const double k = e.youngs_modulus * e.AreaMoment() / (s * L2 * L);
  out.stiffness << 12, 6 * L, -12, 6 * L,                          //
      6 * L, (4 + phi) * L2, -6 * L, (2 - phi) * L2,               //
      -12, -6 * L, 12, -6 * L,                                     //
      6 * L, (2 - phi) * L2, -6 * L, (4 + phi) * L2;
  out.stiffness *= k;

  const double m1 = 13.0 / 35 + 7 * phi / 10 + phi2 / 3;
  const double m2 = 11.0 / 210 + 11 * phi / 120 + phi2 / 24;
  const double m3 = 9.0 / 70 + 3 * phi / 10 + phi2 / 6;
  const double m4 = 13.0 / 420 + 3 * phi / 40 + phi2 / 24;
  const double m5 = 1.0 / 105 + phi / 60 + phi2 / 120;
  const double m6 = 1.0 / 140 + phi / 60 + phi2 / 120;
  Eigen::Matrix4d translational;
  translational << m1, m2 * L, m3, -m4 * L,                        //
      m2 * L, m5 * L2, m4 * L, -m6 * L2,                           //
      m3, m4 * L, m1, -m2 * L,                                     //
      -m4 * L, -m6 * L2, -m2 * L, m5 * L2;
  translational *= e.density * e.Area() * L / (s * s);

  const double m7 = 6.0 / 5, m8 = 1.0 / 10 - phi / 2;
  const double m9 = 2.0 / 15 + phi / 6 + phi2 / 3, m10 = 1.0 / 30 + phi / 6 - phi2 / 6;
  Eigen::Matrix4d rotary;
  rotary << m7, m8 * L, -m7, m8 * L,                               //
      m8 * L, m9 * L2, -m8 * L, -m10 * L2,                         //
      -m7, -m8 * L, m7, -m8 * L,                                   //
      m8 * L, -m10 * L2, -m8 * L, m9 * L2;
  rotary *= e.density * e.AreaMoment() / (s * s * L);

  out.mass = translational + rotary;
  out.gyroscopic = 2.0 * rotary;
  return out;
}

std::vector<double> Shaft::NodePositions() const {
  std::vector<double> z(1, 0.0);
  for (const ShaftElement& e : elements) z.push_back(z.back() + e.length);
  return z;
}

Index BeamModel::Coordinate(int shaft, int node, int component) const {
  Index offset = 0;
  for (int s = 0; s < shaft; ++s) offset += 2 * shafts[static_cast<std::size_t>(s)].Nodes();
  return offset + 2 * node + component;
}

Index BeamModel::Coordinates() const {
  return Coordinate(static_cast<int>(shafts.size()), 0, 0);
}

void BeamModel::Validate() const {
  if (shafts.empty()) throw std::invalid_argument("shafts: at least one shaft is needed");
  for (std::size_t s = 0; s < shafts.size(); ++s) {
    const Shaft& shaft = shafts[s];
    const std::string name = "shafts[" + std::to_string(s) + "]";
    if (shaft.elements.empty()) {
      throw std::invalid_argument(name + ".elements: at least one element is needed");
    }
    for (std::size_t i = 0; i < shaft.elements.size(); ++i) {
      const ShaftElement& e = shaft.elements[i];
      const std::string key = name + ".elements[" + std::to_string(i) + "].";
      CheckPositive(key + "length", e.length, "m");
      CheckPositive(key + "outer_diameter", e.outer_diameter, "m");
      CheckNonNegative(key + "inner_diameter", e.inner_diameter, "m");
      if (e.inner_diameter >= e.outer_diameter) {
        RejectBeam(key + "inner_diameter", e.inner_diameter,
                   "must be below outer_diameter (" + std::to_string(e.outer_diameter) + " m)");
      }
      CheckPositive(key + "youngs_modulus", e.youngs_modulus, "Pa");
      CheckPositive(key + "shear_modulus", e.shear_modulus, "Pa");
      const double nu = e.Poisson();
      if (!(nu > -1.0 && nu <= 0.5)) {
        RejectBeam(key + "shear_modulus", e.shear_modulus,
                   "must give a Poisson ratio E/(2G) − 1 in (−1, 0.5] (it gives " +
                   std::to_string(nu) + ")");
      }
      CheckNonNegative(key + "density", e.density, "kg/m³");
    }
    for (std::size_t d = 0; d < shaft.disks.size(); ++d) {
      const Disk& disk = shaft.disks[d];
      const std::string key = name + ".disks[" + std::to_string(d) + "].";
      CheckNode(key + "node", disk.node, *this, static_cast<int>(s));
      CheckNonNegative(key + "mass", disk.mass, "kg");
      CheckNonNegative(key + "diametral_inertia", disk.diametral_inertia, "kg·m²");
      CheckNonNegative(key + "polar_inertia", disk.polar_inertia, "kg·m²");
    }
  }
  const int shaft_count = static_cast<int>(shafts.size());
  for (std::size_t i = 0; i < springs.size(); ++i) {
    const Spring& spring = springs[i];
    const std::string key = "springs[" + std::to_string(i) + "].";
    if (spring.shaft < 0 || spring.shaft >= shaft_count) {
      RejectBeam(key + "shaft", spring.shaft,
                 "must name a shaft (0 to " + std::to_string(shaft_count - 1) + ")");
    }
    CheckNode(key + "node", spring.node, *this, spring.shaft);
    if (spring.other_shaft >= shaft_count) {
      RejectBeam(key + "other_shaft", spring.other_shaft,
                 "must name a shaft (0 to " + std::to_string(shaft_count - 1) + ") or be negative (ground)");
    }
    if (spring.other_shaft >= 0) {
      CheckNode(key + "other_node", spring.other_node, *this, spring.other_shaft);
      if (spring.other_shaft == spring.shaft && spring.other_node == spring.node) {
        RejectBeam(key + "other_node", spring.other_node, "must differ from node on the same shaft");
      }
    }
    CheckNonNegative(key + "stiffness", spring.stiffness, "N/m");
    CheckNonNegative(key + "damping", spring.damping, "N·s/m");
  }
}

StructuralMatrices Assemble(const BeamModel& model) {
  model.Validate();
  const Index n = model.Coordinates();
  StructuralMatrices out;
  out.mass = Matrix::Zero(n, n);
  out.damping = Matrix::Zero(n, n);
  out.stiffness = Matrix::Zero(n, n);
  out.gyroscopic = Matrix::Zero(n, n);
  for (std::size_t s = 0; s < model.shafts.size(); ++s) {
    const Shaft& shaft = model.shafts[s];
    for (std::size_t i = 0; i < shaft.elements.size(); ++i) {
      const BeamElementMatrices e = TimoshenkoElement(shaft.elements[i]);
      const Index first = model.Coordinate(static_cast<int>(s), static_cast<int>(i), 0);
      out.mass.block<4, 4>(first, first) += e.mass;
      out.stiffness.block<4, 4>(first, first) += e.stiffness;
      out.gyroscopic.block<4, 4>(first, first) += e.gyroscopic;
    }
    for (const Disk& disk : shaft.disks) {
      const Index u = model.Coordinate(static_cast<int>(s), disk.node, 0);
      out.mass(u, u) += disk.mass;
      out.mass(u + 1, u + 1) += disk.diametral_inertia;
      out.gyroscopic(u + 1, u + 1) += disk.polar_inertia;
    }
  }
  for (const Spring& spring : model.springs) {
    const Index a = model.Coordinate(spring.shaft, spring.node, 0);
    auto add = [&](Matrix& m, double value) {
      m(a, a) += value;
      if (spring.other_shaft < 0) return;
      const Index b = model.Coordinate(spring.other_shaft, spring.other_node, 0);
      m(b, b) += value;
      m(a, b) -= value;
      m(b, a) -= value;
    };
    add(out.stiffness, spring.stiffness);
    add(out.damping, spring.damping);
  }
  return out;
}

ComplexVector WhirlEigenvalues(const StructuralMatrices& matrices, double spin,
                               const std::vector<Index>& held) {
  const Index n = matrices.Coordinates();
  std::vector<bool> is_held(static_cast<std::size_t>(n), false);
  for (Index h : held) {
    if (h < 0 || h >= n) {
      throw std::invalid_argument("held coordinate " + std::to_string(h) + ": must be 0 to " +
                                  std::to_string(n - 1));
    }
    is_held[static_cast<std::size_t>(h)] = true;
  }
  std::vector<Index> free;
  for (Index i = 0; i < n; ++i) {
    if (!is_held[static_cast<std::size_t>(i)]) free.push_back(i);
  }
  const Index f = static_cast<Index>(free.size());
  auto pick = [&](const Matrix& x) -> Matrix { return x(free, free); };
  const Eigen::LLT<Matrix> mass(pick(matrices.mass));
  if (mass.info() != Eigen::Success) {
    throw std::invalid_argument(
        "mass: not positive definite on the free coordinates (a massless node left free?)");
  }
  // With M = LLᵀ and L⁻¹KL⁻ᵀ = VΛVᵀ, the state z = (Λ^½ w, ẇ), u = L⁻ᵀVw, moves by
  // ż = [[0, Λ^½], [−Λ^½, −D]] z with D = VᵀL⁻¹(C − jωG)L⁻ᵀV: skew-Hermitian without damping,
  // so its eigenvalues are as well conditioned as they can be (the plain companion form
  // [[0, I], [−M⁻¹K, …]] lost 1e-4 of a thick shaft's first frequency at 32 elements).
  const Matrix l_inverse = mass.matrixL().solve(Matrix::Identity(f, f));
  Matrix k_scaled = l_inverse * pick(matrices.stiffness) * l_inverse.transpose();
  k_scaled = 0.5 * (k_scaled + k_scaled.transpose()).eval();
  const Eigen::SelfAdjointEigenSolver<Matrix> modes(k_scaled);
  const Matrix to_modes = modes.eigenvectors().transpose() * l_inverse;
  const Vector root = modes.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  const ComplexMatrix damping =
      (to_modes * pick(matrices.damping) * to_modes.transpose()).cast<std::complex<double>>() -
      std::complex<double>(0.0, spin) *
          (to_modes * pick(matrices.gyroscopic) * to_modes.transpose()).cast<std::complex<double>>();
  ComplexMatrix a = ComplexMatrix::Zero(2 * f, 2 * f);
  a.topRightCorner(f, f) = root.cast<std::complex<double>>().asDiagonal();
  a.bottomLeftCorner(f, f) = -a.topRightCorner(f, f);
  a.bottomRightCorner(f, f) = -damping;
  ComplexVector s = Eigen::ComplexEigenSolver<ComplexMatrix>(a, false).eigenvalues();
  std::sort(s.data(), s.data() + s.size(),
            [](const std::complex<double>& x, const std::complex<double>& y) {
              return x.imag() < y.imag();
            });
  return s;
}

std::vector<StructureMode> WhirlModes(const StructuralMatrices& matrices, double spin,
                                      const std::vector<Index>& held, bool backward) {
  std::vector<StructureMode> modes;
  for (const std::complex<double>& s : WhirlEigenvalues(matrices, spin, held)) {
    const double nu = backward ? -s.imag() : s.imag();
    if (nu > 1e-9 * std::abs(s)) modes.push_back({RadPerSecondToHz(nu), -s.real() / std::abs(s)});
  }
  std::sort(modes.begin(), modes.end(), [](const StructureMode& a, const StructureMode& b) {
    return a.frequency_hz < b.frequency_hz;
  });
  return modes;
}

}  // namespace rubcont
