#include "models/component_modes.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

namespace rubcont {

StructuralMatrices ModalReduction::Reduce(const StructuralMatrices& full) const {
  auto project = [&](const Matrix& x) -> Matrix {
    Matrix reduced = basis.transpose() * x * basis;
    return 0.5 * (reduced + reduced.transpose());  // symmetric to the last bit
  };
  return {project(full.mass), project(full.damping), project(full.stiffness),
          project(full.gyroscopic)};
}

ModalReduction CraigBampton(const StructuralMatrices& full, const std::vector<Index>& boundary,
                            Index modes) {
  const Index n = full.Coordinates();
  std::vector<bool> is_boundary(static_cast<std::size_t>(n), false);
  for (Index b : boundary) {
    if (b < 0 || b >= n) {
      throw std::invalid_argument("boundary coordinate " + std::to_string(b) +
                                  ": must be a coordinate of the structure (0 to " +
                                  std::to_string(n - 1) + ")");
    }
    if (is_boundary[static_cast<std::size_t>(b)]) {
      throw std::invalid_argument("boundary coordinate " + std::to_string(b) +
                                  ": given twice");
    }
    is_boundary[static_cast<std::size_t>(b)] = true;
  }
  std::vector<Index> interior;
  for (Index i = 0; i < n; ++i) {
    if (!is_boundary[static_cast<std::size_t>(i)]) interior.push_back(i);
  }
  const Index nb = static_cast<Index>(boundary.size());
  const Index ni = static_cast<Index>(interior.size());
  if (modes < 0) {
    throw ModelInputError("modes", "modes = " + std::to_string(modes) + ": must be non-negative");
  }

  const Matrix k_ii = full.stiffness(interior, interior), m_ii = full.mass(interior, interior);
  const Matrix k_ib = full.stiffness(interior, boundary);
  const Eigen::LLT<Matrix> k_factor(k_ii);
  // A rigid motion left to the interior makes K_ii singular; round-off may leave its Cholesky
  // pivot positive at ~1e-16 of the largest, so the smallest pivot decides (a short element beside
  // long ones makes K_ii ill-conditioned, not singular: its pivots stay above 1e-12 of the largest,
  // where the condition-number estimate fell to 1e-14 for the flexible thesis rotors).
  const Vector pivots =
      ni > 0 ? Vector(Matrix(k_factor.matrixL()).diagonal().cwiseAbs2()) : Vector(0);
  if (ni > 0 && (k_factor.info() != Eigen::Success ||
                 !(pivots.minCoeff() > 1e-13 * pivots.maxCoeff()))) {
    throw std::invalid_argument(
        "boundary: the interior stiffness K_ii is not positive definite — the boundary "
        "coordinates do not hold the structure against rigid motion");
  }
  const Matrix constraint = ni > 0 ? Matrix(-k_factor.solve(k_ib)) : Matrix(0, nb);

  // M_ii φ = μ K_ii φ with μ = 1/ω²: K_ii is definite, M_ii may be singular (massless
  // coordinates have μ = 0, infinite frequency, and are never kept).
  Matrix interface(ni, 0);
  Vector frequencies(0);
  if (modes > 0) {
    const Eigen::GeneralizedSelfAdjointEigenSolver<Matrix> eig(m_ii, k_ii);
    if (eig.info() != Eigen::Success) {
      throw std::runtime_error("the fixed-interface eigenproblem failed");
    }
    const Vector& mu = eig.eigenvalues();  // ascending; the largest μ are the lowest modes
    const double mu_max = ni > 0 ? mu.maxCoeff() : 0.0;
    Index finite = 0;
    for (Index i = 0; i < ni; ++i) finite += mu(i) > 1e-13 * mu_max ? 1 : 0;
    if (modes > finite) {
      throw ModelInputError("modes", "modes = " + std::to_string(modes) +
                                         ": the interior has only " + std::to_string(finite) +
                                         " fixed-interface modes of finite frequency");
    }
    interface.resize(ni, modes);
    frequencies.resize(modes);
    for (Index j = 0; j < modes; ++j) {
      const Index col = ni - 1 - j;
      frequencies(j) = 1.0 / std::sqrt(mu(col));
      interface.col(j) = eig.eigenvectors().col(col) / std::sqrt(mu(col));  // φᵀM_iiφ = 1
    }
  }

  ModalReduction out;
  out.boundary = boundary;
  out.interface_frequencies = frequencies;
  out.basis = Matrix::Zero(n, nb + modes);
  for (Index c = 0; c < nb; ++c) out.basis(boundary[c], c) = 1.0;
  out.basis(interior, Eigen::seqN(0, nb)) = constraint;
  out.basis(interior, Eigen::seqN(nb, modes)) = interface;
  return out;
}

}  // namespace rubcont
