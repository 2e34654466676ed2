#include "waves/rotating_wave.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <stdexcept>

#include <fmt/core.h>

#include "continuation/equilibrium_problem.h"
#include "models/units.h"
#include "solvers/constants.h"
#include "solvers/linear_algebra.h"

namespace rubcont {

namespace {

// out = X · Jm for Jm = blkdiag([[0, −1], [1, 0]], ...): multiplication by j on coordinate pairs.
Matrix TimesJ(const Matrix& X) {
  Matrix out(X.rows(), X.cols());
  for (Index i = 0; i + 1 < X.cols(); i += 2) {
    out.col(i) = X.col(i + 1);
    out.col(i + 1) = -X.col(i);
  }
  return out;
}

// j·p on coordinate pairs.
Vector JTimes(const Vector& p) {
  Vector out(p.size());
  for (Index i = 0; i + 1 < p.size(); i += 2) {
    out(i) = -p(i + 1);
    out(i + 1) = p(i);
  }
  return out;
}

constexpr double kMarginTolerance = 1e-12;
// Scaled margins this close to zero at another contact's located event count as simultaneous
// events (the location's own error is ~1e-10 in these units).
constexpr double kSimultaneousTolerance = 1e-8;

}  // namespace

const char* ToString(ContactMode mode) {
  switch (mode) {
    case ContactMode::kFree: return "free";
    case ContactMode::kStick: return "stick";
    case ContactMode::kSlipPositive: return "slip+";
    case ContactMode::kSlipNegative: return "slip-";
  }
  return "?";
}

RotatingWaveProblem::RotatingWaveProblem(RubStructure structure, FrictionLawKind law)
    : structure_(std::move(structure)),
      law_(law),
      modes_(structure_.contacts.size(), ContactMode::kStick),
      frame_(structure_, 0.0) {
  structure_.Validate();
  if (structure_.contacts.empty()) {
    throw std::invalid_argument("RotatingWaveProblem: the structure has no contact");
  }
  mass_ = KronIdentity2(structure_.mass);
  damping_ = KronIdentity2(structure_.damping);
  stiffness_ = KronIdentity2(structure_.stiffness);
  // Scales: positions by the clearance, Ω by the fastest natural frequency of the structure,
  // forces by support stiffness × clearance, ω by Ω / RCI (the speed at which whirl reaches Ω).
  double rci = 0.0;
  for (const RubContact& c : structure_.contacts) {
    position_scale_ = std::max(position_scale_, c.geometry.clearance);
    rci = std::max(rci, c.geometry.radius / c.geometry.clearance);
  }
  const Vector state_scale = frame_.StateScale();
  rate_scale_ = state_scale(state_scale.size() - 1) / state_scale(0);
  force_scale_ = std::max(structure_.stiffness.diagonal().maxCoeff(),
                          structure_.mass.diagonal().maxCoeff() * rate_scale_ * rate_scale_) *
                 position_scale_;
  speed_scale_ = rate_scale_ / rci;
  phase_reference_ = Vector::Zero(2 * Contacts());
  phase_reference_(0) = 1.0;
}

void RotatingWaveProblem::SetStructure(RubStructure structure) {
  structure.Validate();
  if (structure.Coordinates() != structure_.Coordinates() ||
      structure.contacts.size() != structure_.contacts.size()) {
    throw std::invalid_argument(
        "RotatingWaveProblem::SetStructure: the new structure has " +
        std::to_string(structure.Coordinates()) + " coordinates and " +
        std::to_string(structure.contacts.size()) + " contacts: must have " +
        std::to_string(structure_.Coordinates()) + " and " +
        std::to_string(structure_.contacts.size()) + " like the problem's");
  }
  structure_ = std::move(structure);
  frame_ = RubRotatingFrame(structure_, 0.0);
  mass_ = KronIdentity2(structure_.mass);
  damping_ = KronIdentity2(structure_.damping);
  stiffness_ = KronIdentity2(structure_.stiffness);
}

Index RotatingWaveProblem::Dimension() const {
  return 2 * structure_.Coordinates() + 1 + (law_ == FrictionLawKind::kExact ? Contacts() : 0);
}

std::vector<FrictionMode> RotatingWaveProblem::FrictionModes() const {
  std::vector<FrictionMode> modes(modes_.size(), FrictionMode::kRegularized);
  for (std::size_t k = 0; k < modes_.size(); ++k) {
    // The regularized law keeps only the contact events: free, or held in contact (any other
    // mode), with the normal law continued past δ = 0 as for the exact modes.
    if (law_ == FrictionLawKind::kTanh) {
      modes[k] = modes_[k] == ContactMode::kFree ? FrictionMode::kInactive
                                                 : FrictionMode::kRegularizedHeld;
      continue;
    }
    switch (modes_[k]) {
      // A free contact exerts no force even where a trial point penetrates: the piece stays
      // smooth (the normal force's kink at δ = 0 would stall Newton), and the engine locates
      // the contact-regain event on its margin −δ.
      case ContactMode::kFree: modes[k] = FrictionMode::kInactive; break;
      case ContactMode::kStick: modes[k] = FrictionMode::kStick; break;
      case ContactMode::kSlipPositive: modes[k] = FrictionMode::kSlipPositive; break;
      case ContactMode::kSlipNegative: modes[k] = FrictionMode::kSlipNegative; break;
    }
  }
  return modes;
}

void RotatingWaveProblem::Evaluate(const Vector& u, double omega, bool with_derivatives) {
  const Index n2 = 2 * structure_.Coordinates();
  const Vector p = u.head(n2);
  velocity_ = -u(n2) * JTimes(p);  // ḋ = −jΩ d for every coordinate
  const Vector stick_forces =
      law_ == FrictionLawKind::kExact ? Vector(u.tail(Contacts())) : Vector::Zero(Contacts());
  EvaluateContactForces(structure_, omega, p, velocity_, FrictionModes(), stick_forces,
                        with_derivatives, forces_);
}

std::vector<ContactEvaluation> RotatingWaveProblem::EvaluateContacts(const Vector& u,
                                                                     double omega) {
  Evaluate(u, omega, false);
  return forces_.contacts;
}

void RotatingWaveProblem::Residual(const Vector& u, double omega, Vector& F) {
  const Index n2 = 2 * structure_.Coordinates();
  const Index m = Contacts();
  Evaluate(u, omega, false);
  const Vector p = u.head(n2);
  const double W = u(n2);
  F.resize(Dimension());
  // (K − Ω²M) p + C v − Q(p, v),  v = −Ω j p
  F.head(n2) = stiffness_ * p - W * W * (mass_ * p) + damping_ * velocity_ - forces_.generalized;
  double phase = 0.0;
  for (Index k = 0; k < m; ++k) {
    const RubContact& c = structure_.contacts[k];
    const Vector2 d = p.segment<2>(2 * c.rotor) - p.segment<2>(2 * c.stator);
    phase += phase_reference_(2 * k) * d.y() - phase_reference_(2 * k + 1) * d.x();
  }
  F(n2) = phase / position_scale_;
  if (law_ != FrictionLawKind::kExact) return;
  const Index reference = ReferenceStick();
  for (Index k = 0; k < m; ++k) {
    const ContactEvaluation& e = forces_.contacts[k];
    const double Fk = u(n2 + 1 + k);
    switch (modes_[k]) {
      case ContactMode::kFree: F(n2 + 1 + k) = Fk; break;
      case ContactMode::kStick:
        F(n2 + 1 + k) = k == reference
                            ? e.slip_velocity
                            : e.slip_velocity - forces_.contacts[reference].slip_velocity;
        break;
      case ContactMode::kSlipPositive:
        F(n2 + 1 + k) = Fk - structure_.law.friction * e.normal_force;
        break;
      case ContactMode::kSlipNegative:
        F(n2 + 1 + k) = Fk + structure_.law.friction * e.normal_force;
        break;
    }
  }
}

void RotatingWaveProblem::Jacobian(const Vector& u, double omega, Matrix& J) {
  const Index n2 = 2 * structure_.Coordinates();
  const Index m = Contacts();
  Evaluate(u, omega, true);
  const Vector p = u.head(n2);
  const double W = u(n2);
  J.setZero(Dimension(), Dimension());
  const Matrix softness = damping_ - forces_.d_dv;  // C − ∂Q/∂v, multiplied by ∂v/∂p = −Ω Jm
  J.topLeftCorner(n2, n2) = stiffness_ - W * W * mass_ - forces_.d_dq - W * TimesJ(softness);
  J.col(n2).head(n2) = -2.0 * W * (mass_ * p) - softness * JTimes(p);
  Matrix2 rotate;  // J2: v ↦ j v
  rotate << 0.0, -1.0, 1.0, 0.0;
  for (Index k = 0; k < m; ++k) {
    const RubContact& c = structure_.contacts[k];
    const Index r = 2 * c.rotor, s = 2 * c.stator;
    J(n2, r) += -phase_reference_(2 * k + 1) / position_scale_;
    J(n2, r + 1) += phase_reference_(2 * k) / position_scale_;
    J(n2, s) -= -phase_reference_(2 * k + 1) / position_scale_;
    J(n2, s + 1) -= phase_reference_(2 * k) / position_scale_;
  }
  if (law_ != FrictionLawKind::kExact) return;
  // Total derivatives along the rotating wave, where ḋ = −Ω J2 d, of a contact quantity with
  // partial derivatives g_d, g_ḋ, added to `row` with weight `sign`.
  auto add_gradient = [&](Index row, Index k, const RowVector2& g_d, const RowVector2& g_ddot,
                          double sign) {
    const RubContact& c = structure_.contacts[k];
    const Index r = 2 * c.rotor, s = 2 * c.stator;
    const Vector2 d = p.segment<2>(r) - p.segment<2>(s);
    const RowVector2 along_d = sign * (g_d - W * g_ddot * rotate);
    J.block<1, 2>(row, r) += along_d;
    J.block<1, 2>(row, s) -= along_d;
    J(row, n2) -= sign * (g_ddot * rotate * d)(0);
  };
  const Index reference = ReferenceStick();
  for (Index k = 0; k < m; ++k) {
    const Index row = n2 + 1 + k;
    J.col(row).head(n2) = -forces_.d_dstick.col(k);
    const ContactEvaluation& e = forces_.contacts[k];
    switch (modes_[k]) {
      case ContactMode::kFree: J(row, row) = 1.0; break;
      case ContactMode::kStick:
        add_gradient(row, k, e.dV_dd, e.dV_dddot, 1.0);
        if (k != reference) {
          const ContactEvaluation& e0 = forces_.contacts[reference];
          add_gradient(row, reference, e0.dV_dd, e0.dV_dddot, -1.0);
        }
        break;
      case ContactMode::kSlipPositive:
      case ContactMode::kSlipNegative: {
        const double sign = modes_[k] == ContactMode::kSlipPositive ? 1.0 : -1.0;
        J(row, row) = 1.0;
        add_gradient(row, k, e.dN_dd, e.dN_dddot, -sign * structure_.law.friction);
        break;
      }
    }
  }
}

Index RotatingWaveProblem::ReferenceStick() const {
  if (law_ != FrictionLawKind::kExact) return -1;
  for (std::size_t k = 0; k < modes_.size(); ++k) {
    if (modes_[k] == ContactMode::kStick) return static_cast<Index>(k);
  }
  return -1;
}

void RotatingWaveProblem::DfDlambda(const Vector& u, double omega, Vector& dF) {
  const Index n2 = 2 * structure_.Coordinates();
  Evaluate(u, omega, true);
  dF.setZero(Dimension());
  dF.head(n2) = -forces_.d_domega;
  if (law_ != FrictionLawKind::kExact) return;
  const Index reference = ReferenceStick();
  for (Index k = 0; k < Contacts(); ++k) {
    if (modes_[k] == ContactMode::kStick) {  // ∂V/∂ω = R
      dF(n2 + 1 + k) = structure_.contacts[k].geometry.radius -
                       (k == reference ? 0.0 : structure_.contacts[reference].geometry.radius);
    }
  }
}

Vector RotatingWaveProblem::Scale() const {
  const Index n2 = 2 * structure_.Coordinates();
  Vector scale(Dimension());
  scale.head(n2).setConstant(position_scale_);
  scale(n2) = rate_scale_;
  if (law_ == FrictionLawKind::kExact) scale.tail(Contacts()).setConstant(force_scale_);
  return scale;
}

Vector RotatingWaveProblem::ResidualScale() const {
  const Index n2 = 2 * structure_.Coordinates();
  Vector scale(Dimension());
  scale.head(n2).setConstant(force_scale_);
  scale(n2) = 1.0;
  if (law_ == FrictionLawKind::kExact) {
    const Index reference = ReferenceStick();
    for (Index k = 0; k < Contacts(); ++k) {
      if (modes_[k] != ContactMode::kStick) {
        scale(n2 + 1 + k) = force_scale_;
      } else if (k == reference) {
        scale(n2 + 1 + k) = rate_scale_ * position_scale_;
      } else {  // V_k − V_ref = −Ω(δ_k − δ_ref) + ...: penetrations are ~ force / k1
        scale(n2 + 1 + k) = rate_scale_ * force_scale_ / structure_.law.stiffness;
      }
    }
  }
  return scale;
}

LyapunovCoefficient RotatingWaveProblem::FirstLyapunov(const Vector& u, double omega,
                                                       std::complex<double> critical) {
  if (law_ == FrictionLawKind::kExact) {
    LyapunovCoefficient out;
    out.message = "the exact law is not smooth (a sticking contact is a constraint, slip a switch "
                  "of the force law)";
    return out;
  }
  // The point's own contacts: free where it does not penetrate (the problem holds the modes of the
  // last piece it continued, which need not be the point's).
  const std::vector<ContactMode> last_modes = modes_;
  Evaluate(u, omega, false);
  for (Index k = 0; k < Contacts(); ++k) {
    modes_[k] = forces_.contacts[k].penetration < 0.0 ? ContactMode::kFree : ContactMode::kStick;
  }
  const std::vector<FrictionMode> point_modes = FrictionModes();
  modes_ = last_modes;
  const Index n2 = 2 * structure_.Coordinates();
  Vector x0 = Vector::Zero(2 * n2);
  x0.head(n2) = u.head(n2);
  frame_.set_frame_rate(u(n2));
  frame_.SetFrictionModes(point_modes, Vector::Zero(Contacts()));
  EquilibriumProblem field(frame_);  // the co-rotating field ẋ = f(x) at this Ω and ω
  const std::function<Vector(const Vector&)> generator = [this](const Vector& x) {
    Vector g(x.size());
    frame_.RotationGenerator(x, g);
    return g;
  };
  return FirstLyapunovCoefficientOfRelativeEquilibrium(field, x0, omega, generator, 1e-4,
                                                       critical);
}

Spectrum RotatingWaveProblem::Stability(const Vector& u, double omega) {
  const Index n2 = 2 * structure_.Coordinates();
  const Index N = 2 * n2;
  const double W = u(n2);
  Vector x = Vector::Zero(N);
  x.head(n2) = u.head(n2);
  const Vector stick_forces =
      law_ == FrictionLawKind::kExact ? Vector(u.tail(Contacts())) : Vector::Zero(Contacts());
  frame_.set_frame_rate(W);
  frame_.SetParameter(omega);
  frame_.SetFrictionModes(FrictionModes(), stick_forces);
  Matrix A(N, N);
  frame_.JacobianX(0.0, x, A);

  // Rolling constraints of the sticking contacts: H y = 0, multipliers F_k entering through G.
  std::vector<Index> sticking;
  if (law_ == FrictionLawKind::kExact) {
    for (Index k = 0; k < Contacts(); ++k) {
      if (modes_[k] == ContactMode::kStick) sticking.push_back(k);
    }
  }
  const Index ms = static_cast<Index>(sticking.size());
  Matrix H = Matrix::Zero(ms, N), G(N, ms);
  if (ms > 0) {
    Evaluate(u, omega, true);
    const Matrix G_all = frame_.StickForceJacobian();
    Matrix2 rotate;
    rotate << 0.0, -1.0, 1.0, 0.0;
    for (Index i = 0; i < ms; ++i) {
      const Index k = sticking[i];
      const ContactEvaluation& e = forces_.contacts[k];
      const RubContact& c = structure_.contacts[k];
      const Index r = 2 * c.rotor, s = 2 * c.stator;
      // V = ωR + tᵀ(ḋ − Ω j d): ∂V/∂d = dV_dd − Ω dV_dḋ J2, ∂V/∂ḋ = dV_dḋ
      const RowVector2 on_d = e.dV_dd - W * e.dV_dddot * rotate;
      H.block<1, 2>(i, r) += on_d;
      H.block<1, 2>(i, s) -= on_d;
      H.block<1, 2>(i, n2 + r) += e.dV_dddot;
      H.block<1, 2>(i, n2 + s) -= e.dV_dddot;
      G.col(i) = G_all.col(k);
    }
    A -= G * (H * G).partialPivLu().solve(H * A);
  }
  // Orthonormal basis Z of {y : H y = 0, gᵀ y = 0}, g = (j p, 0) the symmetry direction.
  Vector g = Vector::Zero(N);
  g.head(n2) = JTimes(u.head(n2));
  Matrix constraints(N, ms + 1);
  constraints.leftCols(ms) = H.transpose();
  constraints.col(ms) = g.normalized();
  const Eigen::HouseholderQR<Matrix> qr(constraints);
  const Matrix Q = qr.householderQ() * Matrix::Identity(N, N);
  const Matrix Z = Q.rightCols(N - ms - 1);
  const Matrix reduced = Z.transpose() * A * Z;

  Spectrum spectrum;
  spectrum.kind = SpectrumKind::kEigenvalues;
  ComplexVector values;
  if (!BalancedEigenvalues(reduced, values)) return spectrum;  // valid = false
  std::sort(values.data(), values.data() + values.size(),
            [](const std::complex<double>& a, const std::complex<double>& b) {
              return a.real() > b.real();
            });
  spectrum.values = values;
  spectrum.trivial_removed = 1;
  spectrum.valid = true;
  return spectrum;
}

std::vector<std::string> RotatingWaveProblem::MeasureNames() const {
  std::vector<std::string> names = {"precession_hz", "normal_phase_deg"};
  for (const char* quantity : {"normal_force_", "friction_force_", "slip_velocity_",
                               "penetration_", "mu_ratio_", "mode_"}) {
    for (const RubContact& c : structure_.contacts) names.push_back(quantity + c.name);
  }
  return names;
}

Vector RotatingWaveProblem::Measures(const Vector& u, double omega) {
  const Index n2 = 2 * structure_.Coordinates();
  const Index m = Contacts();
  Evaluate(u, omega, false);
  Vector out(2 + 6 * m);
  out(0) = RadPerSecondToHz(u(n2));
  out(1) = 0.0;
  if (m >= 2) {
    const std::complex<double> nL(forces_.contacts[0].normal.x(), forces_.contacts[0].normal.y());
    const std::complex<double> nR(forces_.contacts[1].normal.x(), forces_.contacts[1].normal.y());
    out(1) = std::arg(nR * std::conj(nL)) * 180.0 / kPi;
  }
  for (Index k = 0; k < m; ++k) {
    const ContactEvaluation& e = forces_.contacts[k];
    const double friction =
        law_ == FrictionLawKind::kExact ? (modes_[k] == ContactMode::kFree ? 0.0 : u(n2 + 1 + k))
                                        : e.friction_force;
    out(2 + k) = e.normal_force;
    out(2 + m + k) = friction;
    out(2 + 2 * m + k) = e.slip_velocity;
    out(2 + 3 * m + k) = e.penetration;
    out(2 + 4 * m + k) = e.normal_force > 0.0 ? friction / e.normal_force : kNaN;
    double code = 0.0;
    if (law_ == FrictionLawKind::kExact) {
      code = static_cast<double>(static_cast<int>(modes_[k]));
    } else if (e.touching) {
      code = e.slip_velocity >= 0.0 ? 2.0 : 3.0;
    }
    out(2 + 5 * m + k) = code;
  }
  return out;
}

std::vector<std::string> RotatingWaveProblem::EventNames() const {
  std::vector<std::string> names;
  for (std::size_t k = 0; k < modes_.size(); ++k) {
    const std::string& c = structure_.contacts[k].name;
    if (law_ == FrictionLawKind::kTanh) {
      names.insert(names.end(), {c + (modes_[k] == ContactMode::kFree ? " contact regain"
                                                                        : " contact loss"),
                                 c + " (inactive)", c + " (inactive)"});
      continue;
    }
    switch (modes_[k]) {
      case ContactMode::kFree:
        names.insert(names.end(), {c + " contact regain", c + " (inactive)", c + " (inactive)"});
        break;
      case ContactMode::kStick:
        names.insert(names.end(), {c + " contact loss", c + " stick to slip+",
                                   c + " stick to slip-"});
        break;
      case ContactMode::kSlipPositive:
      case ContactMode::kSlipNegative:
        names.insert(names.end(), {c + " contact loss", c + " slip to stick", c + " (inactive)"});
        break;
    }
  }
  return names;
}

double RotatingWaveProblem::Margin(Index k, int i) const {
  // Validity margins, positive while the contact's current mode is valid.
  const ContactEvaluation& e = forces_.contacts[k];
  const double mu_N = structure_.law.friction * e.normal_force;
  const double Fk = forces_.contacts[k].friction_force;
  const double delta = e.penetration / position_scale_;
  if (law_ == FrictionLawKind::kTanh) {
    if (i != 0) return 1.0;
    return modes_[k] == ContactMode::kFree ? -delta : delta;
  }
  switch (modes_[k]) {
    case ContactMode::kFree: return i == 0 ? -delta : 1.0;
    case ContactMode::kStick:
      if (i == 0) return delta;
      return (i == 1 ? mu_N - Fk : mu_N + Fk) / force_scale_;
    case ContactMode::kSlipPositive:
      if (i == 0) return delta;
      return i == 1 ? e.slip_velocity / (rate_scale_ * position_scale_) : 1.0;
    case ContactMode::kSlipNegative:
      if (i == 0) return delta;
      return i == 1 ? -e.slip_velocity / (rate_scale_ * position_scale_) : 1.0;
  }
  return 1.0;
}

Vector RotatingWaveProblem::EventFunctions(const Vector& u, double omega) {
  Evaluate(u, omega, false);
  Vector g(3 * Contacts());
  for (Index k = 0; k < Contacts(); ++k) {
    for (int i = 0; i < 3; ++i) g(3 * k + i) = Margin(k, i);
  }
  return g;
}

bool RotatingWaveProblem::SwitchAt(int event, Vector& u, double omega) {
  if (event < 0 || event >= 3 * Contacts()) return false;
  const Index k = event / 3;
  const int i = event % 3;
  Evaluate(u, omega, false);
  // Contacts in the same mode whose same margin vanishes here too switch with k (a symmetric
  // rotor's two contacts reach μ together); their margins are read before any mode changes.
  std::vector<Index> partners;
  for (Index j = 0; j < Contacts(); ++j) {
    if (j != k && modes_[j] == modes_[k] && std::abs(Margin(j, i)) <= kSimultaneousTolerance) {
      partners.push_back(j);
    }
  }
  if (!SwitchContact(k, i, u)) return false;
  for (Index j : partners) SwitchContact(j, i, u);
  return true;
}

bool RotatingWaveProblem::SwitchContact(Index k, int i, Vector& u) {
  const Index n2 = 2 * structure_.Coordinates();
  const ContactEvaluation& e = forces_.contacts[k];
  const double mu_N = structure_.law.friction * e.normal_force;
  ContactMode& mode = modes_[k];
  if (law_ == FrictionLawKind::kTanh) {
    // In contact, the regularized law needs no mode: slip± records the side V pointed to.
    if (i != 0) return false;
    mode = mode != ContactMode::kFree         ? ContactMode::kFree
           : e.slip_velocity >= 0.0 ? ContactMode::kSlipPositive
                                    : ContactMode::kSlipNegative;
    return true;
  }
  switch (mode) {
    case ContactMode::kFree:
      if (i != 0) return false;
      // A regained contact slips the way V points. Even beside a rolling contact it cannot
      // stick: V_k = 0 there needs the other contact's penetration, V_k ≈ Ω δ_other at δ_k = 0.
      mode = e.slip_velocity >= 0.0 ? ContactMode::kSlipPositive : ContactMode::kSlipNegative;
      u(n2 + 1 + k) = mode == ContactMode::kSlipPositive ? mu_N : -mu_N;
      return true;
    case ContactMode::kStick:
      if (i == 0) {
        mode = ContactMode::kFree;
        u(n2 + 1 + k) = 0.0;
      } else {
        mode = i == 1 ? ContactMode::kSlipPositive : ContactMode::kSlipNegative;
      }
      return true;
    case ContactMode::kSlipPositive:
    case ContactMode::kSlipNegative:
      if (i == 0) {
        mode = ContactMode::kFree;
        u(n2 + 1 + k) = 0.0;
        return true;
      }
      if (i == 1) {
        mode = ContactMode::kStick;
        return true;
      }
      return false;
  }
  return false;
}

std::string RotatingWaveProblem::PieceLabel() const {
  if (law_ != FrictionLawKind::kExact) {
    // "tanh" while every contact touches; the free ones named otherwise.
    std::string label = "tanh";
    for (std::size_t k = 0; k < modes_.size(); ++k) {
      if (modes_[k] == ContactMode::kFree) label += ' ' + structure_.contacts[k].name + ":free";
    }
    return label;
  }
  std::string label;
  for (std::size_t k = 0; k < modes_.size(); ++k) {
    if (!label.empty()) label += ' ';
    label += structure_.contacts[k].name + ':' + ToString(modes_[k]);
  }
  return label;
}

Vector RotatingWaveProblem::FromRigidContactOrbit(const RigidContactOrbit& orbit) {
  const Index n = structure_.Coordinates();
  Vector u = Vector::Zero(Dimension());
  for (Index i = 0; i < n; ++i) {
    u(2 * i) = orbit.amplitude[i].real();
    u(2 * i + 1) = orbit.amplitude[i].imag();
  }
  // The closed form has rigid contacts (|d_k| = C_k): move each rotor coordinate out along n_k by
  // the Hunt–Crossley penetration δ_k = N_k / k1 that carries the orbit's normal force, so that
  // Newton starts on the smooth side of the contact (at δ = 0 the force has a kink).
  for (Index k = 0; k < Contacts(); ++k) {
    const RubContact& c = structure_.contacts[k];
    const Vector2 d = u.segment<2>(2 * c.rotor) - u.segment<2>(2 * c.stator);
    const double normal_force = orbit.force[k].real();
    if (normal_force > 0.0 && d.norm() > 0.0) {
      u.segment<2>(2 * c.rotor) += d.normalized() * (normal_force / structure_.law.stiffness);
    }
  }
  u(2 * n) = orbit.precession;
  if (law_ == FrictionLawKind::kExact) {
    for (Index k = 0; k < Contacts(); ++k) {
      u(2 * n + 1 + k) = modes_[k] == ContactMode::kFree ? 0.0 : orbit.force[k].imag();
    }
  }
  SetPhaseReference(u);
  return u;
}

std::vector<std::string> RotatingWaveProblem::TestFunctionNames() const {
  std::vector<std::string> names;
  if (law_ != FrictionLawKind::kTanh) return names;
  for (const RubContact& c : structure_.contacts) names.push_back(c.name + " knee");
  return names;
}

Vector RotatingWaveProblem::TestFunctions(const Vector& u, double omega) {
  if (law_ != FrictionLawKind::kTanh) return Vector();
  // dΩ/dω along the branch from F_u du/dω = −F_ω (regular points; one extra LU per evaluation).
  Matrix J;
  Vector dF;
  Jacobian(u, omega, J);
  DfDlambda(u, omega, dF);
  const Vector du = J.partialPivLu().solve(-dF);
  const double slope = du(2 * structure_.Coordinates());
  Vector t(Contacts());
  for (Index k = 0; k < Contacts(); ++k) {
    const ContactGeometry& g = structure_.contacts[k].geometry;
    t(k) = slope * g.clearance / g.radius - 0.5;
  }
  return t;
}

void RotatingWaveProblem::PointAccepted(const Vector& u, double /*omega*/) { SetPhaseReference(u); }

void RotatingWaveProblem::SetPhaseReference(const Vector& u) {
  for (Index k = 0; k < Contacts(); ++k) {
    const RubContact& c = structure_.contacts[k];
    phase_reference_.segment<2>(2 * k) = u.segment<2>(2 * c.rotor) - u.segment<2>(2 * c.stator);
  }
  const double norm = phase_reference_.norm();
  if (!(norm > 0.0)) {
    throw std::invalid_argument("SetPhaseReference: every contact displacement is zero");
  }
  phase_reference_ /= norm;
}

void RotatingWaveProblem::SetModes(const std::vector<ContactMode>& modes) {
  if (modes.size() != modes_.size()) {
    throw std::invalid_argument(fmt::format("SetModes: {} modes for {} contacts", modes.size(),
                                            modes_.size()));
  }
  modes_ = modes;
}

RotatingWaveProblem::StartResult RotatingWaveProblem::SolveConsistent(
    Vector& u, double omega, const NewtonOptions& options) {
  StartResult result;
  const int max_rounds = 2 * static_cast<int>(Contacts()) + 1;
  for (int round = 0; round <= max_rounds; ++round) {
    result.newton = NewtonSolve([&](const Vector& x, Vector& F) { Residual(x, omega, F); },
                                [&](const Vector& x, Matrix& J) { Jacobian(x, omega, J); }, u,
                                options, Scale(), ResidualScale());
    if (!result.newton.Converged()) return result;
    // Switch every contact whose mode is violated at once (one at a time can cycle when the
    // contacts are coupled, e.g. both must start slipping together).
    Evaluate(u, omega, false);
    std::vector<int> violated;
    for (Index k = 0; k < Contacts(); ++k) {
      for (int i = 0; i < 3; ++i) {
        if (Margin(k, i) < -kMarginTolerance) {
          violated.push_back(static_cast<int>(3 * k + i));
          break;
        }
      }
    }
    if (violated.empty()) {
      result.consistent = true;
      return result;
    }
    for (int event : violated) {
      if (!SwitchAt(event, u, omega)) return result;
      ++result.mode_changes;
    }
  }
  return result;
}

std::vector<ContactMode> ModesAt(const Branch& branch, const SpecialPoint& point, Index contacts) {
  std::vector<ContactMode> modes;
  Index first = -1;
  for (std::size_t i = 0; i < branch.measure_names.size(); ++i) {
    if (branch.measure_names[i].rfind("mode_", 0) == 0) {
      first = static_cast<Index>(i);
      break;
    }
  }
  if (first < 0 || first + contacts > point.measures.size()) {
    throw std::invalid_argument("ModesAt: the branch has no contact-mode measures (mode_<contact>)");
  }
  for (Index k = 0; k < contacts; ++k) {
    switch (static_cast<int>(std::lround(point.measures(first + k)))) {
      case 0: modes.push_back(ContactMode::kFree); break;
      case 1: modes.push_back(ContactMode::kStick); break;
      case 2: modes.push_back(ContactMode::kSlipPositive); break;
      default: modes.push_back(ContactMode::kSlipNegative); break;
    }
  }
  return modes;
}

}  // namespace rubcont
