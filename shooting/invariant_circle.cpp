#include "shooting/invariant_circle.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "solvers/constants.h"
#include "solvers/finite_difference.h"
#include "solvers/linear_algebra.h"

namespace rubcont {

namespace {

// CircleFromOrbit: a fitted circle is taken as covered q times where the harmonics that are not
// multiples of q stay below this share of the largest multiple's.
constexpr double kCoverRatio = 0.05;
// CircleFromOrbit: passes of its grid search for ρ. Four passes fit a curve known exactly within
// 5e-6 of its size instead of 3e-4 (tests/shooting/invariant_circle_test.cpp), but left C(c)'s
// first circle at 64 rpm as far from invariant (residual 3.47e-3 against 3.37e-3) and C(a)'s at
// 49 rpm, K = 16, out of Newton's reach (|F| 1.1e-5 after 30 iterations; it converges in 19 from
// two passes' circle): the misfit's least is no better a start.
constexpr int kRhoGridPasses = 2;

// The extremum (sign = +1: maximum, −1: minimum) of the quadratic through a 3 × 3 stencil
// f[a][b] at ((a − 1) hx, (b − 1) hy), whose centre is the extreme sample: its value where the
// quadratic has an extremum of that sign within one spacing of the centre, else f[1][1].
double QuadraticExtremum(const double f[3][3], double hx, double hy, double sign) {
  const double b = f[1][1];
  const double gx = (f[2][1] - f[0][1]) / (2.0 * hx), gy = (f[1][2] - f[1][0]) / (2.0 * hy);
  const double hxx = (f[2][1] - 2.0 * b + f[0][1]) / (hx * hx);
  const double hyy = (f[1][2] - 2.0 * b + f[1][0]) / (hy * hy);
  const double hxy = (f[2][2] - f[2][0] - f[0][2] + f[0][0]) / (4.0 * hx * hy);
  const double det = hxx * hyy - hxy * hxy;
  if (!(sign * hxx < 0.0 && det > 0.0)) return b;  // not definite of the extremum's sign
  // δ = −H⁻¹ g.
  const double dx = -(hyy * gx - hxy * gy) / det, dy = -(hxx * gy - hxy * gx) / det;
  if (!(std::abs(dx) <= hx && std::abs(dy) <= hy)) return b;
  return b + 0.5 * (gx * dx + gy * dy);
}

}  // namespace

const char* ToString(CircleCoordinates coordinates) {
  return coordinates == CircleCoordinates::kChart ? "chart" : "state";
}

InvariantCircleProblem::InvariantCircleProblem(std::shared_ptr<OdeSystem> system, int harmonics,
                                               OrbitKind kind, const IntegratorOptions& options,
                                               CircleCoordinates coordinates)
    : system_(std::move(system)), harmonics_(harmonics), kind_(kind), options_(options) {
  if (!system_) throw std::invalid_argument("InvariantCircleProblem: no system");
  if (harmonics < 1 || harmonics > 500) {
    throw std::invalid_argument(
        fmt::format("InvariantCircleProblem: harmonics = {}: must be in 1 … 500", harmonics));
  }
  const bool forced = system_->ForcingPeriod() > 0.0;
  if (kind_ == OrbitKind::kForced && !forced) {
    throw std::invalid_argument(
        "InvariantCircleProblem: the system is not forced (ForcingPeriod() = 0): the stroboscopic "
        "map needs a forcing period");
  }
  if (kind_ != OrbitKind::kForced && forced) {
    throw std::invalid_argument(fmt::format(
        "InvariantCircleProblem: {} torus needs an unforced system (ForcingPeriod() = {})",
        kind_ == OrbitKind::kAutonomous ? "an autonomous" : "a relative", system_->ForcingPeriod()));
  }
  if (kind_ == OrbitKind::kRelative && !system_->HasRotationSymmetry()) {
    throw std::invalid_argument(
        "InvariantCircleProblem: a relative torus needs a system with a rotation symmetry");
  }
  chart_ = coordinates == CircleCoordinates::kChart;
  if (chart_ && !system_->HasStateChart()) {
    throw std::invalid_argument(
        "InvariantCircleProblem: coordinates = chart, but the system has no state chart");
  }
  Validate(options_);
  n_ = system_->Dimension();
  points_ = 2 * harmonics_ + 1;
  scale_ = system_->StateScale();
  coordinate_scale_ = chart_ ? system_->ChartScale() : scale_;
  if (chart_) angles_ = system_->ChartAngles();
  reference_ = Matrix::Zero(n_, points_);
  phase_weights_.assign(static_cast<size_t>(1 + Extras()), Matrix::Zero(n_, points_));
}

Index InvariantCircleProblem::Extras() const {
  return kind_ == OrbitKind::kForced ? 0 : kind_ == OrbitKind::kAutonomous ? 1 : 2;
}

double InvariantCircleProblem::Node(Index j) const {
  return kTwoPi * static_cast<double>(j) / static_cast<double>(points_);
}

Vector InvariantCircleProblem::Basis(double theta) const {
  Vector b(points_);
  b(0) = 1.0;
  for (int k = 1; k <= harmonics_; ++k) {
    b(2 * k - 1) = std::cos(k * theta);
    b(2 * k) = std::sin(k * theta);
  }
  return b;
}

Vector InvariantCircleProblem::BasisDerivative(double theta) const {
  Vector b(points_);
  b(0) = 0.0;
  for (int k = 1; k <= harmonics_; ++k) {
    b(2 * k - 1) = -k * std::sin(k * theta);
    b(2 * k) = k * std::cos(k * theta);
  }
  return b;
}

Index InvariantCircleProblem::Dimension() const { return n_ * points_ + 1 + Extras(); }

Vector InvariantCircleProblem::Pack(const Matrix& coefficients, double rho, double period,
                                    double rotation) const {
  if (coefficients.rows() != n_ || coefficients.cols() != points_) {
    throw std::invalid_argument(fmt::format(
        "InvariantCircleProblem::Pack: coefficients are {} × {}; must be {} × {}",
        coefficients.rows(), coefficients.cols(), n_, points_));
  }
  Vector u(Dimension());
  u.head(n_ * points_) = Eigen::Map<const Vector>(coefficients.data(), n_ * points_);
  u(n_ * points_) = rho;
  if (Extras() >= 1) u(n_ * points_ + 1) = period;
  if (Extras() == 2) u(n_ * points_ + 2) = rotation;
  return u;
}

double InvariantCircleProblem::Period(const Vector& u, double lambda) {
  const double forced = PeriodAt(lambda);  // sets the system's parameter to λ
  return kind_ == OrbitKind::kForced ? forced : u(n_ * points_ + 1);
}

double InvariantCircleProblem::Rotation(const Vector& u) const {
  return kind_ == OrbitKind::kRelative ? u(n_ * points_ + 2) : 0.0;
}

Matrix InvariantCircleProblem::RotationMatrix(double phi) const {
  Matrix R = Matrix::Identity(n_, n_);
  if (kind_ != OrbitKind::kRelative) return R;
  for (Index i = 0; i < n_; ++i) system_->Rotate(phi, R.col(i));
  return R;
}

Matrix InvariantCircleProblem::Coefficients(const Vector& u) const {
  return Eigen::Map<const Matrix>(u.data(), n_, points_);
}

Vector InvariantCircleProblem::PointAt(const Vector& u, double theta) const {
  return ToState(Coefficients(u) * Basis(theta));
}

Vector InvariantCircleProblem::ToState(const Vector& y, Matrix* jacobian) const {
  if (!chart_) {
    if (jacobian) jacobian->setIdentity(n_, n_);
    return y;
  }
  Vector x(n_);
  system_->FromChart(y, x, jacobian);
  return x;
}

Vector InvariantCircleProblem::ToCoordinates(const Vector& x) const {
  if (!chart_) return x;
  Vector y(n_);
  system_->ToChart(x, y);
  return y;
}

Matrix InvariantCircleProblem::CoordinateJacobian(const Vector& y) const {
  Matrix D;
  ToState(y, &D);
  return D;
}

std::vector<Matrix> InvariantCircleProblem::ShiftDirections(const Matrix& c) const {
  std::vector<Matrix> directions(static_cast<std::size_t>(1 + Extras()), Matrix(n_, points_));
  Vector f(n_), g(n_);
  Matrix D;
  for (Index j = 0; j < points_; ++j) {
    directions[0].col(j) = c * BasisDerivative(Node(j));
    if (kind_ == OrbitKind::kForced) continue;
    const Vector at = ToState(c * Basis(Node(j)), &D);
    const Eigen::PartialPivLU<Matrix> lu(D);
    system_->Rhs(0.0, at, f);
    directions[1].col(j) = lu.solve(f);
    if (kind_ == OrbitKind::kRelative) {
      system_->RotationGenerator(at, g);
      directions[2].col(j) = lu.solve(g);
    }
  }
  return directions;
}

void InvariantCircleProblem::SetPhaseReference(const Vector& u) {
  reference_ = Coefficients(u);
  if (kind_ != OrbitKind::kForced) period_scale_ = std::max(std::abs(u(n_ * points_ + 1)), 1e-300);
  phase_weights_.clear();
  for (const Matrix& directions : ShiftDirections(reference_)) {
    phase_weights_.push_back(PhaseWeights(directions));
  }
}

void InvariantCircleProblem::PointAccepted(const Vector& u, double /*lambda*/) {
  SetPhaseReference(u);
}

std::string InvariantCircleProblem::StrayPoint(const Vector& u, double lambda) {
  if (phase_weights_[0].isZero(0.0)) return {};  // no reference yet
  system_->SetParameter(lambda);
  const std::vector<Matrix> directions = ShiftDirections(Coefficients(u));
  const char* shifts[] = {"θ", "the flow", "the group orbit"};
  for (std::size_t w = 0; w < directions.size(); ++w) {
    const double slope = phase_weights_[w].cwiseProduct(directions[w]).sum();  // Σ_j ⟨w_j, d_j⟩
    if (!(slope > 0.0)) {
      return fmt::format("its circle is turned against the last one along {} (the phase condition's "
                         "slope {:.3g} in that shift: its other root, about half a period away)",
                         shifts[w], slope);
    }
  }
  return {};
}

double InvariantCircleProblem::PeriodAt(double lambda) {
  system_->SetParameter(lambda);
  return system_->ForcingPeriod();
}

const InvariantCircleProblem::Integrated& InvariantCircleProblem::Integrate(const Vector& u,
                                                                            double lambda,
                                                                            bool sensitivities) {
  if (cached_.ok && cached_u_.size() == u.size() && cached_u_ == u && cached_lambda_ == lambda &&
      (cached_sensitivities_ || !sensitivities)) {
    return cached_;
  }
  cached_ = Integrated();
  cached_u_ = u;
  cached_lambda_ = lambda;
  cached_sensitivities_ = sensitivities;
  const double period = Period(u, lambda);
  OdeIntegrator integrator(*system_, options_);
  cached_.ends.resize(n_, points_);
  if (sensitivities) {
    cached_.stms.assign(static_cast<size_t>(points_), Matrix());
    cached_.dpdp.resize(n_, points_);
    cached_.dpdt.resize(n_, points_);
  }
  Vector end(n_), dxdp(n_), dxdt(n_);
  for (Index j = 0; j < points_; ++j) {
    const Vector start = PointAt(u, Node(j));
    const IntegrationResult result =
        sensitivities ? integrator.Integrate(0.0, start, period, end,
                                             &cached_.stms[static_cast<size_t>(j)], &dxdp, &dxdt)
                      : integrator.Integrate(0.0, start, period, end);
    if (!result.Succeeded()) {  // ok stays false
      cached_.failure = fmt::format("the map of the circle's point {} of {} (θ = {:.4f}) failed: {}",
                                    j, points_, Node(j), result.BriefReport());
      return cached_;
    }
    cached_.ends.col(j) = end;
    if (sensitivities) {
      cached_.dpdp.col(j) = dxdp;
      cached_.dpdt.col(j) = dxdt;
    }
  }
  cached_.ok = true;
  return cached_;
}

void InvariantCircleProblem::Residual(const Vector& u, double lambda, Vector& F) {
  F.resize(Dimension());
  const Integrated& data = Integrate(u, lambda, false);
  if (!data.ok) {
    F.setConstant(kNaN);
    return;
  }
  const double rho = RotationNumber(u);
  const Matrix c = Coefficients(u);
  const Matrix R = RotationMatrix(Rotation(u));
  for (Index j = 0; j < points_; ++j) {
    F.segment(n_ * j, n_) = data.ends.col(j) - R * ToState(c * Basis(Node(j) + kTwoPi * rho));
  }
  for (size_t w = 0; w < phase_weights_.size(); ++w) {
    double phase = 0.0;
    for (Index j = 0; j < points_; ++j) {
      phase += phase_weights_[w].col(j).dot((c - reference_) * Basis(Node(j)));
    }
    F(n_ * points_ + static_cast<Index>(w)) = phase;
  }
}

Matrix InvariantCircleProblem::PhaseWeights(const Matrix& directions) const {
  Matrix weights = directions.array().colwise() / coordinate_scale_.array();
  const double norm = std::sqrt(std::max(weights.squaredNorm(), 1e-300) * static_cast<double>(points_));
  return (weights.array().colwise() / coordinate_scale_.array()) / norm;
}

void InvariantCircleProblem::Jacobian(const Vector& u, double lambda, Matrix& J) {
  const Index dim = Dimension();
  J.setZero(dim, dim);
  const Integrated& data = Integrate(u, lambda, true);
  if (!data.ok) {
    J.setConstant(kNaN);
    return;
  }
  system_->SetParameter(lambda);  // f below at λ, also when the integrations came from the cache
  const double rho = RotationNumber(u);
  const Matrix c = Coefficients(u);
  const double phi = Rotation(u);
  const Matrix R = RotationMatrix(phi);
  const Index rho_column = n_ * points_;
  Vector g(n_);
  Matrix D_at, D_shifted;
  for (Index j = 0; j < points_; ++j) {
    const double theta = Node(j);
    const Vector at = Basis(theta);
    const Vector shifted = Basis(theta + kTwoPi * rho);
    ToState(c * at, &D_at);
    const Vector shifted_point = ToState(c * shifted, &D_shifted);
    const Matrix MD = data.stms[static_cast<size_t>(j)] * D_at, RD = R * D_shifted;
    for (Index m = 0; m < points_; ++m) {
      J.block(n_ * j, n_ * m, n_, n_) = at(m) * MD - shifted(m) * RD;
      for (size_t w = 0; w < phase_weights_.size(); ++w) {
        J.block(n_ * points_ + static_cast<Index>(w), n_ * m, 1, n_) +=
            at(m) * phase_weights_[w].col(j).transpose();
      }
    }
    J.block(n_ * j, rho_column, n_, 1) = -kTwoPi * (RD * (c * BasisDerivative(theta + kTwoPi * rho)));
    if (kind_ != OrbitKind::kForced) J.block(n_ * j, rho_column + 1, n_, 1) = data.dpdt.col(j);
    if (kind_ == OrbitKind::kRelative) {
      system_->RotationGenerator(R * shifted_point, g);
      J.block(n_ * j, rho_column + 2, n_, 1) = -g;
    }
  }
}

void InvariantCircleProblem::DfDlambda(const Vector& u, double lambda, Vector& dF) {
  dF.setZero(Dimension());
  const Integrated& data = Integrate(u, lambda, true);
  if (!data.ok) {
    dF.setConstant(kNaN);
    return;
  }
  for (Index j = 0; j < points_; ++j) dF.segment(n_ * j, n_) = data.dpdp.col(j);
  if (kind_ != OrbitKind::kForced) return;  // T is an unknown, not a function of λ
  // The map's end moves with the period when λ changes it: T′(λ) f(T, P(x)).
  const double h = CentralDifferenceStep(lambda, 1.0);
  const double dperiod = (PeriodAt(lambda + h) - PeriodAt(lambda - h)) / (2.0 * h);
  const double period = PeriodAt(lambda);
  Vector f(n_);
  for (Index j = 0; j < points_; ++j) {
    if (dperiod != 0.0) {
      system_->Rhs(period, data.ends.col(j), f);
      dF.segment(n_ * j, n_) += dperiod * f;
    }
  }
}

Vector InvariantCircleProblem::Scale() const {
  Vector s(Dimension());
  for (Index m = 0; m < points_; ++m) s.segment(n_ * m, n_) = coordinate_scale_;
  s(n_ * points_) = 1.0;                                // ρ
  if (Extras() >= 1) s(n_ * points_ + 1) = period_scale_;  // T
  if (Extras() == 2) s(n_ * points_ + 2) = 1.0;         // φ [rad]
  return s;
}

double InvariantCircleProblem::LambdaScale() const {
  return std::max(std::abs(system_->Parameter()), 1.0);
}

Vector InvariantCircleProblem::ResidualScale() const {
  Vector s(Dimension());
  for (Index j = 0; j < points_; ++j) s.segment(n_ * j, n_) = scale_;
  s.tail(1 + Extras()).setOnes();
  return s;
}

std::vector<std::string> InvariantCircleProblem::MeasureNames() const {
  std::vector<std::string> names{"rotation_number", "fourier_tail", "invariance_error"};
  if (Extras() >= 1) names.push_back("period");
  if (Extras() == 2) names.push_back("rotation");
  names.push_back("radius");
  return names;
}

double InvariantCircleProblem::HarmonicSize(const Vector& u, int k) const {
  return HarmonicSizeOf(Coefficients(u), k, coordinate_scale_);
}

double InvariantCircleProblem::HarmonicSizeOf(const Matrix& coefficients, int k, const Vector& scale) {
  return coefficients.middleCols(2 * k - 1, 2).cwiseQuotient(scale.replicate(1, 2)).norm();
}

Matrix InvariantCircleProblem::States(const Vector& u) const {
  Matrix states(n_, points_);
  for (Index j = 0; j < points_; ++j) states.col(j) = PointAt(u, Node(j));
  return states;
}

Vector InvariantCircleProblem::Centre(const Vector& u) const { return States(u).rowwise().mean(); }

double InvariantCircleProblem::Radius(const Vector& u) const {
  const Matrix states = States(u);
  const Matrix off = (states.colwise() - Vector(states.rowwise().mean())).cwiseQuotient(
      scale_.replicate(1, points_));
  return std::sqrt(off.squaredNorm() / static_cast<double>(points_));
}

double InvariantCircleProblem::FourierTail(const Vector& u) const {
  double largest = 0.0;
  for (int k = 1; k <= harmonics_; ++k) largest = std::max(largest, HarmonicSize(u, k));
  return HarmonicSize(u, harmonics_) / std::max(largest, 1e-300);
}

Vector InvariantCircleProblem::Measures(const Vector& u, double lambda) {
  Vector m(4 + Extras());
  m.head(3) << RotationNumber(u), FourierTail(u), InvarianceError(u, lambda);
  if (Extras() >= 1) m(3) = Period(u, lambda);
  if (Extras() == 2) m(4) = Rotation(u);
  m(3 + Extras()) = Radius(u);
  return m;
}

void InvariantCircleProblem::SetMaxFourierTail(double tail) {
  if (!(tail > 0.0 && tail < 1.0)) {
    throw std::invalid_argument(
        fmt::format("InvariantCircleProblem: max Fourier tail = {}: must be in (0, 1)", tail));
  }
  max_tail_ = tail;
}

void InvariantCircleProblem::SetMinRadius(double radius) {
  if (!(radius >= 0.0 && std::isfinite(radius))) {
    throw std::invalid_argument(
        fmt::format("InvariantCircleProblem: min radius = {}: must be finite and ≥ 0", radius));
  }
  min_radius_ = radius;
}

std::vector<std::string> InvariantCircleProblem::EventNames() const {
  return {std::string(kFourierTailReached), std::string(kShrinksOntoCentre)};
}

Vector InvariantCircleProblem::EventFunctions(const Vector& u, double /*lambda*/) {
  // ≥ 0 while the tail stays below the limit and the radius above its own; in decades, so that
  // they cross 0 at a moderate slope.
  Vector margins(2);
  margins(0) = std::log10(max_tail_) - std::log10(std::max(FourierTail(u), 1e-300));
  margins(1) = min_radius_ > 0.0
                   ? std::log10(std::max(Radius(u), 1e-300)) - std::log10(min_radius_)
                   : 1.0;
  return margins;
}

void InvariantCircleProblem::SetGrazingTests(std::vector<TorusGrazing> tests) {
  for (const TorusGrazing& test : tests) {
    if (!test.surface) {
      throw std::invalid_argument(
          fmt::format("InvariantCircleProblem: grazing test '{}' has no surface", test.name));
    }
  }
  grazing_ = std::move(tests);
}

Index InvariantCircleProblem::GrazingSamples() const {
  const Index least = 16 * grazing_samples_per_step_;  // 64 by default
  if (options_.method != IntegrationMethod::kGaussCollocation) return least;
  return std::max<Index>(
      least, grazing_samples_per_step_ * static_cast<Index>(options_.collocation_steps));
}

void InvariantCircleProblem::SetGrazingGrid(int starts_per_point, int samples_per_step) {
  if (starts_per_point < 1 || samples_per_step < 1) {
    throw std::invalid_argument(fmt::format(
        "InvariantCircleProblem: grazing grid {} starts per point, {} samples per step: each must "
        "be at least 1",
        starts_per_point, samples_per_step));
  }
  grazing_starts_per_point_ = starts_per_point;
  grazing_samples_per_step_ = samples_per_step;
}

std::vector<std::string> InvariantCircleProblem::TestFunctionNames() const {
  std::vector<std::string> names;
  for (const TorusGrazing& test : grazing_) names.push_back(test.name);
  return names;
}

SpecialPointType InvariantCircleProblem::TestFunctionType(int /*k*/) const {
  return SpecialPointType::kGrazing;
}

Vector InvariantCircleProblem::TestFunctions(const Vector& u, double lambda) {
  const auto tests = static_cast<Index>(grazing_.size());
  Vector values = Vector::Constant(tests, kNaN);
  if (tests == 0) return values;
  const double period = Period(u, lambda), rho = RotationNumber(u);
  const Index starts = grazing_starts_per_point_ * points_, S = GrazingSamples();
  Vector times(S + 1);
  for (Index m = 0; m <= S; ++m) {
    times(m) = period * static_cast<double>(m) / static_cast<double>(S);
  }
  OdeIntegrator integrator(*system_, options_);
  Matrix states;
  // h of every test at the instants of the orbit from u(ϑ), or false where it cannot be integrated.
  auto sample = [&](double theta, std::vector<Vector>& h) {
    if (!integrator.Sample(0.0, PointAt(u, theta), times, states).Succeeded()) return false;
    h.assign(static_cast<std::size_t>(tests), Vector(S + 1));
    for (Index k = 0; k < tests; ++k) {
      for (Index m = 0; m <= S; ++m) {
        h[static_cast<std::size_t>(k)](m) =
            grazing_[static_cast<std::size_t>(k)].surface(states.col(m));
      }
    }
    return true;
  };
  auto angle = [&](Index i) {
    return kTwoPi * static_cast<double>(i) / static_cast<double>(starts);
  };
  // grid[start][test](instant)
  std::vector<std::vector<Vector>> grid(static_cast<std::size_t>(starts));
  for (Index i = 0; i < starts; ++i) {
    if (!sample(angle(i), grid[static_cast<std::size_t>(i)])) return values;
  }
  const double dtheta = kTwoPi / static_cast<double>(starts), ds = 1.0 / static_cast<double>(S);
  auto wrap = [&](Index i) { return (i + starts) % starts; };
  for (Index k = 0; k < tests; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const double sign = grazing_[kk].side == GrazingSide::kTouchdown ? +1.0 : -1.0;
    auto at = [&](Index i, Index m) { return grid[static_cast<std::size_t>(wrap(i))][kk](m); };
    Index best_i = 0, best_m = 0;
    for (Index i = 0; i < starts; ++i) {
      for (Index m = 0; m <= S; ++m) {
        if (sign * at(i, m) > sign * at(best_i, best_m)) {
          best_i = i;
          best_m = m;
        }
      }
    }
    // The 3 × 3 stencil round it, f[a][b] at start best_i + a − 1, instant best_m + b − 1; across
    // the seam by the map's invariance: Φ_{T+τ}(u(ϑ)) = R_φ Φ_τ(u(ϑ + 2πρ)), h invariant under R_φ.
    double f[3][3];
    for (Index a = 0; a < 3; ++a) {
      const Index i = best_i + a - 1;
      for (Index b = 0; b < 3; ++b) {
        const Index m = best_m + b - 1;
        if (m >= 0 && m <= S) {
          f[a][b] = at(i, m);
          continue;
        }
        std::vector<Vector> seam;
        const double shift = m < 0 ? -kTwoPi * rho : kTwoPi * rho;
        if (!sample(angle(wrap(i)) + shift, seam)) return values;
        f[a][b] = seam[kk](m < 0 ? S - 1 : 1);
      }
    }
    values(k) = QuadraticExtremum(f, dtheta, ds, sign);
  }
  return values;
}

double InvariantCircleProblem::InvarianceError(const Vector& u, double lambda) {
  const double period = Period(u, lambda);
  const double rho = RotationNumber(u);
  const Matrix R = RotationMatrix(Rotation(u));
  OdeIntegrator integrator(*system_, options_);
  Vector end(n_);
  double error = 0.0;
  for (Index j = 0; j < points_; ++j) {
    const double theta = kTwoPi * (static_cast<double>(j) + 0.5) / static_cast<double>(points_);
    if (!integrator.Integrate(0.0, PointAt(u, theta), period, end).Succeeded()) {
      return kNaN;
    }
    error = std::max(error, (end - R * PointAt(u, theta + kTwoPi * rho))
                                .cwiseQuotient(scale_)
                                .lpNorm<Eigen::Infinity>());
  }
  return error;
}

Matrix InvariantCircleProblem::Images(const Vector& u, double lambda, const Vector& angles,
                                      int images, std::string& failure) {
  const double period = Period(u, lambda), phi = Rotation(u);
  OdeIntegrator integrator(*system_, options_);
  Matrix points(n_, angles.size());
  Vector end(n_);
  for (Index k = 0; k < angles.size(); ++k) {
    Vector x = PointAt(u, angles(k));
    for (int i = 0; i < images; ++i) {
      const IntegrationResult mapped = integrator.Integrate(0.0, x, period, end);
      if (!mapped.Succeeded()) {
        failure = fmt::format("the circle's point {} of {}, image {}: {}", k, angles.size(), i + 1,
                              mapped.BriefReport());
        return {};
      }
      if (kind_ == OrbitKind::kRelative) system_->Rotate(-phi, end);  // P = R_{−φ} Φ_T
      x = end;
    }
    points.col(k) = x;
  }
  return points;
}

std::vector<double> InvariantCircleProblem::CircleMultipliers(const Vector& u, double lambda) {
  const Integrated& data = Integrate(u, lambda, true);
  if (!data.ok) return {};
  const double rho = RotationNumber(u);
  const Matrix back = RotationMatrix(-Rotation(u));  // P = R_{−φ} Φ_T
  const Index size = n_ * points_;
  Matrix E = Matrix::Zero(size, size), shifted = Matrix::Zero(size, size),
         image = Matrix::Zero(size, size);
  const Matrix c = Coefficients(u);
  Matrix D_at, D_moved;
  for (Index j = 0; j < points_; ++j) {
    const double theta = Node(j);
    const Vector at = Basis(theta), moved = Basis(theta + kTwoPi * rho);
    ToState(c * at, &D_at);
    ToState(c * moved, &D_moved);
    for (Index m = 0; m < points_; ++m) {
      E.block(n_ * j, n_ * m, n_, n_) = at(m) * D_at;
      shifted.block(n_ * j, n_ * m, n_, n_) = moved(m) * D_moved;
    }
  }
  for (Index j = 0; j < points_; ++j) {
    image.middleRows(n_ * j, n_) = back * data.stms[static_cast<size_t>(j)] * E.middleRows(n_ * j, n_);
  }
  const Matrix operator_ = shifted.partialPivLu().solve(image);
  ComplexVector values;
  if (!BalancedEigenvalues(operator_, values)) return {};
  std::vector<double> moduli;
  for (Index i = 0; i < values.size(); ++i) moduli.push_back(std::abs(values(i)));
  std::sort(moduli.begin(), moduli.end(), std::greater<>());
  return moduli;
}

bool InvariantCircleProblem::TorusStability::IsTrivial(Index i) const {
  return std::find(trivial.begin(), trivial.end(), i) != trivial.end();
}

double InvariantCircleProblem::TorusStability::LargestNontrivial() const {
  double largest = -kInfinity;
  for (Index i = 0; i < exponents.size(); ++i) {
    if (!IsTrivial(i)) largest = std::max(largest, exponents(i));
  }
  return largest;
}

int InvariantCircleProblem::TorusStability::UnstableCount() const {
  if (!valid || !(stable || unstable)) return -1;
  int count = 0;
  for (Index i = 0; i < exponents.size(); ++i) {
    if (!IsTrivial(i) && exponents(i) > tolerance) ++count;
  }
  return count;
}

InvariantCircleProblem::TorusStability InvariantCircleProblem::LyapunovStability(
    const Vector& u, double lambda, int iterates) {
  if (iterates < 1) {
    throw std::invalid_argument(fmt::format("LyapunovStability: iterates = {}: must be ≥ 1", iterates));
  }
  TorusStability result;
  const double period = Period(u, lambda);
  const Matrix back = RotationMatrix(-Rotation(u));  // P = R_{−φ} Φ_T
  OdeIntegrator integrator(*system_, options_);
  // In scaled coordinates, so that the QR's orthogonality weighs the states alike.
  const Matrix S = scale_.asDiagonal(), S_inverse = scale_.cwiseInverse().asDiagonal();
  Vector x = PointAt(u, 0.0), end(n_);
  Matrix Q = Matrix::Identity(n_, n_), stm;
  Vector sums = Vector::Zero(n_);
  // The first quarter aligns the frame with the Oseledets directions and is not counted: while
  // it turns, each step it spends on a faster-decaying direction biases the sums by the gap
  // (measured on an exact relative torus: errors 33/k per period after k steps without it).
  const int warm_up = iterates / 4;
  for (int k = 0; k < warm_up + iterates; ++k) {
    if (!integrator.Integrate(0.0, x, period, end, &stm).Succeeded()) return result;
    Eigen::HouseholderQR<Matrix> qr(S_inverse * back * stm * S * Q);
    const Matrix R = qr.matrixQR().triangularView<Eigen::Upper>();
    Q = qr.householderQ() * Matrix::Identity(n_, n_);
    for (Index i = 0; i < n_; ++i) {
      if (k >= warm_up) sums(i) += std::log(std::abs(R(i, i)));
      if (R(i, i) < 0.0) Q.col(i) = -Q.col(i);
    }
    x = back * end;
  }
  result.exponents = sums / static_cast<double>(iterates);
  std::sort(result.exponents.data(), result.exponents.data() + n_, std::greater<>());
  std::vector<Index> order(static_cast<size_t>(n_));
  for (Index i = 0; i < n_; ++i) order[static_cast<size_t>(i)] = i;
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) {
    return std::abs(result.exponents(a)) < std::abs(result.exponents(b));
  });
  result.trivial.assign(order.begin(), order.begin() + std::min<Index>(1 + Extras(), n_));
  double largest_trivial = 0.0;
  for (Index i : result.trivial) largest_trivial = std::max(largest_trivial, std::abs(result.exponents(i)));
  result.tolerance = std::max(10.0 * largest_trivial, 1e-6);
  result.stable = result.LargestNontrivial() < -result.tolerance;
  result.unstable = result.LargestNontrivial() > result.tolerance;
  result.valid = true;
  return result;
}

