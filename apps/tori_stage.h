// The "tori" stage of `rubcont run` for model two_point (level L2): the modulated orbits of
// [analysis.orbits] (without side branches), and from each of their Neimark–Sacker points that
// bounds a stable piece the relative 2-tori born there, continued in speed (shooting/rub_tori.h;
// [analysis.tori] neimark_sacker = "skip": none) — the same from the family through the orbit of
// [analysis.orbits.transient] where it is given — and with [analysis.tori.transient] the tori
// through the torus a transient settles on,
// summarized on `out` and written as
//   /tori                          attrs level, parameter_name ("speed_rpm"), numerics (the
//                                  orbits' integrator and mesh, K, points), friction_law
//   /tori/orbits/<branch>_hopf<k>  the modulated family (apps/orbit_output.h layout), attrs
//                                  hopf_branch, hopf_speed_rpm, hopf_precession_hz (the frame's
//                                  rate), hopf_modulation_hz
//   /tori/<branch>_hopf<k>_ns<j>   the tori from its j-th followed Neimark–Sacker point: attrs
//                                  parent, birth_speed_rpm, birth_rotation_number, birth_modulus,
//                                  harmonics, circle_coordinates ("state", or "chart": the
//                                  coefficients below are then the contact chart's,
//                                  RubFixedFrame::ToChart), end ("phase locking", "breakdown",
//                                  "reached the range's end", "reached the step limit", "a
//                                  contact lifts off", "failed"), end_note,
//                                  convergence_note (with max_harmonics: the tori not converged
//                                  in K, "" without), status, message, summary; per torus speed_rpm, rotation_number,
//                                  fourier_tail, invariance_error, period, rotation, carrier_hz,
//                                  first_hz (1/T), second_hz (ρ/T), per contact <c> line_hz_<c>,
//                                  line_l_<c>, line_k_<c> (its f_carrier − (k + lρ)/T),
//                                  line_ratio_<c>, min_normal_force_<c>, max_normal_force_<c>;
//                                  stable (1 / 0 / −1 undecided within the tolerance, or not
//                                  computed), unstable_count (the nontrivial exponents above
//                                  it; −1 as stable), arclength, largest_exponent (the largest
//                                  nontrivial Lyapunov exponent per period), exponent_tolerance,
//                                  exponents (tori × states, per period); unknowns (tori × n(2K + 1)
//                                  + 3: each circle's Fourier coefficients a₀, a₁, b₁, … column
//                                  by column in the co-rotating frame's states (SI; or their
//                                  chart's: circle_coordinates), then ρ, T
//                                  [s], φ [rad]: InvariantCircleProblem::Pack), so that a torus
//                                  can be reopened; the frame turns at its family's
//                                  hopf_precession_hz; special_points/ (apps/branch_output.h
//                                  layout: the family's folds in speed and its end event);
//                                  harmonics per torus (the K it was solved with: with
//                                  max_harmonics the family refines in K, its coarser circles
//                                  written in the finest K's layout, padded with zero
//                                  harmonics) and 1-D attrs refinement_speeds_rpm, _from_harmonics,
//                                  _to_harmonics, _images, _rotation_numbers_from, _to,
//                                  _fourier_tails_from, _to (one entry per doubling of K: both
//                                  circles are tori of the family, at that speed).
//   /tori/orbits/orbit_transient, /tori/orbit_transient_ns<j>
//                                  with [analysis.orbits.transient] (and neimark_sacker =
//                                  "follow"): the family through the transient's orbit (attrs
//                                  transient_speed_rpm, transient_seconds, transient_settled,
//                                  frame_precession_hz, laps) and the tori from its followed
//                                  Neimark–Sacker points, as the two above (parent
//                                  "orbit_transient")
//   /tori/transient_down, _up    with [analysis.tori.transient]: the tori through the torus a
//                                  transient settles on, continued towards lower / higher speed
//                                  (as the families above without birth_*; parent "transient"),
//                                  attrs numerics, transient_speed_rpm, transient_seconds,
//                                  transient_settled (1 / 0), frame_precession_hz (the
//                                  transient's backward precession at the first contact: the
//                                  frame's rate), start_laps, start_rotation_number,
//                                  start_first_hz, start_second_hz, start_carrier_hz,
//                                  start_fourier_tail, start_invariance_error, start_message (the
//                                  torus solved on the transient's points, before the families'
//                                  first correction by the orbits' integrator; in the state with
//                                  Gauss orbits, solved by BDF and again under the orbits' Gauss
//                                  mesh, whose numbers these are, the BDF circle's ρ in
//                                  start_first_map_rotation_number);
//                                  start_in_k_harmonics, _rotation_numbers, _fourier_tails,
//                                  _invariance_errors, _images (1-D, one entry per K solved
//                                  under the final map: max_harmonics' refinement; images 0 for
//                                  the first circle).
//   /tori/<...>_ns<j>_locked       where that family ends in phase locking at p:q: the q-lap
//                                  relative periodic orbits of the resonance (apps/orbit_output.h
//                                  layout), attrs resonance_p, resonance_q, fold_speeds_rpm (the
//                                  tongue's edges), tori_inside (the family's tori between
//                                  them: no invariant circles, LockedOrbits::tori_inside), note
//                                  (where they were found).
//   /tori/<family>_centre          where a family (either kind) ends shrinking onto its centre:
//                                  the relative periodic orbits through the last circle's centre
//                                  (ContinueCentreOrbits; apps/orbit_output.h layout with the
//                                  modulated orbits' measures, their untrusted column and
//                                  check_note), continued in the family's direction to their
//                                  located Neimark–Sacker point and, with centre_orbits =
//                                  "follow", on over the range to their end; attrs
//                                  neimark_sacker_speed_rpm, neimark_sacker_rotation_number
//                                  (arg μ / 2π), note.
#pragma once

#include "apps/models.h"

namespace rubcont {

// Appends a line to the context's failures when a family cannot start or ends on a numerical
// failure.
void RunRubTori(const Scene& scene, StageContext& context);

}  // namespace rubcont
