// Floquet multipliers of a periodic orbit from the state-transition matrices of its shooting
// segments, M_0, …, M_{N−1} (each n × n; M_i maps a perturbation at the start of segment i to its
// end, so the monodromy is M_{N−1} ⋯ M_1 M_0).
//
// Forming that product loses every multiplier smaller than ε·‖product‖: for a strongly contracting
// orbit (van der Pol at μ = 10 has a multiplier e^{−311.8}) the small ones come out as round-off,
// and for a strongly unstable one (multipliers 1e20 and 1.001) even the multiplier near the unit
// circle — the one that decides stability — drowns in ε·1e20. Three methods are offered:
//
// kPeriodicSchur (default): the periodic real Schur form (Bojanczyk, Golub & Van Dooren 1992;
//   Lust 2001, "Improved numerical Floquet multipliers", IJBC 11(9)), here in block form, computed
//   by unshifted periodic QR (periodic orthogonal iteration): Q_{i+1} R_i = M_i Q_i (QR,
//   i = 0…N−1), repeated with Q_0 ← Q_N. The bases converge to Q_{i+1}ᵀ M_i Q_i block upper
//   triangular; each multiplier of distinct modulus is then a product of diagonal entries
//   Π_i R_i(j,j) — each factor computed to relative accuracy, so the small and the large
//   multipliers keep theirs — and multipliers of similar modulus (complex pairs, moduli within a
//   factor ≈ 2.4, which the unshifted iteration separates slowly) come from the small, well
//   conditioned product of their diagonal block. Cost O(sweeps · N n³): measured 2.7 ms for
//   N = 10, n = 16 (QZ pencil 7.6 ms), 15 ms for N = 40 (QZ 250 ms).
// kPencil: the n finite eigenvalues of the block-cyclic pencil (Fairgrieve & Jepson 1991)
//
//     A v = μ B v,   A = ⎡ M_0  −I              ⎤     B = ⎡ 0            ⎤
//                        ⎢      M_1  −I         ⎥         ⎢    0         ⎥
//                        ⎢           ⋱    ⋱     ⎥         ⎢       ⋱      ⎥
//                        ⎣                M_{N−1}⎦         ⎣ I        0   ⎦
//
//   by real QZ (Eigen's GeneralizedEigenSolver), O((Nn)³). Each factor is scaled by a power of two
//   near its norm first, so that finite and infinite eigenvalues separate by |β|/|α| however
//   large the multipliers. QZ is backward stable for the pencil as a whole, not for each factor:
//   its error falls on the identity and zero blocks too, and measured (tests/solvers/
//   floquet_test.cpp, tests/shooting/van_der_pol_test.cpp) it loses graded multipliers like the
//   product does (a unit-circle pair beside 1e20; e^{−311.8} on van der Pol). Kept for comparison.
// kProduct: eigenvalues of the explicit product; cheap, for comparison.
//
// Trivial multipliers (1 for the phase of an autonomous orbit; two for a relative periodic orbit:
// time shift and group rotation) are deflated exactly rather than by picking the values closest to
// 1, which fails where it matters (at a fold a nontrivial multiplier is also 1). Given bases U_i of
// the trivial directions at every segment start (f(x_i), and g(x_i) for a relative orbit) —
// M_i maps span U_i into span U_{i+1}, indices cyclic — completed to orthonormal [U_i W_i], each
// factor is block triangular up to the orbit's own error,
//     [U_{i+1} W_{i+1}]ᵀ M_i [U_i W_i] = [[A_i, B_i], [E_i, C_i]],  E_i ≈ 0,
// and the multipliers split into eig(Π A_i) (trivial, ≈ 1) and eig(Π C_i) (the nontrivial ones).
// Ignoring E_i costs, per segment, a relative error ‖E_i‖/σ(C_i): a multiplier is resolved as
// long as each segment's contraction stays above the integration error (van der Pol μ = 10,
// e^{−311.8}: 40 segments give it to 1e-3 in log μ, 20 do not). Transporting one basis around the
// cycle instead (U_{i+1} = orth(M_i U_i)) would put the whole error in one factor, but it is
// unstable as soon as a nontrivial multiplier exceeds 1: the transported direction turns into the
// expanding one (measured on the repelling van der Pol cycle: log μ = 23 instead of 311.8).
#pragma once

#include <vector>

#include "solvers/types.h"

namespace rubcont {

enum class FloquetMethod {
  kPeriodicSchur,  // periodic Schur form by periodic orthogonal iteration (structured, accurate)
  kPencil,         // finite eigenvalues of the block-cyclic pencil by real QZ
  kProduct,        // eigenvalues of the explicitly formed product (cheap, loses small multipliers)
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
  // max_i ‖E_i‖_F / ‖M_i‖_F: 0 when the trivial subspace is exactly invariant.
  double invariance_defect = 0.0;
  // The smallest modulus the method resolves: a nontrivial multiplier below it is round-off, not a
  // value. kProduct and kPencil: ε·Π_i ‖C_i‖_F (C_i the factors after deflation; ε = 2.2e-16),
  // the error of forming the product, which every eigenvalue of it carries (measured: QZ on the
  // pencil loses graded multipliers like the product). kPeriodicSchur: 0, each multiplier keeps
  // its relative accuracy. +∞ when the bound overflows.
  double resolution = 0.0;
  bool valid = false;  // false when a factor was not finite
  // Nontrivial multipliers with |μ| below `resolution`: a stability verdict that rests on them is
  // not one (e.g. a unit-circle pair beside a multiplier of 1e20, kProduct).
  int Unresolved() const;
};

// Floquet multipliers of the cycle M_{N−1} ⋯ M_0 with trivial directions deflated.
// trivial_bases: empty (no deflation), or N matrices n × k (1 ≤ k < n, the same k for all, full
// column rank; orthonormalized here) where trivial_bases[i] spans the trivial directions at the
// start of factor i, and factor N−1 maps span trivial_bases[N−1] back into span trivial_bases[0].
FloquetResult FloquetMultipliers(const std::vector<Matrix>& factors,
                                 const std::vector<Matrix>& trivial_bases,
                                 FloquetMethod method = FloquetMethod::kPeriodicSchur);

}  // namespace rubcont
