// The whip modulated at two frequencies (level L2): the relative 2-tori of a rub structure born at
// the Neimark–Sacker points of its modulated orbits (shooting/rub_orbits.h), continued in running
// speed (shooting/torus_branches.h), and read in the fixed frame as a waterfall reads them.
//
// The frequencies. In the frame co-rotating at Ω_f the torus is the invariant circle u(θ) of
// P = R_{−φ} Φ_T with rotation number ρ, and the motion on it is p(t) = R_{φt/T} G(θ₀ + 2πρt/T, t/T)
// with G doubly 2π/1-periodic, G(ϑ, s) = R_{−φs} Φ_{sT}(u(ϑ − 2πρs)). Expanding each contact's
// relative displacement d = u_rotor − u_stator of G in e^{i(lϑ + 2πks)} (coefficients c_{l,k}), the
// fixed-frame d is a sum of backward precessions at
//     f_{l,k} = f_carrier − (k + lρ)/T,   f_carrier = (Ω_f − φ/T)/2π,
// with amplitudes |c_{l,k}|: the lattice of lines of f₁ = 1/T and f₂ = ρ/T around the carrier.
// TorusLines samples G on the circle's N = 2K + 1 points times `samples` instants of one period
// (Φ_{sT} of the circle's points, each turned back by R_{−φs}: G on a grid sheared by 2πρs, which
// the transform over θ undoes) and returns, per contact, the strongest line other than the carrier,
// its amplitude against the carrier's, and the normal force's range over the samples.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "shooting/modulated_torus.h"
#include "shooting/rub_orbits.h"
#include "shooting/torus_branches.h"

