// A modulated whirl or whip of the rub model at one running speed (level L2): a relative periodic
// orbit (docs/theory.md §7), periodic in a frame that turns by φ per period T, found by shooting
// (ShootingProblem, kRelative) from a point near it — the end of a settled transient — and read
// the way a time-marching sweep reads a precession. Where ContinueOrbitsFromHopf reaches such an
// orbit by continuation from its Hopf point (small steps in speed, minutes), this solves it at
// the speed asked for, from where a transient ended.
//
// The start. The transient's fixed-frame state is taken into the frame precessing backward at
// Ω_f (the transient's precession; RubRotatingFrame::ToRotatingFrame at t = 0) and integrated on
// over a short stretch, sampled. The modulation shows in the slip velocity V of the first contact,
// which the rotation of the frame does not change (the contact radius barely moves while the
// contact holds: its penetration is ~1e-8 m): the dominant frequency of V over the stretch
// (TwoSidedSpectrum, DominantPeak: Hann window, refined below the bin width) is the modulation
// frequency 1/T. The start x_0 is the state at the end of the stretch, and φ the turn of the first
// contact's d = u_rotor − u_stator over one more period T from there (x(T) = R_φ x(0) with
// R_φ = e^{jφ} as OdeSystem::Rotate).
//
// The precession. With x(T) = R_φ x(0), p(t) = e^{jφt/T} q(t) with q T-periodic, so the
// fixed-frame motion u = e^{−jΩ_f t} p is a sum of backward precessions
//     Ω_k = Ω_f − φ/T − 2πk/T,   k ∈ Z,
// with the amplitudes |c_k| of the Fourier coefficients of q over one period (at the first
// contact's d). k = 0 is the carrier: φ continues from 0 at the Hopf point where the orbit is born,
// and the transient's own precession is Ω_f. The component of largest amplitude among the
// backward ones (Ω_k > 0) is what a sweep reports as its precession (the dominant negative
// frequency of d, sweeps/rub_sweep.h).
//
// Locked orbits (`laps` m > 1). Where a two-frequency whip (a relative 2-torus, shooting/
// modulated_torus.h) locks at a p:m resonance, the motion is again a relative periodic orbit, but
// one of m modulation periods: the slip's dominant line still gives T, the orbit closes after mT
// (C(a) at 49.4 rpm: R_{−φ}x(mT) − x(0) is 7e-3 of |x| for m = 1, 2.5e-5 for m = 3, scaled). T
// and the harmonics below are then the whole orbit's: the lines are k/(mT) apart.
#pragma once

#include <complex>
#include <optional>
#include <string>

#include "models/rub_model.h"
#include "shooting/orbit_branches.h"
#include "shooting/shooting.h"
#include "solvers/constants.h"
#include "solvers/newton.h"

namespace rubcont {

struct ModulatedOrbitOptions {
  // Segments and integrator (the kind is kRelative); the search's too unless search_integrator
  // is set.
  ShootingOptions shooting;
  // Tolerances above the integration error: the residual is only as smooth as the integration
  // (about 100·rtol; tests/shooting/van_der_pol_test.cpp).
  NewtonOptions newton;
  double search_duration = 0.05;   // the sampled stretch [s] > 0: 1/T to about 1/(duration·N)
  double search_rate = 20000.0;    // its samples per second [1/s], ≥ 16/search_duration
  int harmonics = 3;              // Fourier components |k| ≤ harmonics examined (≥ 0)
  int laps = 1;                   // modulation periods per orbit, 1 … 64 (above: locked orbits)
  // The integrator of the search and of the turn that measures φ: the transient's, where the
  // caller settled the state with one (the orbits stage: the sweep's). Unset: the shooting's, with
  // CVODES BDF ≤ 2 at its tolerances in place of Gauss collocation, which may not keep a locked
  // whip: C(a) at 75 rpm (the 3:7 orbit, a 4 s search) under BDF ≤ 2 at 1e-7 guessed 7T =
  // 0.0563839 s against the orbit's 0.0562348 and Newton failed; under Dormand–Prince at 1e-9,
  // the orbit in 4 iterations (docs/studies/attractors.md).
  std::optional<IntegratorOptions> search_integrator;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const ModulatedOrbitOptions& options);

// d = u_rotor − u_stator of contact 0, from a state [q; v] of either frame (real pairs).
std::complex<double> FirstContactGap(const RubStructure& structure, ConstVectorRef x);

// The start of the modulated solvers (this one and shooting/modulated_torus.h): `fixed_state` taken
// into `frame` at t = 0 and integrated over `duration` s sampled at `rate` per s (BDF ≤ 2 where the
// options say Gauss collocation); the modulation period T = 1 / the dominant frequency of contact
// 0's slip velocity, and the co-rotating state at the stretch's end. found = false, with the
// message, when the integration fails or the slip does not vary.
// Throws std::invalid_argument unless duration > 0 is finite and gives ≥ 16 samples at `rate`
// (the fields named `owner`.search_duration, `owner`.search_rate).
void ValidateModulationSearch(const std::string& owner, double duration, double rate);
// The inputs both modulated solvers take: throws std::invalid_argument, naming `solver`, unless
// frame_rate and omega are positive and fixed_state has the structure's number of states.
void CheckModulationInputs(const std::string& solver, const RubStructure& structure, double omega,
                           double frame_rate, const Vector& fixed_state);
struct ModulationSearch {
  bool found = false;
  std::string message;
  double period = kNaN;
  Vector state;
};
ModulationSearch SearchModulation(RubRotatingFrame& frame, const Vector& fixed_state,
                                  const IntegratorOptions& integrator, double duration, double rate);

struct ModulatedOrbit {
  bool converged = false;
  std::string message;       // how the search and Newton went, one sentence with numbers
  NewtonResult newton;
  double frame_rate = 0.0;   // Ω_f [rad/s]
  int laps = 1;              // modulation periods per orbit (the options')
  double period = kNaN;    // T [s], all laps
  double rotation = kNaN;  // φ [rad]
  double carrier_hz = kNaN;   // Ω_0 / 2π [Hz]
  double dominant_hz = kNaN;  // the largest backward Ω_k / 2π [Hz]
  int dominant_harmonic = 0;  // its k
  // The largest other component over the dominant one, |c_k| / |c_dominant| (modulation depth).
  double sideband_ratio = kNaN;
  Vector u;                   // the shooting unknowns (ShootingProblem::Pack layout)
  Vector x0;                  // the orbit's state at t = 0 (co-rotating frame; empty until converged)
  ShootingStatistics work;    // integrations of Newton (the search adds one more)
};

// The orbit near `fixed_state` (RubFixedFrame layout, 4 n_c entries) at running speed ω [rad/s],
// with the frame precessing at `frame_rate` Ω_f [rad/s] > 0. The structure must be balanced (no
// imbalance). Throws std::invalid_argument for wrong sizes, a non-positive Ω_f or ω, an imbalance,
// or invalid options; numerical outcomes (no modulation in the stretch, an integration failure,
// Newton not converged) are `converged = false` with the message.
ModulatedOrbit SolveModulatedOrbit(const RubStructure& structure, double omega, double frame_rate,
                                   const Vector& fixed_state, const ModulatedOrbitOptions& options);

// A converged orbit at ω as the start of its family (ContinuePeriodicOrbits, kRelative, in a
// RubRotatingFrame precessing at orbit.frame_rate): its first segment's start, T and φ. Throws
// std::invalid_argument for an orbit that did not converge.
OrbitStart StartOf(const ModulatedOrbit& orbit, double omega);

}  // namespace rubcont
