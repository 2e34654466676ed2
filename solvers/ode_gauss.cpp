// Gauss–Legendre collocation on a fixed mesh (the implicit Runge–Kutta method of order 2s
// with s stages; Hairer & Wanner, Solving ODEs II, §IV.5 and §IV.8). SUNDIALS has no fully implicit
// Runge–Kutta method, and this one is what the stiff rub contact needs in shooting:
//   - A-stable with |R(iy)| = 1: a nearly undamped stiff mode (the contact at √(k1/m) ≈ 1.3e5 rad/s)
//     is neither amplified nor damped numerically, its multiplier keeps modulus ≈ 1 even where the
//     mesh does not resolve its oscillation, and the solution on the slow manifold is collocated to
//     stage order s;
//   - on a fixed mesh the step map x_n ↦ x_{n+1} is a smooth function of x_n and p, so the
//     state-transition matrix below is its exact derivative: Newton on a shooting residual built from
//     it converges quadratically on the discrete problem, whatever the stiff modes do. An adaptive
//     step sequence that does not see a mode the sensitivities do see cannot give that (ode.h).
// It is orthogonal collocation of the segment with the interior unknowns eliminated step by step —
// AUTO's condensation — closed by the shooting code's matching and periodicity conditions.
//
// Step n, stage increments Z_i = X_i − x_n, F_i = f(t_n + c_i h, x_n + Z_i):
//   G(Z) = Z − h (A ⊗ I) F = 0,  solved by Newton with M = I − h (A ⊗ I) blockdiag(J_1 … J_s),
//   x_{n+1} = x_n + Σ d_i Z_i,   dᵀ = bᵀ A⁻¹.
// Differentiating G(Z(x_n, p), x_n, p) = 0:
//   M W = h (A ⊗ I) [J_i Φ_n]_i,             Φ_{n+1} = Φ_n + Σ d_i W_i;
//   M w = h (A ⊗ I) [J_i q_n + ∂f/∂p(X_i)]_i,  q_{n+1} = q_n + Σ d_i w_i,
// and with h = (t1 − t0)/N, the derivative of the whole map in its end time t1 (Z = h (A ⊗ I) F):
//   M v = h (A ⊗ I) [J_i r_n + ∂f/∂t(X_i)·(n + c_i)/N]_i + Z/(t1 − t0),  r_{n+1} = r_n + Σ d_i v_i,
// with the factorisation of M from the last Newton iteration (its Jacobians one increment below
// the converged stages: a relative error of the Newton tolerance in Φ).
//
// A second-order system x = [q; v], f = [v; a(t, q, v)] (every rotor model: checked at each stage,
// f's first half equal to x's second half and J's first block row exactly [0 I]) has the stages'
// first halves linear in their second: Q_i = h Σ_j A_ij (v + V_j). Eliminating them, every solve
// with M (Newton's and the sensitivities') is one with the Schur complement of size s·n/2,
//   M_V = I − h (A ⊗ I) blockdiag(a_v,j) − h² (A ⊗ I) blockdiag(a_q,j) (A ⊗ I),
//   M_V Δ_V = G_V + h (A ⊗ I) blockdiag(a_q,j) G_Q,   Δ_Q = G_Q + h (A ⊗ I) Δ_V,
// the same linear algebra as M's by block elimination (the same iterates, to rounding), an eighth
// of its factorisation's cost (SolveWithNewtonMatrix).
//
// The mesh is uniform (collocation_steps per call) or set by OdeIntegrator::SetCollocationMesh.
// Errors are not estimated: the accuracy is the mesh's, measured against a tight CVODES reference
// where it is used (docs/studies/orbits.md); each call leaves u^(s) on its steps
// (CollocationDerivatives), from which a caller equidistributes a mesh (EquidistributedMesh, as
// AUTO-07p adapts its collocation mesh). Events are not supported.
#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <fmt/core.h>

#include "solvers/constants.h"
#include "solvers/finite_difference.h"
#include "solvers/ode_internal.h"

