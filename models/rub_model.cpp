#include "models/rub_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/core.h>

#include "models/analytic.h"
#include "models/units.h"
#include "solvers/linear_algebra.h"

namespace rubcont {

void RubStructure::Validate() const {
  const Index n = mass.rows();
  if (mass.cols() != n || damping.rows() != n || damping.cols() != n || stiffness.rows() != n ||
      stiffness.cols() != n || imbalance_weights.size() != n) {
    throw std::invalid_argument(fmt::format(
        "RubStructure: M is {}×{}, C {}×{}, K {}×{}, imbalance_weights {}: all must match n_c = {}",
        mass.rows(), mass.cols(), damping.rows(), damping.cols(), stiffness.rows(),
        stiffness.cols(), imbalance_weights.size(), n));
  }
  if (gyroscopic.size() != 0 &&
      (gyroscopic.rows() != n || gyroscopic.cols() != n ||
       !(gyroscopic - gyroscopic.transpose()).isZero(1e-12 * gyroscopic.norm()))) {
    throw std::invalid_argument(fmt::format(
        "RubStructure: the gyroscopic matrix is {}×{}: must be empty or symmetric {}×{}",
        gyroscopic.rows(), gyroscopic.cols(), n, n));
  }
  if (!(mass - mass.transpose()).isZero(1e-12 * mass.norm())) {
    throw std::invalid_argument("RubStructure: mass matrix must be symmetric");
  }
  if (Eigen::LLT<Matrix>(mass).info() != Eigen::Success) {
    throw std::invalid_argument("RubStructure: mass matrix must be positive definite");
  }
  for (const RubContact& contact : contacts) {
    if (contact.rotor < 0 || contact.rotor >= n || contact.stator < 0 || contact.stator >= n ||
        contact.rotor == contact.stator) {
      throw std::invalid_argument(fmt::format(
          "RubStructure: contact '{}' joins coordinates {} and {}: need two distinct indices in "
          "[0, {})", contact.name, contact.rotor, contact.stator, n));
    }
  }
}

std::vector<Index> ContactExchange(const RubStructure& structure) {
  if (structure.contacts.size() != 2) return {};
  const RubContact& a = structure.contacts[0];
  const RubContact& b = structure.contacts[1];
  const Index n = structure.Coordinates();
  std::vector<Index> exchange(static_cast<std::size_t>(n));
  for (Index c = 0; c < n; ++c) exchange[c] = c;
  const std::pair<int, int> pairs[] = {{a.rotor, b.rotor}, {a.stator, b.stator}};
  for (const auto& [i, j] : pairs) {
    if (i == j || exchange[i] != i || exchange[j] != j) return {};  // shared coordinates
    exchange[i] = j;
    exchange[j] = i;
  }
  const auto invariant = [&](const Matrix& m) {
    Matrix p(n, n);
    for (Index i = 0; i < n; ++i) {
      for (Index j = 0; j < n; ++j) p(i, j) = m(exchange[i], exchange[j]);
    }
    return (p - m).norm() <= 1e-12 * m.norm();
  };
  Vector weights(n);
  for (Index i = 0; i < n; ++i) weights(i) = structure.imbalance_weights(exchange[i]);
  const bool same_geometry = a.geometry.clearance == b.geometry.clearance &&
                             a.geometry.radius == b.geometry.radius;
  if (!same_geometry || !invariant(structure.mass) || !invariant(structure.damping) ||
      !invariant(structure.stiffness) ||
      (structure.gyroscopic.size() != 0 && !invariant(structure.gyroscopic)) ||
      (structure.imbalance != 0.0 &&
       !((weights - structure.imbalance_weights).norm() <=
         1e-12 * structure.imbalance_weights.norm()))) {
    return {};
  }
  return exchange;
}

RubStructure TwoPointStructure(const TwoPointParams& p) {
  RubStructure s;
  const Matrix M_r = RotorMassMatrix(p);
  const Matrix M_s = StatorMassMatrix(p);
  s.mass = Matrix::Zero(4, 4);
  s.mass.topLeftCorner(2, 2) = M_r;
  s.mass.bottomRightCorner(2, 2) = M_s;
  s.stiffness = Matrix::Zero(4, 4);
  s.stiffness(2, 2) = p.support_stiffness[0];
  s.stiffness(3, 3) = p.support_stiffness[1];
  s.damping = Matrix::Zero(4, 4);
  s.damping(2, 2) = p.support_damping[0];
  s.damping(3, 3) = p.support_damping[1];
  const Eigen::Vector4d w(0.5, 0.5, -0.5, -0.5);  // centre damper: mid-point relative motion
  s.damping += p.center_damping * w * w.transpose();
  s.imbalance_weights = Eigen::Vector4d(1.0 - p.a(), p.a(), 0.0, 0.0);
  s.imbalance = p.imbalance;
  s.law = ContactLawOf(p);
  s.contacts = {RubContact{0, 2, {p.clearance[0], p.radius[0]}, "left"},
                RubContact{1, 3, {p.clearance[1], p.radius[1]}, "right"}};
  s.coordinate_names = {"rotor_left", "rotor_right", "stator_left", "stator_right"};
  s.Validate();
  return s;
}

void EvaluateContactForces(const RubStructure& structure, double omega, ConstVectorRef q,
                           ConstVectorRef v, const std::vector<FrictionMode>& modes,
                           const Vector& stick_forces, bool with_derivatives, ContactForces& out) {
  const Index n2 = 2 * structure.Coordinates();
  const Index m = static_cast<Index>(structure.contacts.size());
  out.generalized.setZero(n2);
  out.contacts.resize(m);
  if (with_derivatives) {
    out.d_dq.setZero(n2, n2);
    out.d_dv.setZero(n2, n2);
    out.d_domega.setZero(n2);
    out.d_dstick.setZero(n2, m);
  }
  for (Index k = 0; k < m; ++k) {
    const RubContact& contact = structure.contacts[k];
    const Index r = 2 * contact.rotor;
    const Index s = 2 * contact.stator;
    const Vector2 d = q.segment<2>(r) - q.segment<2>(s);
    const Vector2 ddot = v.segment<2>(r) - v.segment<2>(s);
    const double stick_force = stick_forces.size() > k ? stick_forces(k) : 0.0;
    ContactEvaluation& e = out.contacts[k];
    EvaluateContact(structure.law, contact.geometry, omega, d, ddot, modes[k], stick_force,
                    with_derivatives, e);
    if (!e.touching) continue;
    out.generalized.segment<2>(r) += e.force;
    out.generalized.segment<2>(s) -= e.force;
    if (!with_derivatives) continue;
    // d = q_r − q_s: ∂f/∂q_r = ∂f/∂d, ∂f/∂q_s = −∂f/∂d; rotor rows get +f, stator rows −f.
    out.d_dq.block<2, 2>(r, r) += e.df_dd;
    out.d_dq.block<2, 2>(r, s) -= e.df_dd;
    out.d_dq.block<2, 2>(s, r) -= e.df_dd;
    out.d_dq.block<2, 2>(s, s) += e.df_dd;
    out.d_dv.block<2, 2>(r, r) += e.df_dddot;
    out.d_dv.block<2, 2>(r, s) -= e.df_dddot;
    out.d_dv.block<2, 2>(s, r) -= e.df_dddot;
    out.d_dv.block<2, 2>(s, s) += e.df_dddot;
    out.d_domega.segment<2>(r) += e.df_domega;
    out.d_domega.segment<2>(s) -= e.df_domega;
    out.d_dstick.block<2, 1>(r, k) += e.df_dF;
    out.d_dstick.block<2, 1>(s, k) -= e.df_dF;
  }
}

RigidContactOrbit SolveRigidContactOrbit(const RubStructure& structure, double precession,
                                 const std::vector<std::complex<double>>& normals) {
  using Complex = std::complex<double>;
  const Index n = structure.Coordinates();
  const Index m = static_cast<Index>(structure.contacts.size());
  if (static_cast<Index>(normals.size()) != m) {
    throw std::invalid_argument(fmt::format(
        "SolveRigidContactOrbit: {} normals given for {} contacts", normals.size(), m));
  }
  if (!(precession > 0.0)) {
    throw std::invalid_argument(
        fmt::format("SolveRigidContactOrbit: precession = {}: must be positive", precession));
  }
  // [D  B diag(n)] [u0]   [0  ]      D = K − Ω²M − jΩC, f_k = −P_k n_k
  // [Bᵀ 0        ] [P ] = [C n]
  const double W = precession;
  ComplexMatrix A = ComplexMatrix::Zero(n + m, n + m);
  A.topLeftCorner(n, n) = (structure.stiffness - W * W * structure.mass).cast<Complex>() -
                          Complex(0.0, W) * structure.damping.cast<Complex>();
  ComplexVector rhs = ComplexVector::Zero(n + m);
  for (Index k = 0; k < m; ++k) {
    if (normals[k] == 0.0) {  // contact k not touching: no force, no constraint (P_k = 0)
      A(n + k, n + k) = 1.0;
      continue;
    }
    const RubContact& c = structure.contacts[k];
    const Complex nk = normals[k] / std::abs(normals[k]);
    A(c.rotor, n + k) += nk;
    A(c.stator, n + k) -= nk;
    A(n + k, c.rotor) = 1.0;
    A(n + k, c.stator) = -1.0;
    rhs(n + k) = c.geometry.clearance * nk;
  }
  // Every pivot counts (threshold 0): with a flexible model's stiff modal coordinates (|D| to
  // 1e15 against constraint entries of 1) the default threshold took the constraint rows' pivots
  // for zeros and returned forces of 0.
  Eigen::FullPivLU<ComplexMatrix> lu(A);
  lu.setThreshold(0.0);
  const ComplexVector solution = lu.solve(rhs);
  RigidContactOrbit orbit;
  orbit.precession = precession;
  for (Index i = 0; i < n; ++i) orbit.amplitude.push_back(solution(i));
  for (Index k = 0; k < m; ++k) orbit.force.push_back(solution(n + k));
  return orbit;
}

RubFixedFrame::RubFixedFrame(RubStructure structure, double omega)
    : structure_(std::move(structure)), omega_(omega) {
  structure_.Validate();
  mass_inverse_ = KronIdentity2(structure_.mass.inverse());
  damping_ = KronIdentity2(structure_.damping);
  stiffness_ = KronIdentity2(structure_.stiffness);
  const Matrix mass_inverse = structure_.mass.inverse();
  small_mass_inverse_transpose_ = mass_inverse.transpose();
  small_damping_rate_transpose_ = (mass_inverse * structure_.damping).transpose();
  small_stiffness_rate_transpose_ = (mass_inverse * structure_.stiffness).transpose();
  if (structure_.gyroscopic.size() != 0 && !structure_.gyroscopic.isZero(0.0)) {
    const Index n = structure_.Coordinates();
    gyroscopic_ = Matrix::Zero(2 * n, 2 * n);
    for (Index i = 0; i < n; ++i) {
      for (Index j = 0; j < n; ++j) {
        gyroscopic_(2 * i, 2 * j + 1) = -structure_.gyroscopic(i, j);
        gyroscopic_(2 * i + 1, 2 * j) = structure_.gyroscopic(i, j);
      }
    }
    small_gyroscopic_rate_transpose_ = (mass_inverse * structure_.gyroscopic).transpose();
  }
  modes_.assign(structure_.contacts.size(), FrictionMode::kRegularized);
  stick_forces_.setZero(static_cast<Index>(structure_.contacts.size()));
  load_.resize(2, structure_.Coordinates());
  exchange_ = ContactExchange(structure_);
  // The contact chart needs a stator coordinate per contact that no other contact uses.
  chart_ = !structure_.contacts.empty();
  std::vector<int> used;
  for (const RubContact& c : structure_.contacts) used.push_back(c.rotor);
  for (const RubContact& c : structure_.contacts) {
    if (std::find(used.begin(), used.end(), c.stator) != used.end()) chart_ = false;
    used.push_back(c.stator);
  }
}

void RubFixedFrame::ToChart(ConstVectorRef x, VectorRef y) const {
  y = x;
  if (!chart_) return;
  const Index v = 2 * structure_.Coordinates();  // the velocities' offset
  for (const RubContact& c : structure_.contacts) {
    const Index r = 2 * c.rotor, s = 2 * c.stator;
    const double dx = x(r) - x(s), dy = x(r + 1) - x(s + 1);
    const double angle = std::atan2(dy, dx);
    const double cos_a = std::cos(angle), sin_a = std::sin(angle);
    const double dvx = x(v + r) - x(v + s), dvy = x(v + r + 1) - x(v + s + 1);
    y(s) = std::hypot(dx, dy) - c.geometry.clearance;
    y(s + 1) = angle;
    y(v + s) = cos_a * dvx + sin_a * dvy;    // n·ḋ: the gap's rate
    y(v + s + 1) = -sin_a * dvx + cos_a * dvy;  // t·ḋ
  }
}

void RubFixedFrame::FromChart(ConstVectorRef y, VectorRef x, Matrix* jacobian) const {
  x = y;
  if (jacobian) jacobian->setIdentity(Dimension(), Dimension());
  if (!chart_) return;
  const Index v = 2 * structure_.Coordinates();
  for (const RubContact& c : structure_.contacts) {
    const Index r = 2 * c.rotor, s = 2 * c.stator;
    const double radius = c.geometry.clearance + y(s), angle = y(s + 1);
    const double cos_a = std::cos(angle), sin_a = std::sin(angle);
    const double rate = y(v + s), along = y(v + s + 1);
    // u_stator = u_rotor − (C + r) n, u̇_stator = u̇_rotor − (ṙ n + w t), n = e^{jα}, t = j n.
    x(s) = y(r) - radius * cos_a;
    x(s + 1) = y(r + 1) - radius * sin_a;
    x(v + s) = y(v + r) - (rate * cos_a - along * sin_a);
    x(v + s + 1) = y(v + r + 1) - (rate * sin_a + along * cos_a);
    if (!jacobian) continue;
    Matrix& J = *jacobian;
    J(s, s) = -cos_a;
    J(s + 1, s) = -sin_a;
    J(s, s + 1) = radius * sin_a;
    J(s + 1, s + 1) = -radius * cos_a;
    J(s, r) = 1.0;
    J(s + 1, r + 1) = 1.0;
    J(v + s, v + s) = -cos_a;
    J(v + s + 1, v + s) = -sin_a;
    J(v + s, v + s + 1) = sin_a;
    J(v + s + 1, v + s + 1) = -cos_a;
    J(v + s, s + 1) = rate * sin_a + along * cos_a;
    J(v + s + 1, s + 1) = -rate * cos_a + along * sin_a;
    J(v + s, v + r) = 1.0;
    J(v + s + 1, v + r + 1) = 1.0;
  }
}

Vector RubFixedFrame::ChartScale() const {
  Vector scale = StateScale();
  if (!chart_) return scale;
  for (const RubContact& c : structure_.contacts) {
    scale(2 * c.stator) = 1e-3 * c.geometry.clearance;
    scale(2 * c.stator + 1) = 1.0;
  }
  return scale;
}

std::vector<Index> RubFixedFrame::ChartAngles() const {
  std::vector<Index> angles;
  if (!chart_) return angles;
  for (const RubContact& c : structure_.contacts) angles.push_back(2 * c.stator + 1);
  return angles;
}

void RubFixedFrame::Rhs(double t, ConstVectorRef x, VectorRef f) {
  if (structure_.Coordinates() == 4) {
    Evaluate<4>(t, x.data(), f.data());  // the two-point rotor: fixed sizes, unrolled
  } else {
    Evaluate<Eigen::Dynamic>(t, x.data(), f.data());
  }
}

template <int N>
void RubFixedFrame::Evaluate(double t, const double* x, double* f) {
  // Allocation-free and in the n × n coordinates (the 2n × 2n matrices are kron(·, I₂)): explicit
  // sweeps call it millions of times per simulated second. Positions, velocities and loads as
  // 2 × n matrices (column i: the x and y components of coordinate i), so M⁻¹ load = L M⁻ᵀ.
  using Rows = Eigen::Matrix<double, 2, N>;
  const Index n = structure_.Coordinates();
  const Index n2 = 2 * n;
  Rows fixed_load;  // the loads on the stack for a fixed size (empty for Eigen::Dynamic: load_)
  Eigen::Map<Rows> load(N == Eigen::Dynamic ? load_.data() : fixed_load.data(), 2, n);
  if (regularized_) {
    // Time marching: the contact forces alone (RegularizedContactForce: EvaluateContactForces'
    // loads bit for bit, at a fifth of its cost on A(a): bench/march_bench.cpp).
    load.setZero();
    for (const RubContact& contact : structure_.contacts) {
      const Index r = 2 * contact.rotor, s = 2 * contact.stator;
      const Vector2 d(x[r] - x[s], x[r + 1] - x[s + 1]);
      const Vector2 ddot(x[n2 + r] - x[n2 + s], x[n2 + r + 1] - x[n2 + s + 1]);
      Vector2 force;
      if (!RegularizedContactForce(structure_.law, contact.geometry, omega_, d, ddot, force)) continue;
      load.col(contact.rotor) += force;
      load.col(contact.stator) -= force;
    }
  } else {
    const Eigen::Map<const Vector> state(x, 2 * n2);
    EvaluateContactForces(structure_, omega_, state.head(n2), state.tail(n2), modes_, stick_forces_,
                          false, forces_);
    load = Eigen::Map<const Rows>(forces_.generalized.data(), 2, n);
  }
  if (structure_.imbalance != 0.0) {
    const double amplitude = structure_.imbalance * omega_ * omega_;
    const double c = std::cos(omega_ * t), s = std::sin(omega_ * t);
    for (Index i = 0; i < n; ++i) {
      load(0, i) += amplitude * structure_.imbalance_weights(i) * c;
      load(1, i) += amplitude * structure_.imbalance_weights(i) * s;
    }
  }
  Accelerations<N>(x, load.data(), f + n2);
  // ẋ's positions are the velocities (a fixed-size copy for a fixed N: no call to memmove).
  Eigen::Map<Rows>(f, 2, n) = Eigen::Map<const Rows>(x + n2, 2, n);
}

// Inlined into Evaluate: the call and a memmove of the velocities were 4 % of A(a)'s marching CPU
// (bench/march_bench.cpp).
template <int N>
EIGEN_ALWAYS_INLINE void RubFixedFrame::Accelerations(const double* x, const double* loads,
                                                      double* acceleration) const {
  using Small = Eigen::Matrix<double, N, N>;
  using Rows = Eigen::Matrix<double, 2, N>;
  const Index n = structure_.Coordinates();
  const Eigen::Map<const Rows> q(x, 2, n), v(x + 2 * n, 2, n), load(loads, 2, n);
  const Eigen::Map<const Small> m(small_mass_inverse_transpose_.data(), n, n);
  const Eigen::Map<const Small> c(small_damping_rate_transpose_.data(), n, n);
  const Eigen::Map<const Small> k(small_stiffness_rate_transpose_.data(), n, n);
  Eigen::Map<Rows> a(acceleration, 2, n);
  a.noalias() = load.lazyProduct(m) - v.lazyProduct(c) - q.lazyProduct(k);
  if (gyroscopic_.size() != 0) {  // jωG u̇ = ωG(−v_y + j v_x)
    const Eigen::Map<const Small> g(small_gyroscopic_rate_transpose_.data(), n, n);
    a.row(0).noalias() -= omega_ * v.row(1).lazyProduct(g);
    a.row(1).noalias() += omega_ * v.row(0).lazyProduct(g);
  }
}

void RubFixedFrame::JacobianX(double /*t*/, ConstVectorRef x, MatrixRef J) {
  const Index n2 = 2 * structure_.Coordinates();
  EvaluateContactForces(structure_, omega_, x.head(n2), x.tail(n2), modes_, stick_forces_, true,
                        forces_);
  J.setZero();
  J.topRightCorner(n2, n2).setIdentity();
  J.bottomLeftCorner(n2, n2).noalias() = mass_inverse_ * (forces_.d_dq - stiffness_);
  J.bottomRightCorner(n2, n2).noalias() = mass_inverse_ * (forces_.d_dv - damping_);
  if (gyroscopic_.size() != 0) {
    J.bottomRightCorner(n2, n2).noalias() += omega_ * mass_inverse_ * gyroscopic_;
  }
}

void RubFixedFrame::DfDparameter(double t, ConstVectorRef x, VectorRef df) {
  const Index n2 = 2 * structure_.Coordinates();
  EvaluateContactForces(structure_, omega_, x.head(n2), x.tail(n2), modes_, stick_forces_, true,
                        forces_);
  Vector load = forces_.d_domega;
  if (structure_.imbalance != 0.0) {
    // ∂/∂ω [m_u e ω² (cos ωt, sin ωt)] = m_u e (2ω (cos, sin) + ω² t (−sin, cos))
    const double c = std::cos(omega_ * t), s = std::sin(omega_ * t);
    const double me = structure_.imbalance;
    for (Index i = 0; i < structure_.Coordinates(); ++i) {
      const double b = structure_.imbalance_weights(i);
      load(2 * i) += me * b * (2.0 * omega_ * c - omega_ * omega_ * t * s);
      load(2 * i + 1) += me * b * (2.0 * omega_ * s + omega_ * omega_ * t * c);
    }
  }
  if (gyroscopic_.size() != 0) load.noalias() += gyroscopic_ * x.tail(n2);
  df.head(n2).setZero();
  df.tail(n2).noalias() = mass_inverse_ * load;
}

void RubFixedFrame::SwitchingFunctions(double /*t*/, ConstVectorRef x, VectorRef h) const {
  for (std::size_t c = 0; c < structure_.contacts.size(); ++c) {
    const RubContact& contact = structure_.contacts[c];
    const Index r = 2 * contact.rotor, s = 2 * contact.stator;
    h(static_cast<Index>(c)) =
        std::hypot(x(r) - x(s), x(r + 1) - x(s + 1)) - contact.geometry.clearance;
  }
}

bool RubFixedFrame::SwitchingIncrementBounds(double /*t*/, ConstVectorRef x, ConstVectorRef f,
                                             double s, VectorRef bound) const {
  // h_k = |d| − C along d + s ḋ (ḋ = the positions' entries of f):
  //   |d + s ḋ| − |d| = (2 s d·ḋ + s² |ḋ|²) / (|d + s ḋ| + |d|),  |d + s ḋ| ≥ |d| − s |ḋ|,
  // so |Δh| ≤ (2 s |d·ḋ| + s² |ḋ|²) / (2|d| − s|ḋ|) while s|ḋ| < |d|/2 (else s|ḋ|, h being
  // 1-Lipschitz in d). The first is the radial motion's: a contact whirling closed (|ḋ| ≈ 0.1 m/s
  // tangential, δ a few nm) moves h by s δ̇, not s |ḋ|. The rounding of x + s f, of d's differences
  // and of hypot stays within a few ulps of the positions, |d| and C: 64 ulps of their sum covers
  // it with room, and 1e-10 the relative rounding of this bound (the integrator doubles it again).
  constexpr double kUlp = std::numeric_limits<double>::epsilon();
  for (std::size_t c = 0; c < structure_.contacts.size(); ++c) {
    const RubContact& contact = structure_.contacts[c];
    const Index r = 2 * contact.rotor, q = 2 * contact.stator;
    const double dx = x(r) - x(q), dy = x(r + 1) - x(q + 1);
    const double vx = f(r) - f(q), vy = f(r + 1) - f(q + 1);
    const double rho = std::sqrt(dx * dx + dy * dy);
    const double travel = s * std::sqrt(vx * vx + vy * vy);
    const double change =
        travel < 0.5 * rho ? (2.0 * s * std::abs(dx * vx + dy * vy) + travel * travel) / (2.0 * rho - travel)
                           : travel;
    const double size = std::abs(x(r)) + std::abs(x(r + 1)) + std::abs(x(q)) + std::abs(x(q + 1)) +
                        travel + contact.geometry.clearance;
    bound(static_cast<Index>(c)) = change * (1.0 + 1e-10) + 64.0 * kUlp * size;
  }
  return true;
}

Vector RubFixedFrame::StateScale() const {
  // Positions scale with the largest clearance; velocities with clearance × the fastest
  // undamped frequency of the structure with the contacts pinned (or 2π·100 rad/s when free).
  double clearance = 0.0;
  for (const RubContact& c : structure_.contacts) {
    clearance = std::max(clearance, c.geometry.clearance);
  }
  if (clearance == 0.0) clearance = 1e-3;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Matrix> modes(structure_.stiffness,
                                                               structure_.mass,
                                                               Eigen::EigenvaluesOnly);
  const double fastest = std::sqrt(std::max(modes.eigenvalues().maxCoeff(), 0.0));
  const double rate = fastest > 0.0 ? fastest : HzToRadPerSecond(100.0);
  const Index n2 = 2 * structure_.Coordinates();
  Vector scale(2 * n2);
  scale.head(n2).setConstant(clearance);
  scale.tail(n2).setConstant(clearance * rate);
  return scale;
}

double RubFixedFrame::ForcingPeriod() const {
  return structure_.imbalance != 0.0 && omega_ > 0.0 ? kTwoPi / omega_ : 0.0;
}

void RubFixedFrame::Rotate(double phi, VectorRef x) const {
  const double c = std::cos(phi), s = std::sin(phi);
  for (Index i = 0; i + 1 < x.size(); i += 2) {
    const double a = x(i), b = x(i + 1);
    x(i) = c * a - s * b;
    x(i + 1) = s * a + c * b;
  }
}

void RubFixedFrame::RotationGenerator(ConstVectorRef x, VectorRef g) const {
  for (Index i = 0; i + 1 < x.size(); i += 2) {
    g(i) = -x(i + 1);
    g(i + 1) = x(i);
  }
}

void RubFixedFrame::Mirror(VectorRef x) const {
  const Index n = structure_.Coordinates();
  const Vector y = x;
  for (Index half = 0; half < 2; ++half) {  // positions, then velocities
    for (Index c = 0; c < n; ++c) {
      x.segment(2 * (half * n + c), 2) = y.segment(2 * (half * n + exchange_[c]), 2);
    }
  }
}

std::vector<ContactEvaluation> RubFixedFrame::Contacts(ConstVectorRef x) {
  const Index n2 = 2 * structure_.Coordinates();
  EvaluateContactForces(structure_, omega_, x.head(n2), x.tail(n2), modes_, stick_forces_, false,
                        forces_);
  return forces_.contacts;
}

void RubFixedFrame::SetFrictionModes(std::vector<FrictionMode> modes, Vector stick_forces) {
  const std::size_t m = structure_.contacts.size();
  if (modes.size() != m || static_cast<std::size_t>(stick_forces.size()) != m) {
    throw std::invalid_argument(fmt::format(
        "SetFrictionModes: {} modes and {} stick forces for {} contacts", modes.size(),
        stick_forces.size(), m));
  }
  modes_ = std::move(modes);
  stick_forces_ = std::move(stick_forces);
  regularized_ = std::all_of(modes_.begin(), modes_.end(),
                             [](FrictionMode mode) { return mode == FrictionMode::kRegularized; });
}

Matrix RubFixedFrame::StickForceJacobian() const {
  const Index n2 = 2 * structure_.Coordinates();
  Matrix G = Matrix::Zero(2 * n2, static_cast<Index>(structure_.contacts.size()));
  G.bottomRows(n2).noalias() = mass_inverse_ * forces_.d_dstick;
  return G;
}

RubRotatingFrame::RubRotatingFrame(RubStructure structure, double frame_rate, double omega)
    : fixed_(std::move(structure), omega), frame_rate_(frame_rate) {
  if (fixed_.structure().imbalance != 0.0) {
    throw std::invalid_argument(fmt::format(
        "RubRotatingFrame: imbalance = {} kg·m: the rotating frame needs rotational symmetry "
        "(imbalance 0); integrate an imbalanced rotor in the fixed frame",
        fixed_.structure().imbalance));
  }
  fixed_state_.resize(fixed_.Dimension());
  fixed_jacobian_.resize(fixed_.Dimension(), fixed_.Dimension());
}

void RubRotatingFrame::LoadFixedState(ConstVectorRef x) {
  const Index n2 = x.size() / 2;
  const double W = frame_rate_;
  fixed_state_.head(n2) = x.head(n2);
  for (Index i = 0; i < n2; i += 2) {  // w = ṗ − jΩ p
    fixed_state_(n2 + i) = x(n2 + i) + W * x(i + 1);
    fixed_state_(n2 + i + 1) = x(n2 + i + 1) - W * x(i);
  }
}

void RubRotatingFrame::Rhs(double t, ConstVectorRef x, VectorRef f) {
  // p̈ = a(p, ṗ − jΩ p) + 2jΩ ṗ + Ω² p
  const Index n2 = x.size() / 2;
  const double W = frame_rate_;
  LoadFixedState(x);
  fixed_.Rhs(t, fixed_state_, f);  // f = [w; a]
  f.head(n2) = x.tail(n2);
  for (Index i = 0; i < n2; i += 2) {
    f(n2 + i) += -2.0 * W * x(n2 + i + 1) + W * W * x(i);
    f(n2 + i + 1) += 2.0 * W * x(n2 + i) + W * W * x(i + 1);
  }
}

void RubRotatingFrame::JacobianX(double t, ConstVectorRef x, MatrixRef J) {
  // ∂p̈/∂p = a_q − Ω a_v J + Ω² I,  ∂p̈/∂ṗ = a_v + 2Ω J  (J: multiplication by j on each pair)
  const Index n2 = x.size() / 2;
  const double W = frame_rate_;
  LoadFixedState(x);
  fixed_.JacobianX(t, fixed_state_, fixed_jacobian_);
  const auto a_q = fixed_jacobian_.bottomLeftCorner(n2, n2);
  const auto a_v = fixed_jacobian_.bottomRightCorner(n2, n2);
  J.setZero();
  J.topRightCorner(n2, n2).setIdentity();
  auto dp = J.bottomLeftCorner(n2, n2);
  auto dv = J.bottomRightCorner(n2, n2);
  dp = a_q;
  dv = a_v;
  for (Index i = 0; i < n2; i += 2) {
    // column pair (i, i+1): a_v J has columns (a_v e_{i+1}, −a_v e_i)
    dp.col(i) -= W * a_v.col(i + 1);
    dp.col(i + 1) += W * a_v.col(i);
    dp(i, i) += W * W;
    dp(i + 1, i + 1) += W * W;
    dv(i + 1, i) += 2.0 * W;
    dv(i, i + 1) -= 2.0 * W;
  }
}

void RubRotatingFrame::DfDparameter(double t, ConstVectorRef x, VectorRef df) {
  LoadFixedState(x);
  fixed_.DfDparameter(t, fixed_state_, df);
}

Vector RubRotatingFrame::ToFixedFrame(double t, ConstVectorRef x) const {
  const Index n2 = x.size() / 2;
  const double W = frame_rate_;
  Vector u(x.size());
  for (Index i = 0; i < n2; i += 2) {
    u(i) = x(i);
    u(i + 1) = x(i + 1);
    u(n2 + i) = x(n2 + i) + W * x(i + 1);
    u(n2 + i + 1) = x(n2 + i + 1) - W * x(i);
  }
  fixed_.Rotate(-W * t, u);
  return u;
}

Vector RubRotatingFrame::ToRotatingFrame(double t, ConstVectorRef u) const {
  const Index n2 = u.size() / 2;
  const double W = frame_rate_;
  Vector x = u;
  fixed_.Rotate(W * t, x);
  for (Index i = 0; i < n2; i += 2) {
    x(n2 + i) -= W * x(i + 1);
    x(n2 + i + 1) += W * x(i);
  }
  return x;
}

}  // namespace rubcont
