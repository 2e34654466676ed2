// Craig–Bampton component-mode reduction (Craig & Bampton 1968), as the thesis's XLTRC² models
// keep physical coordinates at the contacts (§3.1–3.2): the boundary coordinates stay physical,
// the interior ones are spanned by the static constraint modes (the interior's deflection when one
// boundary coordinate moves by 1 and the others are held) and the lowest fixed-interface modes
// (the structure's modes with every boundary coordinate held):
//     u = B q,  q = (u_b, η),  B = [[I, 0], [−K_ii⁻¹K_ib, Φ_m]]  (rows in the original order),
// and every matrix X of the structure becomes BᵀXB. With no modes this is Guyan's static
// condensation; with all of them the reduction is exact. The boundary must hold the structure
// against rigid motion (K_ii positive definite), as two contact planes hold a free–free rotor.
#pragma once

#include <vector>

#include "models/beam.h"
#include "models/input_error.h"
#include "solvers/types.h"

namespace rubcont {

struct ModalReduction {
  std::vector<Index> boundary;   // original indices of the reduced coordinates 0 … b−1, in order
  Matrix basis;                  // B, n × (b + m)
  Vector interface_frequencies;  // the m fixed-interface modes kept [rad/s], ascending

  Index ReducedCoordinates() const { return basis.cols(); }
  StructuralMatrices Reduce(const StructuralMatrices& full) const;
};

// Keeps the `modes` lowest fixed-interface modes (mass-normalized, from K_ii and M_ii at rest).
// Throws std::invalid_argument for a boundary index out of range or repeated, or a boundary that
// leaves the interior free to move rigidly; ModelInputError (input "modes") for negative modes or
// more than the interior has of finite frequency.
ModalReduction CraigBampton(const StructuralMatrices& full, const std::vector<Index>& boundary,
                            Index modes);

}  // namespace rubcont