namespace rubcont {
namespace detail {
namespace {

// Newton on the stage equations stops when the scaled increment is below this fraction of the
// absolute tolerance, or fails after kMaxNewtonIterations.
constexpr double kNewtonFraction = 1e-3;
constexpr double kNewtonFloor = 1e-14;
constexpr int kMaxNewtonIterations = 30;
// Backtracking (SolveStages): at most this many halvings in all, none below kMinDamping.
constexpr int kMaxGaussHalvings = 60;
constexpr double kMinDamping = 1.0 / 1024.0;

}  // namespace

GaussCoefficients GaussCoefficients::Make(int stages) {
  GaussCoefficients g;
  const int s = stages;
  // Golub–Welsch: the nodes of Legendre P_s on [−1, 1] are the eigenvalues of the Jacobi matrix
  // with off-diagonal k/√(4k² − 1); the weights are 2·(first eigenvector component)².
  Matrix jacobi = Matrix::Zero(s, s);
  for (int k = 1; k < s; ++k) {
    jacobi(k, k - 1) = jacobi(k - 1, k) = k / std::sqrt(4.0 * k * k - 1.0);
  }
  Eigen::SelfAdjointEigenSolver<Matrix> eigen(jacobi);
  g.c = (eigen.eigenvalues().array() + 1.0) / 2.0;
  g.b = eigen.eigenvectors().row(0).transpose().array().square();  // (2 v₀²)/2 on [0, 1]
  // A_ij = ∫₀^{c_i} ℓ_j: with V_jk = c_j^k, A V = C, C_ik = c_i^{k+1}/(k+1).
  Matrix V(s, s), C(s, s);
  for (int j = 0; j < s; ++j) {
    for (int k = 0; k < s; ++k) {
      V(j, k) = std::pow(g.c(j), k);
      C(j, k) = std::pow(g.c(j), k + 1) / (k + 1);
    }
  }
  g.vandermonde_inverse = V.inverse();
  g.A = C * g.vandermonde_inverse;
  g.A_inverse = g.A.inverse();
  g.d = (g.b.transpose() * g.A_inverse).transpose();
  return g;
}

Vector GaussCoefficients::Interpolation(double theta) const {
  // u(t_n + θh) = x_n + Σ_j γ_j(θ) Z_j, γ(θ)ᵀ = β(θ)ᵀ A⁻¹, β_j(θ) = ∫₀^θ ℓ_j.
  const Index s = c.size();
  Vector powers(s);
  for (Index k = 0; k < s; ++k) powers(k) = std::pow(theta, static_cast<double>(k + 1)) / (k + 1);
  const Vector beta = vandermonde_inverse.transpose() * powers;
  return A_inverse.transpose() * beta;
}

GaussBackend::GaussBackend(CallbackContext& context, const IntegratorOptions& options)
    : context_(context),
      options_(options),
      coefficients_(GaussCoefficients::Make(options.collocation_stages)) {
  const Index n = context.n;
  const Index s = options.collocation_stages;
  stages_.resize(n, s);
  previous_stages_.resize(n, s);
  derivatives_.resize(n, s);
  jacobians_.assign(static_cast<std::size_t>(s), Matrix(n, n));
  newton_matrix_.resize(n * s, n * s);
  residual_.resize(n * s);
  extrapolation_.resize(s);
  for (Index i = 0; i < s; ++i) extrapolation_[static_cast<std::size_t>(i)] =
      coefficients_.Interpolation(1.0 + coefficients_.c(i));
  output_weights_.resize(s);
  stage_state_.resize(n);
  // u(θ) = x_n + Σ_i γ_i(θ) Z_i interpolates (0, x_n) and (c_i, x_n + Z_i), so γ_i is the Lagrange
  // polynomial θ Π_{k≠i} (θ − c_k) / (c_i Π_{k≠i} (c_i − c_k)), whose s-th derivative is s! over
  // that denominator.
  derivative_weights_.resize(s);
  double factorial = 1.0;
  for (Index k = 2; k <= s; ++k) factorial *= static_cast<double>(k);
  for (Index i = 0; i < s; ++i) {
    double denominator = coefficients_.c(i);
    for (Index k = 0; k < s; ++k) {
      if (k != i) denominator *= coefficients_.c(i) - coefficients_.c(k);
    }
    derivative_weights_(i) = factorial / denominator;
  }
}

void GaussBackend::SetMesh(std::vector<double> fractions) {
  if (!fractions.empty()) {
    const std::size_t last = fractions.size() - 1;
    if (fractions.size() < 2 || fractions[0] != 0.0 || fractions[last] != 1.0) {
      throw std::invalid_argument(fmt::format(
          "OdeIntegrator::SetCollocationMesh: {} fractions from {} to {}: need at least 2, from "
          "exactly 0 to exactly 1",
          fractions.size(), fractions[0], fractions[last]));
    }
    for (std::size_t k = 0; k < last; ++k) {
      if (!(fractions[k + 1] > fractions[k])) {
        throw std::invalid_argument(fmt::format(
            "OdeIntegrator::SetCollocationMesh: fractions[{}] = {} ≤ fractions[{}] = {}: must "
            "increase strictly",
            k + 1, fractions[k + 1], k, fractions[k]));
      }
    }
  }
  mesh_ = std::move(fractions);
}

IntegrationResult GaussBackend::Fail(IntegrationStatus status, double t, std::string message) {
  IntegrationResult result;
  result.status = status;
  result.t_reached = t;
  if (context_.state_bound_exceeded) {
    result.status = IntegrationStatus::kStateBound;
    message = StateBoundMessage(options_.state_bound, t);
  } else if (context_.non_finite) {
    result.status = IntegrationStatus::kNonFinite;
    message = fmt::format("the right-hand side returned NaN or Inf near t = {:.9g}", t);
  }
  result.flag_name = "GAUSS_" + std::string(status == IntegrationStatus::kConvergenceFailures
                                                ? "CONV_FAILURE"
                                                : "RHS_FAILURE");
  result.message = std::move(message);
  result.statistics = statistics_;
  return result;
}

// Newton on the stage equations of the step from (t, x) with step h; stages_ holds the guess.
// Leaves the converged stages, F at them, the Jacobians and the factorised Newton matrix.
// Globalised by backtracking: a Newton step that does not decrease ‖S⁻¹G‖₂ (the Newton direction
// descends it for any diagonal weight) is halved until it does. Full steps are taken wherever they
// decrease it, so the iterates — and the step map — are those of plain Newton there; the halving
// is for a stage that meets a steep nonlinearity with a poor guess (measured: tanh friction with
// the slip velocity through 0.7 mm/s ≈ ε on A(a)'s asymmetric modulated whip, where plain Newton
// diverged at every mesh).
bool GaussBackend::SolveStages(double t, const Vector& x, double h, std::string& failure) {
  const Index n = context_.n;
  const Index s = stages_.cols();
  const Matrix& A = coefficients_.A;
  const double tolerance = std::max(kNewtonFraction * options_.absolute_tolerance, kNewtonFloor);
  double previous_norm = kInfinity;
  double previous_merit = kInfinity;  // ‖S⁻¹G‖₂ where the last Newton step started
  double damping = 1.0;
  int iteration = 0;
  for (int pass = 0; pass < kMaxNewtonIterations + kMaxGaussHalvings; ++pass) {
    second_order_ = n % 2 == 0;
    for (Index i = 0; i < s; ++i) {
      const double ti = t + coefficients_.c(i) * h;
      stage_state_ = x + stages_.col(i);
      ++statistics_.rhs_evaluations;
      Matrix& J = jacobians_[static_cast<std::size_t>(i)];
      if (EvaluateRhs(context_, ti, stage_state_.data(), derivatives_.col(i).data()) != 0 ||
          EvaluateJacobian(context_, ti, stage_state_.data(), J.data()) != 0) {
        failure = fmt::format("the right-hand side or its Jacobian failed at t = {:.9g}", ti);
        return false;
      }
      ++statistics_.jacobian_evaluations;
      const Index h2 = n / 2;
      second_order_ = second_order_ && derivatives_.col(i).head(h2) == stage_state_.tail(h2) &&
                      (J.topLeftCorner(h2, h2).array() == 0.0).all() &&
                      J.topRightCorner(h2, h2) == Matrix::Identity(h2, h2);
    }
    // G = Z − h (A ⊗ I) F.
    double merit = 0.0;
    for (Index i = 0; i < s; ++i) {
      residual_.segment(i * n, n) = stages_.col(i) - h * derivatives_ * A.row(i).transpose();
      merit += residual_.segment(i * n, n).cwiseProduct(context_.inverse_scale).squaredNorm();
    }
    merit = std::sqrt(merit);
    // Backtrack only far from convergence: near it ‖G‖ stalls at rounding level.
    if (!(merit < previous_merit) && previous_merit < kInfinity && damping > kMinDamping &&
        !(merit <= 1e3 * tolerance)) {
      damping *= 0.5;  // back to the start of the last step, then half as far along it
      for (Index i = 0; i < s; ++i) stages_.col(i) += damping * increment_.segment(i * n, n);
      continue;
    }
    if (iteration == kMaxNewtonIterations) break;
    ++iteration;
    previous_merit = merit;
    damping = 1.0;
    FactorNewtonMatrix(h);
    ++statistics_.nonlinear_iterations;
    SolveWithNewtonMatrix(h, residual_, increment_);
    double norm = 0.0;
    for (Index i = 0; i < s; ++i) {
      stages_.col(i) -= increment_.segment(i * n, n);
      norm = std::max(norm, increment_.segment(i * n, n).cwiseProduct(context_.inverse_scale)
                                .cwiseAbs().maxCoeff());
    }
    if (!std::isfinite(norm)) break;
    if (norm <= tolerance) return true;
    // Rounding level reached: the increment stopped shrinking at a size the tolerance can't see.
    if (iteration >= 3 && norm >= 0.5 * previous_norm && norm <= 1e3 * tolerance) return true;
    previous_norm = norm;
  }
  ++statistics_.nonlinear_convergence_failures;
  failure = fmt::format(
      "Newton on the collocation equations did not converge in {} iterations at t = {:.9g} "
      "(h = {:.3g}): refine the mesh (collocation_steps)",
      kMaxNewtonIterations, t, h);
  return false;
}

// M = I − h (A ⊗ I) blockdiag(J_j) at the Jacobians of the last evaluation, factorised: M itself,
// or for a second-order system its Schur complement M_V (block (i, k):
// δ_ik I − h A_ik a_v,k − h² Σ_j A_ij A_jk a_q,j).
void GaussBackend::FactorNewtonMatrix(double h) {
  const Index n = context_.n;
  const Index s = stages_.cols();
  const Matrix& A = coefficients_.A;
  ++statistics_.linear_solver_setups;
  reduced_ = second_order_;
  if (reduced_) {
    ++statistics_.reduced_setups;
    const Index m = n / 2;
    const Index ms = m * s;
    reduced_matrix_.resize(ms, ms);
    if (m == 1) {  // a scalar oscillator (Duffing, van der Pol): the same sums on numbers
      for (Index i = 0; i < s; ++i) {
        for (Index k = 0; k < s; ++k) {
          double entry = 0.0 - (h * A(i, k)) * jacobians_[static_cast<std::size_t>(k)](1, 1);
          for (Index j = 0; j < s; ++j) {
            entry -= (h * h * A(i, j) * A(j, k)) * jacobians_[static_cast<std::size_t>(j)](1, 0);
          }
          reduced_matrix_(i, k) = entry;
        }
      }
    } else {
      // Column by column on the raw arrays (Eigen's expressions on the s² dynamic m × m blocks
      // cost several times their arithmetic): each entry 0 − h A_ik a_v,k − Σ_j h² A_ij A_jk a_q,j.
      for (Index k = 0; k < s; ++k) {
        for (Index c = 0; c < m; ++c) {
          double* column = reduced_matrix_.data() + (k * m + c) * ms;
          const double* a_v = jacobians_[static_cast<std::size_t>(k)].data() + (m + c) * n + m;
          for (Index i = 0; i < s; ++i) {
            double* entry = column + i * m;
            const double factor = h * A(i, k);
            for (Index r = 0; r < m; ++r) entry[r] = 0.0 - factor * a_v[r];
            for (Index j = 0; j < s; ++j) {
              const double factor_q = h * h * A(i, j) * A(j, k);
              const double* a_q = jacobians_[static_cast<std::size_t>(j)].data() + c * n + m;
              for (Index r = 0; r < m; ++r) entry[r] -= factor_q * a_q[r];
            }
          }
        }
      }
    }
    reduced_matrix_.diagonal().array() += 1.0;
    reduced_lu_.compute(reduced_matrix_);
    return;
  }
  for (Index i = 0; i < s; ++i) {
    for (Index j = 0; j < s; ++j) {
      newton_matrix_.block(i * n, j * n, n, n) = -h * A(i, j) * jacobians_[static_cast<std::size_t>(j)];
    }
  }
  newton_matrix_.diagonal().array() += 1.0;
  lu_.compute(newton_matrix_);
}

// out = M⁻¹ rhs (columns of s·n rows, stage by stage) with FactorNewtonMatrix's factorisation.
void GaussBackend::SolveWithNewtonMatrix(double h, const Matrix& rhs, Matrix& out) {
  if (!reduced_) {
    out = lu_.solve(rhs);
    return;
  }
  const Index n = context_.n;
  const Index m = n / 2;
  const Index s = stages_.cols();
  const Matrix& A = coefficients_.A;
  if (m == 1) {  // a scalar oscillator: the block rows below are single rows
    SolveScalarOscillator(h, rhs, out);
    return;
  }
  // a_q,j G_Q,j (Eigen's products), then G_V + h (A ⊗ I) of them and after the solve
  // Δ_Q = G_Q + h (A ⊗ I) Δ_V, column by column on the raw arrays (the same operations in the same
  // order as on the m-row blocks).
  const Index columns = rhs.cols();
  reduced_products_.resize(m * s, columns);
  for (Index j = 0; j < s; ++j) {
    reduced_products_.middleRows(j * m, m).noalias() =
        jacobians_[static_cast<std::size_t>(j)].bottomLeftCorner(m, m) * rhs.middleRows(j * n, m);
  }
  reduced_rhs_.resize(m * s, columns);
  for (Index col = 0; col < columns; ++col) {
    for (Index i = 0; i < s; ++i) {
      double* entry = &reduced_rhs_(i * m, col);
      const double* g_v = &rhs(i * n + m, col);
      for (Index r = 0; r < m; ++r) entry[r] = g_v[r];
      for (Index j = 0; j < s; ++j) {
        const double factor = h * A(i, j);
        const double* product = &reduced_products_(j * m, col);
        for (Index r = 0; r < m; ++r) entry[r] += factor * product[r];
      }
    }
  }
  reduced_products_ = reduced_lu_.solve(reduced_rhs_);  // Δ_V
  out.resize(n * s, columns);
  for (Index col = 0; col < columns; ++col) {
    for (Index i = 0; i < s; ++i) {
      double* delta_v = &out(i * n + m, col);
      double* delta_q = &out(i * n, col);
      const double* solved = &reduced_products_(i * m, col);
      const double* g_q = &rhs(i * n, col);
      for (Index r = 0; r < m; ++r) delta_v[r] = solved[r];
      for (Index r = 0; r < m; ++r) delta_q[r] = g_q[r];
      for (Index j = 0; j < s; ++j) {
        const double factor = h * A(i, j);
        const double* product = &reduced_products_(j * m, col);
        for (Index r = 0; r < m; ++r) delta_q[r] += factor * product[r];
      }
    }
  }
}

// SolveWithNewtonMatrix's block elimination for n = 2 (m = 1), entry by entry: Eigen's expressions
// on 1 × 1 blocks cost several times their arithmetic (with FactorNewtonMatrix's, 36 % of the
// Duffing scene's CPU in one `perf record`).
void GaussBackend::SolveScalarOscillator(double h, const Matrix& rhs, Matrix& out) {
  const Index s = stages_.cols();
  const Matrix& A = coefficients_.A;
  const Index columns = rhs.cols();
  reduced_products_.resize(s, columns);
  reduced_rhs_.resize(s, columns);
  out.resize(2 * s, columns);
  for (Index c = 0; c < columns; ++c) {
    for (Index j = 0; j < s; ++j) {
      reduced_products_(j, c) = jacobians_[static_cast<std::size_t>(j)](1, 0) * rhs(2 * j, c);
    }
    for (Index i = 0; i < s; ++i) {
      double sum = rhs(2 * i + 1, c);
      for (Index j = 0; j < s; ++j) sum += (h * A(i, j)) * reduced_products_(j, c);
      reduced_rhs_(i, c) = sum;
    }
  }
  reduced_products_ = reduced_lu_.solve(reduced_rhs_);  // Δ_V
  for (Index c = 0; c < columns; ++c) {
    for (Index i = 0; i < s; ++i) {
      out(2 * i + 1, c) = reduced_products_(i, c);
      double sum = rhs(2 * i, c);
      for (Index j = 0; j < s; ++j) sum += (h * A(i, j)) * reduced_products_(j, c);
      out(2 * i, c) = sum;
    }
  }
}

void GaussBackend::SolveWithNewtonMatrix(double h, const Vector& rhs, Vector& out) {
  if (!reduced_) {
    out = lu_.solve(rhs);
    return;
  }
  vector_rhs_ = rhs;
  SolveWithNewtonMatrix(h, vector_rhs_, vector_out_);
  out = vector_out_.col(0);
}

IntegrationResult GaussBackend::Run(const IntegrationRequest& request) {
  const Index n = context_.n;
  const Index s = stages_.cols();
  statistics_ = IntegrationStatistics{};
  const double t0 = request.t0;
  const double t1 = request.times[request.count - 1];
  Eigen::Map<const Vector> x0(request.x0, n);
  Eigen::Map<Vector> x_final(request.x_final, n);
  const bool with_stm = request.stm != nullptr;
  const bool with_dxdp = request.dxdp != nullptr;
  const bool with_dxdt1 = request.dxdt1 != nullptr;
  x_ = x0;
  const Index stm_columns = request.StmColumns(n);
  Eigen::Map<Matrix> stm(request.stm, with_stm ? n : 0, stm_columns);
  Eigen::Map<Vector> dxdp(request.dxdp, with_dxdp ? n : 0);
  for (Index j = 0; j < stm_columns; ++j) stm.col(j) = request.InitialColumn(j, n);
  if (with_dxdp) dxdp.setZero();
  Eigen::Map<Vector> dxdt1(request.dxdt1, with_dxdt1 ? n : 0);
  if (with_dxdt1) {
    dxdt1.setZero();
    later_.resize(n);
    earlier_.resize(n);
  }
  Index output = 0;  // outputs at t0 are x0
  while (output < request.count && request.times[output] == t0) {
    if (request.states != nullptr) Eigen::Map<Vector>(request.states + output * n, n) = x_;
    ++output;
  }
  if (t1 == t0) {
    x_final = x_;
    if (with_dxdt1) {  // the map's derivative in its length at 0: f
      ++statistics_.rhs_evaluations;
      if (EvaluateRhs(context_, t0, x_.data(), dxdt1.data()) != 0) {
        return Fail(IntegrationStatus::kRhsFailure, t0, "the right-hand side failed at t0");
      }
    }
    IntegrationResult result;
    result.t_reached = t1;
    return result;
  }
  // Step k: [t0 + θ_k (t1 − t0), t0 + θ_{k+1} (t1 − t0)], θ_k = k/N on the uniform mesh (whose
  // times are computed as t0 + k h, h = (t1 − t0)/N, as before meshes could be set).
  const bool uniform = mesh_.empty();
  const long steps = uniform ? options_.collocation_steps : static_cast<long>(mesh_.size()) - 1;
  const double span = t1 - t0;
  const double uniform_h = span / static_cast<double>(steps);
  const auto fraction = [&](long k) {
    return uniform ? static_cast<double>(k) / static_cast<double>(steps)
                   : mesh_[static_cast<std::size_t>(k)];
  };
  step_derivatives_.resize(n, steps);
  std::string failure;
  double previous_h = 0.0;
  for (long step = 0; step < steps; ++step) {
    const double t = uniform ? t0 + static_cast<double>(step) * uniform_h : t0 + fraction(step) * span;
    const double t_next = step + 1 == steps ? t1
                          : uniform ? t0 + static_cast<double>(step + 1) * uniform_h
                                    : t0 + fraction(step + 1) * span;
    const double h = uniform ? uniform_h : t_next - t;
    // Guess: the previous step's collocation polynomial extended over this step, or h·c_i·f(x).
    if (step == 0) {
      ++statistics_.rhs_evaluations;
      if (EvaluateRhs(context_, t, x_.data(), stage_state_.data()) != 0) {
        return Fail(IntegrationStatus::kRhsFailure, t, "the right-hand side failed at t0");
      }
      for (Index i = 0; i < s; ++i) stages_.col(i) = coefficients_.c(i) * h * stage_state_;
    } else {
      // γ(1 + c_i h/h_prev): the cached γ(1 + c_i) on equal steps (no copy on the uniform mesh).
      const double ratio = h / previous_h;
      for (Index i = 0; i < s; ++i) {
        const Vector* weights = &extrapolation_[static_cast<std::size_t>(i)];
        if (ratio != 1.0) {
          guess_weights_ = coefficients_.Interpolation(1.0 + ratio * coefficients_.c(i));
          weights = &guess_weights_;
        }
        stages_.col(i) = previous_x_ - x_ + previous_stages_ * *weights;
      }
    }
    previous_h = h;
    if (!SolveStages(t, x_, h, failure)) {
      return Fail(IntegrationStatus::kConvergenceFailures, t, failure);
    }
    ++statistics_.steps;
    step_derivatives_.col(step).noalias() = stages_ * derivative_weights_;
    step_derivatives_.col(step) /= std::pow(h, static_cast<double>(s));
    // Outputs inside (t, t_next]: the collocation polynomial.
    while (output < request.count &&
           (h > 0 ? request.times[output] <= t_next : request.times[output] >= t_next)) {
      if (request.states != nullptr) {
        const double theta = step + 1 == steps && request.times[output] == t1
                                 ? 1.0
                                 : (request.times[output] - t) / h;
        output_weights_ = coefficients_.Interpolation(theta);
        Eigen::Map<Vector>(request.states + output * n, n) = x_ + stages_ * output_weights_;
      }
      ++output;
    }
    if (with_stm) {
      // Right-hand sides h (A ⊗ I) [J_i Φ_n, J_i q_n + ∂f/∂p, J_i r_n + ∂f/∂t·(step + c_i)/N]
      // (+ Z/(t1 − t0) for r): stm's columns, then dxdp's and dxdt1's when asked for.
      const Index p_column = stm_columns;
      const Index t1_column = stm_columns + (with_dxdp ? 1 : 0);
      const Index columns = t1_column + (with_dxdt1 ? 1 : 0);
      sensitivity_rhs_.resize(n * s, columns);
      blocks_.resize(n * s, columns);
      for (Index i = 0; i < s; ++i) {
        const Matrix& J = jacobians_[static_cast<std::size_t>(i)];
        const double ti = t + coefficients_.c(i) * h;
        blocks_.block(i * n, 0, n, stm_columns).noalias() = J * stm;
        stage_state_ = x_ + stages_.col(i);
        if (with_dxdp) {
          if (EvaluateDfDparameter(context_, ti, stage_state_.data()) != 0) {
            return Fail(IntegrationStatus::kRhsFailure, t, "∂f/∂p failed");
          }
          blocks_.block(i * n, p_column, n, 1).noalias() = J * dxdp;
          blocks_.block(i * n, p_column, n, 1) += context_.dfdp;
        }
        if (with_dxdt1) {
          blocks_.block(i * n, t1_column, n, 1).noalias() = J * dxdt1;
          // ∂f/∂t by a central difference (exactly 0 for an autonomous f): the stage time
          // t0 + (θ_k + c_i (θ_{k+1} − θ_k))(t1 − t0) moves with t1 at θ_k + c_i (θ_{k+1} − θ_k)
          // ((k + c_i)/N on the uniform mesh).
          const double dt = CentralDifferenceStep(ti, std::abs(h));
          if (EvaluateRhs(context_, ti + dt, stage_state_.data(), later_.data()) != 0 ||
              EvaluateRhs(context_, ti - dt, stage_state_.data(), earlier_.data()) != 0) {
            return Fail(IntegrationStatus::kRhsFailure, t, "the right-hand side failed");
          }
          const double moves =
              uniform ? (static_cast<double>(step) + coefficients_.c(i)) / static_cast<double>(steps)
                      : fraction(step) + coefficients_.c(i) * (fraction(step + 1) - fraction(step));
          blocks_.block(i * n, t1_column, n, 1) += (later_ - earlier_) / (2.0 * dt) * moves;
        }
      }
      // h (A ⊗ I) of the blocks, column by column on the raw arrays (the same operations in the
      // same order as on the n-row blocks). The step h = (θ_{k+1} − θ_k)(t1 − t0) itself:
      // ∂G/∂t1 = −(A ⊗ I) F (θ_{k+1} − θ_k) = −Z/(t1 − t0) at the stages.
      for (Index col = 0; col < columns; ++col) {
        for (Index i = 0; i < s; ++i) {
          double* entry = &sensitivity_rhs_(i * n, col);
          for (Index r = 0; r < n; ++r) entry[r] = 0.0;
          for (Index j = 0; j < s; ++j) {
            const double factor = h * coefficients_.A(i, j);
            const double* block = &blocks_(j * n, col);
            for (Index r = 0; r < n; ++r) entry[r] += factor * block[r];
          }
          if (col == t1_column && with_dxdt1) {
            for (Index r = 0; r < n; ++r) entry[r] += stages_(r, i) / (t1 - t0);
          }
        }
      }
      SolveWithNewtonMatrix(h, sensitivity_rhs_, blocks_);
      // Φ += Σ_i d_i K_i (and q, r), the stages in order.
      for (Index col = 0; col < columns; ++col) {
        double* column = col < stm_columns ? &stm(0, col)
                         : col == p_column && with_dxdp ? dxdp.data()
                                                        : dxdt1.data();
        for (Index i = 0; i < s; ++i) {
          const double weight = coefficients_.d(i);
          const double* block = &blocks_(i * n, col);
          for (Index r = 0; r < n; ++r) column[r] += weight * block[r];
        }
      }
    }
    previous_x_ = x_;
    previous_stages_ = stages_;
    x_ += stages_ * coefficients_.d;
  }
  x_final = x_;
  IntegrationResult result;
  result.t_reached = t1;
  result.statistics = statistics_;
  result.warnings = context_.warnings;
  return result;
}

}  // namespace detail

namespace {

detail::GaussCoefficients CoefficientsFor(const char* caller, int stages) {
  if (stages < 1 || stages > 6) {
    throw std::invalid_argument(fmt::format("{}: stages = {}: must lie in [1, 6]", caller, stages));
  }
  return detail::GaussCoefficients::Make(stages);
}

// R(z) = 1 + z bᵀ(I − zA)⁻¹𝟙.
std::complex<double> StabilityFunction(const detail::GaussCoefficients& g, std::complex<double> z) {
  const Index s = g.c.size();
  const Eigen::MatrixXcd M = Eigen::MatrixXcd::Identity(s, s) - z * g.A.cast<std::complex<double>>();
  const Eigen::VectorXcd y = M.partialPivLu().solve(Eigen::VectorXcd::Ones(s));
  return 1.0 + z * g.b.cast<std::complex<double>>().dot(y);
}

}  // namespace

std::complex<double> GaussStabilityFunction(int stages, std::complex<double> z) {
  return StabilityFunction(CoefficientsFor("GaussStabilityFunction", stages), z);
}

double GaussLogGrowth(int stages, std::complex<double> lambda, const Vector& steps) {
  const detail::GaussCoefficients g = CoefficientsFor("GaussLogGrowth", stages);
  double sum = 0.0;
  for (Index k = 0; k < steps.size(); ++k) sum += std::log(std::abs(StabilityFunction(g, lambda * steps(k))));
  return sum;
}

}  // namespace rubcont
