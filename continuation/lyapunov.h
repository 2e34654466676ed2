// The first Lyapunov coefficient of a Hopf point of equilibria of F(u, λ) = 0: whether the
// periodic orbits born there are stable and exist beyond the Hopf point (l1 < 0, supercritical: a
// gentle onset) or unstable and exist before it (l1 > 0, subcritical: a jump with hysteresis).
//
// Kuznetsov (Elements of Applied Bifurcation Theory, 3rd ed., eq. 3.20): with A = F_u at the Hopf
// point, A q = iω q, Aᵀ p = −iω p, ⟨q, q⟩ = 1, ⟨p, q⟩ = 1 (⟨x, y⟩ = x̄ᵀ y),
//   l1 = 1/(2ω) Re[ ⟨p, C(q,q,q̄)⟩ − 2⟨p, B(q, A⁻¹ B(q,q̄))⟩ + ⟨p, B(q̄, (2iω − A)⁻¹ B(q,q))⟩ ],
// B and C the second and third derivatives of F in u. They come from central differences of the
// residual along real directions (steps relative to Problem::Scale(); the complex arguments by
// multilinearity and polarization), so any Problem works, analytic derivatives or not. For
// ż = iωz + σ z|z|² (z = x + iy) this gives l1 = 2σ/ω: the value depends on the normalization of q,
// its sign does not.
//
// A Jacobian with a zero eigenvalue besides the pair (a continuous symmetry: rotating waves are
// relative equilibria) makes A singular; the coefficient then needs the reduced system and is
// returned as not valid, with that reason.
#pragma once

#include <complex>
#include <functional>
#include <string>

#include "continuation/problem.h"

namespace rubcont {

struct LyapunovCoefficient {
  bool valid = false;
  // The first Lyapunov coefficient (see above), from the step h/10; valid only when it agrees
  // with the one from h to 1 % (the finite differences are trusted only where they converge).
  double l1 = 0.0;
  double l1_coarse = 0.0;  // the same from the step h
  double omega = 0.0;  // the Hopf frequency ω > 0 (of the eigenvalue pair nearest the axis)
  double real_part = 0.0;  // Re of that pair: how far (u, λ) is from the Hopf point
  std::string message;     // why not valid
};

// Whether the two steps of `c` agree to 1 % of max(|l1|, |l1_coarse|, scale), `scale` a size of
// l1 known from elsewhere (e.g. |l1| where a Hopf curve starts): then l1 is known to that accuracy
// also where it is near 0 — at a generalized Hopf point, where `valid` (1 % of |l1| itself) fails.
bool AgreesTo(const LyapunovCoefficient& c, double scale);

// `step` is the relative finite-difference step h (in units of Problem::Scale()). `near`: the
// Hopf eigenvalue ≈ iω (e.g. SpecialPoint::critical_value) picks the pair; 0: the pair with Im > 0
// nearest the imaginary axis.
LyapunovCoefficient FirstLyapunovCoefficient(Problem& problem, const Vector& u, double lambda,
                                             double step = 1e-3,
                                             std::complex<double> near = {0.0, 0.0});

// The same for a relative equilibrium x0 of a field F(·, λ) = `problem` that commutes with a
// one-parameter rotation group with generator x ↦ G x (`generator`): a rotating wave in its
// co-rotating frame, whose Jacobian has the zero eigenvalue of g = G x0. The coefficient is that
// of the slice-reduced field on the hyperplane gᵀ(x − x0) = 0 (the method of slices): with N an
// orthonormal basis of g⊥ and c(x) = gᵀF(x) / (gᵀG x) the drift along the group,
//   y ↦ Nᵀ [F(x0 + N y) − c(x0 + N y) G (x0 + N y)],
// whose Hopf pair is that of the wave and whose zero eigenvalue is gone. Its sign says whether the
// modulated waves born at the Hopf point are stable (l1 < 0) or not.
LyapunovCoefficient FirstLyapunovCoefficientOfRelativeEquilibrium(
    Problem& problem, const Vector& x0, double lambda,
    const std::function<Vector(const Vector&)>& generator, double step = 1e-3,
    std::complex<double> near = {0.0, 0.0});

}  // namespace rubcont