namespace rubcont {

struct RubTorusLines {
  bool valid = false;       // false: an integration failed
  double carrier_hz = 0.0;  // f_carrier
  double first_hz = 0.0;    // f₁ = 1/T
  double second_hz = 0.0;   // f₂ = ρ/T
  struct Contact {
    double line_hz = 0.0;     // the strongest line other than the carrier
    int line_l = 0;           // its (l, k): f = f_carrier − (k + lρ)/T
    int line_k = 0;
    double line_ratio = 0.0;  // its amplitude over the carrier's
    double min_normal_force = 0.0;  // [N] over the samples
    double max_normal_force = 0.0;
  };
  std::vector<Contact> contacts;  // in structure.contacts order
};

// The lines of the torus held in `u` (InvariantCircleProblem::Pack layout, kRelative, of `frame`,
// in `coordinates`) at running speed λ = ω [rad/s], from `samples` ≥ 4 instants per period
// integrated by `integrator`.
RubTorusLines TorusLines(const RubRotatingFrame& frame, int harmonics, const Vector& u,
                         double lambda, const IntegratorOptions& integrator, int samples,
                         CircleCoordinates coordinates = CircleCoordinates::kState);

// A family whose continuation failed (TorusEnd::kFailed) with a contact's least normal force at
// its last torus below this share of that contact's largest is read as ending where the contact
// lifts off (TorusEnd::kGrazing; the Gauss map does not follow the contact opening). The fallback
// for an end the grazing tests (RubTorusGrazing) did not locate: before them C(c)'s family failed
// at 71.1142 rpm with its left contact's least force 0.6 N of 495.6 N over TorusLines' 64 instants
// per period, which missed the stiff contact's ripple; located, the lift-off lies at 70.9107 rpm.
constexpr double kLiftOffForceShare = 0.01;
// The rub's reading of a family's end, with its lines (one per torus): a located grazing is named
// in rpm; a kFailed family whose last torus has such a contact ends kGrazing, its note naming the
// contact, its forces and the speed.
void ReadLiftOff(const RubStructure& structure, const std::vector<RubTorusLines>& lines,
                 TorusBranch& tori);

// Each contact's grazing by a torus (InvariantCircleProblem::SetGrazingTests, on its penetration
// δ_c as RubGrazingTests for orbits): "lift_off_<c>" where a torus in permanent contact first
// opens the contact somewhere (min δ_c = 0), "touchdown_<c>" where one that never touches first
// does (max δ_c = 0). The rub's torus families end at the first located one.
std::vector<TorusGrazing> RubTorusGrazing(const RubStructure& structure);

struct RubTorusOptions {
  // Range, harmonics, engine, amplitude, breakdown and locking limits, Lyapunov iterates. The
  // integrator is the modulated family's (its Gauss mesh covering one period) and the grazing
  // tests RubTorusGrazing's, set here.
  TorusBranchOptions tori;
  int samples = 64;  // TorusLines' instants per period
  // Called before each torus's lines and exponents (the work after its family is continued) with
  // the family's index (as on_torus_step's), "lines" or "exponents", the torus's index and the
  // family's size; tori.on_exponents is set from it.
  std::function<void(std::size_t, const char*, std::size_t, std::size_t)> on_work;
  // The orbits a family shrinks onto (ContinueCentreOrbits, where it ends kShrinks): their range,
  // engine, stop_at_neimark_sacker and on_step as given; their shooting is this one's of one
  // modulation period, its segments times the section's laps, for a transient family, and the
  // orbit family's for a Neimark–Sacker family; their measures (RubFamilyMeasures), grazing tests
  // (RubGrazingTests) and stop_at_grazing are set here: past a contact's lift-off the fixed mesh
  // creeps (PeriodicOrbitBranchOptions::stop_at_grazing).
  PeriodicOrbitBranchOptions centre_orbits;
};

struct RubModulatedTori {
  RubModulatedOrbits orbits;  // the family (no side branches)
  // From each located Neimark–Sacker point of the family that bounds a stable piece of it (where a
  // stable modulated whip hands over to a torus), in the order of its special points.
  std::vector<TorusBranch> tori;
  std::vector<std::vector<RubTorusLines>> lines;  // per torus family, per point
  // Per torus family: the locked orbits where it ended in phase locking (ContinueLockedOrbits:
  // q-lap relative periodic orbits, folds at the tongue's edges); ok = false otherwise.
  std::vector<LockedOrbits> locked;
  // Per torus family: the orbits it shrank onto (ContinueCentreOrbits) where it ended kShrinks;
  // ok = false otherwise.
  std::vector<CentreOrbits> centres;
};

// The modulated orbits born at `start` (ContinueModulatedOrbits with `orbits`, no side branches),
// then the tori from their Neimark–Sacker points, and the locked orbits where a torus family ends
// in phase locking; `on_torus_step` is called after every torus (and locked-orbit) continuation
// step, with the index of the torus family. Throws std::invalid_argument as
// ContinueModulatedOrbits and for invalid torus options.
RubModulatedTori ContinueModulatedTori(
    const RubStructure& structure, const std::vector<RotatingWaveBranch>& branches,
    const RubHopfStart& start, const HopfOrbitOptions& orbits, const RubTorusOptions& options,
    const std::function<bool(std::size_t, const Branch&)>& on_torus_step = {});

// The tori from the Neimark–Sacker points of the family through a transient's orbit
// (ContinueTransientOrbits: result.orbits is `orbits.family`), as ContinueModulatedTori's from a
// Hopf point's family: where a whip no Hopf point's family reaches loses stability to a torus
// (C(b)'s, stable at 53 rpm, at 53.95 rpm). No tori where the start did not converge.
// Throws std::invalid_argument for invalid torus options.
RubModulatedTori ContinueTransientOrbitTori(
    const RubStructure& structure, const RubTransientOrbits& orbits, const RubTorusOptions& options,
    const std::function<bool(std::size_t, const Branch&)>& on_torus_step = {});

// The tori through the torus a settled transient lies on: SolveModulatedTorus at running speed ω
// [rad/s] from `fixed_state` in the frame precessing at `frame_rate` (its options `start`: K, the
// section's laps, the start's integrator), then ContinueTori towards lower and towards higher speed
// over options.tori's range with options.tori's integrator (a Gauss mesh given per modulation
// period: collocation_steps is multiplied by the section's laps), K the start's, each torus read by
// TorusLines; the family upwards starts from the downward family's first torus (the start once
// corrected by that integrator). For whips that no Neimark–Sacker point of a computed family reaches (C(a) beyond the
// 2:5 tongue). Decision: two integrators — from the circle fitted to a transient's points Newton
// with the map by Gauss collocation failed (C(a) at 49 rpm, 400 intervals per period: a non-finite
// residual after 5 iterations; at 60 rpm the collocation equations' own Newton did not converge on
// the first mesh step at 32 of the 33 points, at 2 with 1000 intervals), with BDF it converged (19
// iterations); from BDF's solution Gauss continues at 10–13 s a step with exact derivatives,
// where BDF's steps (sensitivities outside the error test) took 3–163 s, median 17 s (measured).
struct RubTransientTori {
  ModulatedTorus start;
  // Empty when the start did not converge; else [0] towards lower speed, [1] towards higher.
  std::vector<TorusBranch> tori;
  std::vector<std::vector<RubTorusLines>> lines;  // per family, per point
  // Per family: the orbits it shrank onto where it ended kShrinks (ContinueCentreOrbits with
  // options.centre_orbits); ok = false otherwise.
  std::vector<CentreOrbits> centres;
};

// Throws std::invalid_argument as SolveModulatedTorus and for invalid torus options.
// on_torus_step is called after every step with the family's index (0 down, 1 up).
RubTransientTori ContinueTransientTori(
    const RubStructure& structure, double omega, double frame_rate, const Vector& fixed_state,
    const ModulatedTorusOptions& start, const RubTorusOptions& options,
    const std::function<bool(std::size_t, const Branch&)>& on_torus_step = {});

}  // namespace rubcont
