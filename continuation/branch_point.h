// Simple branch points located by Newton on a regular augmented system (the branch-point system
// of Allgower & Georg 1990 §8.1 and MATCONT's BP; Govaerts 2000 §4.3).
//
// At a simple branch point x* of F(x) = 0, x = (u, λ) ∈ Rⁿ⁺¹, the n × (n+1) matrix DF(x*) has rank
// n − 1: a one-dimensional left kernel φ and a two-dimensional kernel. The pseudo-arclength
// corrector's bordered matrix [DF; τᵀ] is singular there, so correcting points ever closer to x*
// converges ever more slowly, and bisecting det [DF; τᵀ] along the branch stalls short of it. The
// system in the unknowns (x, β, φ) ∈ R²ⁿ⁺²
//     F(x) + β φ = 0            n equations
//     DF(x)ᵀ φ   = 0            n + 1
//     φᵀφ − 1    = 0            1
// is regular at a simple branch point (where β = 0) and Newton converges quadratically to it. All
// in the engine's scaled variables (continuation/scaled_system.h). The block ∂(DFᵀφ)/∂x =
// Σ_i φ_i ∇²F̂_i comes from central differences of DF̂ along each coordinate (2(n + 1) Jacobians per
// iteration; solvers/finite_difference.h's step).
#pragma once

#include <string>

#include "continuation/options.h"
#include "continuation/scaled_system.h"

namespace rubcont {

struct BranchPointLocation {
  bool converged = false;
  Vector x;                      // (û, λ̂), scaled
  double beta = 0.0;             // 0 at a branch point; large where there is none near the guess
  Vector phi;                    // the unit left null vector of DF̂ there
  int iterations = 0;
  double residual_norm = 0.0;    // ‖[F̂ + βφ; DF̂ᵀφ / max(1, max|DF̂|); φᵀφ − 1]‖∞
  double last_correction = 0.0;  // ‖Δ(x̂, β, φ)‖∞ of the last Newton step
  std::string message;           // why not, when !converged
};

// Newton from a guess x̂ near a branch point (φ starts as DF̂'s left singular vector of the
// smallest singular value, β as −φᵀF̂). Converged when the residual is at most
// options.residual_tolerance after a correction of at most options.step_tolerance.
BranchPointLocation LocateBranchPoint(ScaledSystem& system, const Vector& x_guess,
                                      const LocationOptions& options = {});

}  // namespace rubcont
