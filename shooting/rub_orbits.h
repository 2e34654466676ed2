// The modulated whirl and whip of a rub structure: periodic orbits of the frame co-rotating with a
// rotating wave (relative periodic orbits, docs/theory.md §7), born at the Hopf points of the tanh-law
// rotating-wave branches and continued against running speed with Floquet stability (level L2).
//
// A rotating wave is an equilibrium of the frame precessing backward at its precession Ω_H; at a
// Hopf point a pair of its eigenvalues crosses ±iω_H and a family of orbits is born that, in that
// frame, is periodic up to a rotation: p(T) = R_φ p(0). In the fixed frame the motion is
// quasi-periodic with a carrier (the mean backward precession Ω_H − φ/T) and a modulation 1/T:
// the whip "with sidebands" of a waterfall. Single-frequency shooting in the fixed frame cannot
// converge on it (tests/shooting/rub_orbits_test.cpp); here it is one more continuation problem.
//
// Which Hopf points: those that bound a stable piece of a rotating wave (stable on one side,
// unstable on the other), in order of speed — where a sweep leaves or reaches a circular state.
// Mirror images (the left-only and right-only branches of a symmetric rotor) are followed once.
//
// Cost (bench/modulated_whip_methods_bench.cpp): the contact mode (√(k1/m) ≈ 1.3e5 rad/s for the
// thesis's k1 = 1.75e11 N/m) is almost undamped and lives in every column of the state-transition
// matrix: CVODES BDF with sensitivities under error control takes ~3e4 steps per modulation period
// (11–17 s per orbit of case A(a) at tolerance 1e-7); Gauss collocation on a fixed mesh of 200–300
// steps per period neither resolves nor damps it and costs ~0.15 s per orbit.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "models/rub_model.h"
#include "shooting/hopf_orbits.h"
#include "shooting/modulated_orbit.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {

// Measures of a relative periodic orbit of RubRotatingFrame, evaluated in the fixed frame:
//   precession_hz                  the carrier: mean backward precession (Ω_f − φ/T)/2π
//   modulation_hz                  1/T
//   min_/max_precession_hz_<c>     instantaneous backward precession −Im(ḋ/d)/2π of the contact's
//                                  relative displacement d = u_rotor − u_stator
//   min_/max_normal_force_<c>      N [N] (0 while the contact is open)
//   max_penetration_<c>            the largest penetration δ_c = |d_c| − C_c [m] (< 0: never touches)
//   defect                         PeriodicityDefect with Dormand–Prince 5(4) at 1e-12, state
//                                  only (left out with defect_check = false)
//   unresolved_multiplier          UnresolvedMultiplier, with Gauss collocation only (added by
//                                  ContinueModulatedOrbits, which knows the mesh)
//   asymmetry                      MirrorAsymmetry, for a left–right symmetric structure only
//                                  (ContactExchange): ~1e-11 on symmetric orbits
// for each contact <c> ("left", "right" or "contact"). The frame is copied.
std::vector<OrbitMeasure> RubOrbitMeasures(const RubRotatingFrame& frame, bool defect_check = true);

// The measures of a family's orbits shot with `shooting`, run `laps` times per shooting period
// (period-doubled families: 2): RubOrbitMeasures (without the defect when defect_check is false:
// PeriodicOrbitBranchOptions::defect_check), and with Gauss collocation the unresolved-mode check
// (UnresolvedMultiplier), which needs the mesh's steps per period.
std::vector<OrbitMeasure> RubFamilyMeasures(const RubRotatingFrame& frame,
                                            const ShootingOptions& shooting, int laps,
                                            bool defect_check = true);

// Per point of a family (RubOrbitMeasures), why the orbit is untrusted, or "": a contact
// penetrates more than `max_penetration` × its clearance, beyond the small overlap the contact laws
// describe (the sweeps' rule, [analysis.sweep] max_penetration; sweeps/rub_sweep.h).
std::vector<std::string> UntrustedOrbits(const Branch& branch, const RubStructure& structure,
                                         double max_penetration);

// Grazing of each contact c along a family (Grazing, shooting/shooting.h, on its penetration
// δ_c = |d_c| − C_c, which the co-rotating frame leaves unchanged): "lift_off_<c>" where an orbit
// in permanent contact first opens the contact for part of each period (min δ_c = 0),
// "touchdown_<c>" where an orbit that never touches first does (max δ_c = 0).
std::vector<OrbitTestFunction> RubGrazingTests(const RubStructure& structure);
// Contact c's penetration δ_c(x) at a state of either frame (the grazing tests' surface).
std::function<double(ConstVectorRef)> ContactPenetration(const RubStructure& structure,
                                                         std::size_t c);