Vector InvariantCircleProblem::CircleFromOrbit(const Matrix& points, double period,
                                               double rotation) const {
  const Index m = points.cols();
  if (points.rows() != n_ || m < points_ + 1) {
    throw std::invalid_argument(fmt::format(
        "CircleFromOrbit: {} × {} points; need {} rows and at least {} columns", points.rows(), m,
        n_, points_ + 1));
  }
  // The angles θ_k and ρ from the states; with a chart, the coefficients are fitted at the end in
  // its coordinates at those angles. (Angles and ρ from the chart's points were worse: C(c) at 64
  // rpm, K = 8, ρ 0.309 against the torus's 0.3053 — the transient's ringing of the contact,
  // which the chart's gap rate magnifies, weighed in the misfit — and Newton failed.)
  // Scaled, centred; the plane of the two leading principal directions.
  const Vector centre = points.rowwise().mean();
  Matrix scaled = (points.colwise() - centre).array().colwise() / scale_.array();
  Eigen::JacobiSVD<Matrix> svd(scaled, Eigen::ComputeThinU);
  const Matrix plane = svd.matrixU().leftCols(std::min<Index>(2, n_));
  if (plane.cols() < 2) throw std::invalid_argument("CircleFromOrbit: the system has one state");
  const Matrix projected = plane.transpose() * scaled;  // 2 × m
  Vector theta(m);
  for (Index k = 0; k < m; ++k) theta(k) = std::atan2(projected(1, k), projected(0, k));
  // Mean advance per iterate in [0, 1) turns; the angles must advance steadily.
  double advance = 0.0;
  for (Index k = 1; k < m; ++k) {
    double step = theta(k) - theta(k - 1);
    step -= kTwoPi * std::floor(step / kTwoPi);
    advance += step;
  }
  double rho = advance / kTwoPi / static_cast<double>(m - 1);
  // The fit in given angles: coefficients in the state and the largest scaled misfit (A: the
  // last fit's basis rows).
  Matrix A, c;
  auto fit = [&](const Vector& angles) {
    A = BasisMatrix(angles);
    c = A.colPivHouseholderQr().solve(points.transpose()).transpose();
    return ((c * A.transpose() - points).array().colwise() / scale_.array()).abs().maxCoeff();
  };
  double misfit = fit(theta);
  // The map's own angles: on an invariant circle with rotation number ρ the orbit's points sit at
  // θ_k = 2πkρ of the circle's conjugating parametrisation, which the Newton solve looks for; the
  // geometric angles above only approximate it, badly where the points bunch (near a resonance
  // the orbit lingers at q places). ρ is refined by the least misfit on a grid of ±4/m round the
  // mean advance (each pass 1/50 of the last one's step, about its best), and those angles are kept
  // where they fit better. Measured on C(a) at 60 rpm (sections of 5 modulation periods, ρ = 0.562,
  // the orbit bunched at 16 places): the first circle's residual 40 with the geometric angles,
  // 9.1e-4 with the map's (scaled, K = 16).
  auto orbit_angles = [&](double r) {
    return Vector(Vector::LinSpaced(m, 0.0, kTwoPi * r * static_cast<double>(m - 1)));
  };
  // The least misfit on grids of 201 values of ρ round `centre`, each pass 50 times finer about
  // the best of the last (kRhoGridPasses passes).
  auto refine = [&](double centre, double& best_rho) {
    double best = kInfinity;
    double step = 4.0 / static_cast<double>(m) / 100.0;
    best_rho = centre;
    for (int pass = 0; pass < kRhoGridPasses; ++pass, step /= 50.0) {
      const double around = best_rho;
      for (int i = -100; i <= 100; ++i) {
        const double r = around + i * step;
        const double e = fit(orbit_angles(r));
        if (e < best) {
          best = e;
          best_rho = r;
        }
      }
    }
    return best;
  };
  double best_rho = rho;
  bool geometric = false;  // whether the fit is in the geometric angles θ_k (else 2πkρ)
  if (refine(rho, best_rho) < misfit) {
    misfit = fit(orbit_angles(best_rho));
    rho = best_rho - std::floor(best_rho);
  } else {
    fit(theta);
    geometric = true;
  }
  // A fit at angles 2πkρ' with ρ' = ρ/q fits as well as the one at 2πkρ (u(θ) = w(qθ)): a circle
  // covered q times, whose invariance equation is singular (u(θ + 2π/q) is the same circle). Where
  // only multiples of some q > 1 carry the circle (every other harmonic below kCoverRatio of the
  // largest multiple's), it is unwound: ρ ← qρ mod 1, refined and refitted. Measured on C(c) at
  // 64 rpm (sections of one modulation period, K = 8): harmonic 2 at 0.21, the odd ones ≤ 4.9e-3,
  // Newton met a singular Jacobian (rcond < 1e-14) before this.
  for (int q = harmonics_; q >= 2; --q) {
    double multiples = 0.0, others = 0.0;
    for (int k = 1; k <= harmonics_; ++k) {
      double& largest = k % q == 0 ? multiples : others;
      largest = std::max(largest, HarmonicSizeOf(c, k, scale_));
    }
    if (multiples > 0.0 && others <= kCoverRatio * multiples) {
      refine(q * rho, best_rho);
      rho = best_rho - std::floor(best_rho);
      misfit = fit(orbit_angles(rho));
      geometric = false;
      break;
    }
  }
  // One orientation of the angle: ρ ≤ 1/2. The principal directions' signs are arbitrary (the
  // SVD's), so the plane's orientation, and with it ρ or 1 − ρ for the same torus traversed the
  // other way, turned with the points' last bits: C(a) at 49 rpm gave ρ = 0.3789 or 0.6211 from
  // two Dormand–Prince transients that differ in rounding only, and the locking and line readings
  // with it (3/5 for 2/5, f₁ − f₂ for f₂). θ → −θ turns ρ into 1 − ρ; the same fit, mirrored.
  if (rho > 0.5) {
    rho = 1.0 - rho;
    misfit = fit(geometric ? Vector(-theta) : orbit_angles(rho));
  }
  // The fitted circle must pass through the points (else they are not one winding circle).
  const double size = scaled.cwiseAbs().maxCoeff();
  if (!(misfit <= 0.1 * size)) {
    throw std::invalid_argument(fmt::format(
        "CircleFromOrbit: the points do not lie on one curve around their centroid (fit misfit "
        "{:.3g} against their size {:.3g}): a locked orbit, or a torus that does not wind once "
        "in its principal plane",
        misfit, size));
  }
  if (chart_) c = FitCoefficients(points, A);
  return Pack(c, rho, period, rotation);
}

