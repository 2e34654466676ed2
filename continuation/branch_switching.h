// Branch switching at a simple branch point by the algebraic branching equation (Keller 1977;
// Allgower & Georg 1990, §8.3; as in AUTO).
//
// At a simple branch point x* the n × (n+1) matrix DF̂(x*) has a two-dimensional kernel and a
// one-dimensional left kernel ψ. Write the kernel as span{τ₁, φ}, τ₁ the incoming branch's tangent
// (projected onto the kernel) and φ ⊥ τ₁. Both branch tangents t = ατ₁ + βφ satisfy the ABE
//     ψᵀ D²F̂(x*)(t, t) = a₁₁α² + 2a₁₂αβ + a₂₂β² = 0,     a_ij = ψᵀ D²F̂(p_i, p_j),
// a quadratic form with two real root directions when the branch point is simple (a₁₂² > a₁₁a₂₂).
// We take the root least aligned with τ₁ (the incoming branch is the other root, up to the error
// of the location). Kernel and ψ come from an SVD of DF̂(x*) (solvers/linear_algebra.h); the
// second derivatives from central differences of DF̂ along p_j (exact for the quadratic problems of
// the tests, O(h²) otherwise; only a direction is needed, which the corrector then refines).
//
// Why not simply perturb along φ? For a pitchfork φ is the other branch's tangent and that works;
// for a transcritical branch point the other branch is oblique (β ≠ ±1) and a step along φ lands
// off both branches at distance O(Δs), leaving it to Newton to pick one. The ABE predicts the
// direction to O(h²) at the cost of three differences.
#pragma once

#include <string>

#include "continuation/branch.h"
#include "continuation/continuation.h"
#include "continuation/problem.h"

namespace rubcont {

struct BranchSwitch {
  bool ok = false;
  std::string message;      // why not, when !ok
  Vector tangent;           // the other branch's unit tangent, scaled (û, λ̂), side +1
  Vector du;                // the same direction in problem units
  double dlambda = 0.0;
  double a11 = 0.0;         // ABE coefficients in the (τ₁, φ) basis
  double a12 = 0.0;
  double a22 = 0.0;
  double angle = 0.0;       // angle between the two branches, rad, in (0, π/2]
  double singular_value = 0.0;  // the second smallest singular value of DF̂ at the point (≈ 0)
};

// Side convention: `tangent` (side +1) has a positive λ-component when that component exceeds
// 1e-8, else a positive largest-magnitude state component; side −1 is the opposite half.
BranchSwitch ComputeBranchSwitch(Problem& problem, const SpecialPoint& branch_point);

// Continues the other branch through a located simple branch point (side ±1, see above): the
// branch point is the first point. Throws std::invalid_argument when the special point is not a
// branch point.
Branch ContinueFromBranchPoint(Problem& problem, const SpecialPoint& branch_point, int side,
                               const ContinuationOptions& options = {},
                               const StepCallback& callback = {});

}  // namespace rubcont