// The Hopf points of `branches` that bound a stable piece, sorted by speed, mirror images once.
struct RubHopfStart {
  std::string branch;   // RotatingWaveBranch::name
  std::size_t special_point = 0;  // index into its special_points
  double speed = 0.0;       // ω_H [rad/s]
  double precession = 0.0;  // Ω_H [rad/s]
  double modulation = 0.0;  // ω of the critical pair [rad/s]
  bool stable_below = false;  // the rotating wave is stable on the lower-speed side
};
std::vector<RubHopfStart> StableBoundaryHopfPoints(const std::vector<RotatingWaveBranch>& branches,
                                                   Index coordinates);

struct RubModulatedOrbits {
  RubHopfStart hopf;
  PeriodicOrbitBranch orbits;
  // The branches through its located branch points (ContinueModulatedOrbits with
  // switch_at_branch_points), in the order of orbits.branch.special_points.
  std::vector<OrbitBranchSwitch> switches;
  // The period-doubled families born at its located period doublings that bound a stable piece
  // of it (stable on one side: where a stable whip hands over to its doubled successor), in the
  // same order.
  std::vector<OrbitPeriodDoubling> doublings;
};

// The orbits born at `start` (a point of StableBoundaryHopfPoints(branches, ...)) of the tanh-law
// branches of `structure`, continued in speed with `options` (kind is set to kRelative, the
// measures to RubFamilyMeasures unless options.orbits.measures holds the caller's own for the
// family and its side branches — of its frame, RubRotatingFrame(structure, start.precession,
// start.speed) — and the test functions to RubGrazingTests). With
// switch_at_branch_points, the other branch through every located branch point (converged; on a
// left–right symmetric rotor also one located only to a bracket) is followed over the same range
// (ContinueOrbitsFromBranchPoint: of a symmetric rotor, one of two mirror images where the point
// breaks the symmetry, up to where it rejoins it; a branch point where an earlier switched branch
// rejoined is not followed again), and the doubled orbits from every located period doubling that
// bounds a stable piece of the family (ContinueOrbitsFromPeriodDoubling; not those of the
// switched branches), on_step called for their steps too. Throws
// std::invalid_argument when the structure has an imbalance or the start names no Hopf point of
// `branches`; numerical failures end the branch with a status.
RubModulatedOrbits ContinueModulatedOrbits(const RubStructure& structure,
                                           const std::vector<RotatingWaveBranch>& branches,
                                           const RubHopfStart& start, HopfOrbitOptions options,
                                           bool switch_at_branch_points = false);

// The orbits through the relative periodic orbit a settled transient lies on: SolveModulatedOrbit
// at running speed ω [rad/s] from `fixed_state` (RubFixedFrame layout) in the frame precessing at
// `frame_rate` with `start` (its `laps` > 1: a whip locked at p:laps, an orbit of laps modulation
// periods), then its family continued both ways over options' range with start.shooting (the
// orbit's own segments and mesh; options.shooting is replaced) and `family_max_steps` steps each
// way, the measures and grazing tests of ContinueModulatedOrbits, stop_round_closed_curve set (a
// resonance's locked orbits form a closed curve between the tongue's two folds), and with
// switch_at_branch_points the side branches as there, each with options' own step limit. For
// whips no Hopf point of a computed family reaches (C(a)'s whip locked at 1:3 above 49.2 rpm;
// bench/locked_whip_bench.cpp). Throws std::invalid_argument as SolveModulatedOrbit
// and for invalid options; a start that does not converge leaves `family` empty (start.message).
struct RubTransientOrbits {
  ModulatedOrbit start;
  RubModulatedOrbits family;  // hopf left empty
};
RubTransientOrbits ContinueTransientOrbits(const RubStructure& structure, double omega,
                                           double frame_rate, const Vector& fixed_state,
                                           const ModulatedOrbitOptions& start,
                                           PeriodicOrbitBranchOptions options,
                                           int family_max_steps,
                                           bool switch_at_branch_points = false);

// The period-doubled orbits born at the period doubling `special_point` of `orbits.family.orbits`
// (a family ContinueTransientOrbits found from a converged start), continued with `options`' range,
// continuation (max_steps), stop_at_grazing and on_step; the shooting, measures (for two laps) and
// grazing tests are the family's, as ContinueModulatedOrbits' doubled families have them (the
// `loop` command's L2, which follows only the doubling its run meets). Throws
// std::invalid_argument when the start did not converge, and as ContinueOrbitsFromPeriodDoubling.
OrbitPeriodDoubling ContinueTransientDoubling(const RubStructure& structure,
                                              const RubTransientOrbits& orbits,
                                              std::size_t special_point,
                                              PeriodicOrbitBranchOptions options);

}  // namespace rubcont