Matrix InvariantCircleProblem::BasisMatrix(const Vector& angles) const {
  Matrix A(angles.size(), points_);
  for (Index k = 0; k < angles.size(); ++k) A.row(k) = Basis(angles(k)).transpose();
  return A;
}

Matrix InvariantCircleProblem::FitCoefficients(const Matrix& states, const Matrix& basis) const {
  const Index m = states.cols();
  Matrix values(n_, m);
  for (Index k = 0; k < m; ++k) values.col(k) = ToCoordinates(states.col(k));
  // The chart's angles unwrapped round their circular mean.
  for (const Index i : angles_) {
    const double mean = std::atan2(values.row(i).array().sin().sum(), values.row(i).array().cos().sum());
    for (Index k = 0; k < m; ++k) values(i, k) = mean + std::remainder(values(i, k) - mean, kTwoPi);
  }
  return basis.colPivHouseholderQr().solve(values.transpose()).transpose();
}

Vector InvariantCircleProblem::CircleAtRotationNumber(const Matrix& states, double rho,
                                                      double period, double rotation) const {
  const Index m = states.cols();
  return CircleAtAngles(states,
                        Vector::LinSpaced(m, 0.0, kTwoPi * rho * static_cast<double>(m - 1)), rho,
                        period, rotation);
}

