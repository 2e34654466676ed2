// Floquet multipliers of a periodic orbit from the state-transition matrices of its shooting
// segments, M_0, …, M_{N−1} (each n × n; M_i maps a perturbation at the start of segment i to its
// end, so the monodromy is M_{N−1} ⋯ M_1 M_0).
//
// Forming that product loses every multiplier smaller than ε·‖product‖: for a strongly contracting
// orbit (van der Pol at μ = 10 has a multiplier near e^{−290}) the small ones come out as round-off.
// The block-cyclic pencil avoids the product (Fairgrieve & Jepson 1991; Lust 2001, "Improved
// numerical Floquet multipliers", IJBC 11(9)): with v_{i+1} = M_i v_i,
//
//     A v = μ B v,   A = ⎡ M_0  −I              ⎤     B = ⎡ 0            ⎤
//                        ⎢      M_1  −I         ⎥         ⎢    0         ⎥
//                        ⎢           ⋱    ⋱     ⎥         ⎢       ⋱      ⎥
//                        ⎣                M_{N−1}⎦         ⎣ I        0   ⎦
//
// has the n multipliers as its finite generalized eigenvalues and (N−1)n semisimple infinite ones.
// Real QZ (Eigen's GeneralizedEigenSolver) is backward stable for the pencil, i.e. for each factor
// separately, which keeps small multipliers to relative accuracy ~ ε·cond(M_i) instead of ε·‖Π M‖.
// Cost O((Nn)³) against O(N n³) for a periodic Schur method (Bojanczyk, Golub & Van Dooren 1992),
// which would be the next step if N n grows beyond a few hundred.
//
// Trivial multipliers (1 for the phase of an autonomous orbit; two for a relative periodic orbit:
// time shift and group rotation) are deflated exactly rather than by picking the values closest to
// 1, which fails where it matters (at a fold a nontrivial multiplier is also 1). Given orthonormal
// bases U_i of the trivial directions at each segment start (M_i maps span U_i into span U_{i+1},
// indices cyclic), and W_i completing them to orthonormal bases, each factor is block triangular,
//     [U_{i+1} W_{i+1}]ᵀ M_i [U_i W_i] = [[A_i, B_i], [E_i, C_i]],  E_i ≈ 0,
// so the multipliers split into eig(Π A_i) (trivial, ≈ 1) and eig(Π C_i) (the nontrivial ones).
// ‖E_i‖ measures how far the computed orbit is from exact invariance (reported, not hidden).
#pragma once

#include <vector>

#include "solvers/types.h"

namespace rubcont {

enum class FloquetMethod {
  kPencil,   // finite eigenvalues of the block-cyclic pencil, real QZ: no product is formed
  kProduct,  // eigenvalues of the explicitly formed product (cheap, inaccurate for small multipliers)
};
const char* ToString(FloquetMethod method);

// Eigenvalues of M_{N−1} ⋯ M_0 (factors[0] acts first), sorted by decreasing modulus.
// All factors must be square and of one size (std::invalid_argument otherwise).
ComplexVector ProductEigenvalues(const std::vector<Matrix>& factors, FloquetMethod method);

struct FloquetResult {
  // Nontrivial multipliers, sorted by decreasing modulus.
  ComplexVector multipliers;
  // Multipliers of the deflated trivial subspace, eig(Π A_i): ≈ 1 on a converged orbit.
  ComplexVector trivial;
  // max_i ‖E_i‖₂ / ‖M_i‖₂: 0 when the trivial subspace is exactly invariant.
  double invariance_defect = 0.0;
  bool valid = false;  // false when a factor was not finite
};

// Floquet multipliers of the cycle M_{N−1} ⋯ M_0 with trivial directions deflated.
// trivial_bases: empty (no deflation), or N matrices n × k (k < n, the same k for all, full column
// rank; orthonormalized here) where trivial_bases[i] spans the trivial directions at the start of
// segment i and M_{N−1} maps span trivial_bases[N−1] back into span trivial_bases[0].
FloquetResult FloquetMultipliers(const std::vector<Matrix>& factors,
                                 const std::vector<Matrix>& trivial_bases,
                                 FloquetMethod method = FloquetMethod::kPencil);

}  // namespace rubcont