Vector InvariantCircleProblem::CircleAtAngles(const Matrix& states, const Vector& angles,
                                              double rho, double period, double rotation) const {
  const Index m = states.cols();
  if (states.rows() != n_ || m < points_ + 1 || angles.size() != m) {
    throw std::invalid_argument(fmt::format(
        "InvariantCircleProblem: {} × {} points at {} angles; need {} rows, at least {} columns "
        "and an angle per column",
        states.rows(), m, angles.size(), n_, points_ + 1));
  }
  return Pack(FitCoefficients(states, BasisMatrix(angles)), rho, period, rotation);
}

Vector CircleWithHarmonics(const Vector& u, Index states, int from, int to) {
  const Index coefficients = states * (2 * from + 1), target = states * (2 * to + 1);
  if (from < 1 || to < 1 || u.size() < coefficients || u.size() > coefficients + 3) {
    throw std::invalid_argument(fmt::format(
        "CircleWithHarmonics: a circle of {} unknowns is not one of {} states and {} harmonics",
        u.size(), states, from));
  }
  const Index extras = u.size() - coefficients, kept = std::min(coefficients, target);
  Vector v = Vector::Zero(target + extras);
  v.head(kept) = u.head(kept);
  v.tail(extras) = u.tail(extras);
  return v;
}

void ValidateRefinementImages(const std::string& prefix, const std::vector<int>& images) {
  if (images.empty() ||
      std::any_of(images.begin(), images.end(), [](int n) { return n < 1 || n > 100; })) {
    throw std::invalid_argument(
        fmt::format("{}refinement_images = {{{}}}: must be one or more counts in 1 … 100", prefix,
                    fmt::join(images, ", ")));
  }
}

CircleRefinement RefineCircle(InvariantCircleProblem& coarse, const Vector& u, double lambda,
                              InvariantCircleProblem& finer, const std::vector<int>& images,
                              const NewtonOptions& newton) {
  CircleRefinement result;
  result.u = CircleWithHarmonics(u, coarse.states(), coarse.harmonics(), finer.harmonics());
  const double period = coarse.Period(u, lambda), phi = coarse.Rotation(u);
  const double rho = coarse.RotationNumber(u);
  const Index count = 4 * (2 * finer.harmonics() + 1);
  const Vector nodes = Vector::LinSpaced(
      count, 0.0, kTwoPi * static_cast<double>(count - 1) / static_cast<double>(count));
  std::vector<std::string> failures;
  for (const int n : images) {
    std::string failure;
    const Matrix points = coarse.Images(u, lambda, nodes, n, failure);
    if (failure.empty()) {
      Vector start = finer.CircleAtAngles(points, nodes.array() + kTwoPi * rho * n, rho, period, phi);
      finer.SetPhaseReference(start);
      result.newton = NewtonSolve(
          [&](const Vector& v, Vector& F) { finer.Residual(v, lambda, F); },
          [&](const Vector& v, Matrix& J) { finer.Jacobian(v, lambda, J); }, start, newton,
          finer.Scale(), finer.ResidualScale());
      if (result.newton.Converged()) {
        result.converged = true;
        result.u = std::move(start);
        result.images = n;
        break;
      }
      failure = result.newton.BriefReport();
    }
    failures.push_back(fmt::format("from {} image{}: {}", n, n > 1 ? "s" : "", failure));
  }
  result.failures = fmt::format("{}", fmt::join(failures, "; "));
  return result;
}

}  // namespace rubcont
