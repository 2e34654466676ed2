// The "orbits" stage of `rubcont run` (level L2), summarized on `out`:
//   textbook models (Duffing, Stuart–Landau, van der Pol): their periodic orbits continued in the
//     model's parameter by shooting, with Floquet stability and special points
//     (shooting/orbit_branches.h), written to /branches/periodic_orbits (apps/orbit_output.h);
//   model two_point: the modulated whirl and whip (shooting/rub_orbits.h) —
//     /orbits                        attrs level, parameter_name, friction_law ("tanh"),
//                                    velocity_scale, numerics (segments, integrator and mesh or
//                                    tolerance), note (imbalance left out)
//     /orbits/rotating_waves/<name>  the tanh-law rotating waves (layout of apps/branch_output.h)
//     /orbits/<branch>_hopf<k>       the orbits born at special point k of that rotating wave
//                                    (layout of apps/orbit_output.h, parameter speed_rpm), attrs
//                                    hopf_branch, hopf_speed_rpm, hopf_precession_hz,
//                                    hopf_modulation_hz, check_note (when a check fails);
//                                    measures precession_hz (the carrier), modulation_hz, defect,
//                                    min_/max_precession_hz_<c>, min_/max_normal_force_<c>,
//                                    max_penetration_<c>, unresolved_multiplier with Gauss
//                                    collocation, and asymmetry for a left–right symmetric rotor;
//                                    untrusted (per orbit, why, or "": a contact penetrates beyond
//                                    [analysis.sweep] max_penetration × its clearance).
//     /orbits/<family>_bp<k>[b]      the branch followed from the family's k-th branch point
//                                    (branch_points = "follow"; "b": the other side, where the two
//                                    are not mirror images), the same layout, attrs parent,
//                                    branch_point_speed_rpm, branch_point_precession_hz,
//                                    branch_point_note (the symmetry it breaks), branch_angle.
//     /orbits/<family>_pd<k>         the period-doubled orbits from the family's k-th period
//                                    doubling that bounds a stable piece of it (branch_points =
//                                    "follow"; period 2T, twice the segments), the same layout,
//                                    attrs parent, branch_point_speed_rpm,
//                                    branch_point_precession_hz, branch_point_note,
//                                    period_doubling_multiplier; its modulation_hz is 1/(2T).
//     /orbits/transient              with [analysis.orbits.transient]: the family through the
//                                    orbit a transient settles on (ContinueTransientOrbits), both
//                                    ways joined, the same layout, attrs transient_speed_rpm,
//                                    transient_seconds, transient_settled (1 / 0),
//                                    frame_precession_hz (the transient's backward precession at
//                                    the first contact: the frame's rate), laps, fold_speeds_rpm,
//                                    start_period, start_rotation, start_carrier_hz,
//                                    start_dominant_hz, start_message (the orbit solved on the
//                                    transient); its side branches /orbits/transient_bp<k>[b] and
//                                    /orbits/transient_pd<k> as above.
#pragma once

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "apps/models.h"
#include "shooting/rub_orbits.h"
#include "solvers/stopwatch.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {

// The modulated orbits of model two_point as the scene asks for them (shared by the "orbits" and
// "tori" stages): the balanced structure, the tanh-law rotating waves over speed_range_rpm, the
// Hopf points that bound a stable piece of them, how many to follow ([analysis.orbits]
// hopf_points), and the Hopf-orbit options of [analysis.orbits] (RubOrbitOptionsOf, no on_step).
struct RubOrbitsPlan {
  RubStructure structure;   // the imbalance set to 0
  std::string note;         // why the imbalance is left out, or ""
  std::vector<RotatingWaveBranch> waves;
  std::vector<RubHopfStart> starts;
  std::size_t followed = 0;
  HopfOrbitOptions options;
};
RubOrbitsPlan PlanRubOrbits(const Scene& scene);
// One line per Hopf start: branch, speed, precession, modulation, side, Lyapunov coefficient.
void PrintHopfStarts(const RubOrbitsPlan& plan, std::ostream& out);
// One line for summaries and result files: segments, integrator and mesh or tolerance.
std::string RubOrbitsNumerics(const Scene& scene);

// One speed of the scene's sweep model (model two_point; [analysis.sweep]'s integrator, windows and
// impulse) from rest for `seconds`: the transient the orbits' and the tori's
// [analysis.*.transient] start from. `structure` is the plan's (balanced).
RubSettledSpeed SceneTransient(const Scene& scene, const RubStructure& structure, double speed_rpm,
                               double seconds);

// Prints the transient's line ("<prefix> transient at … rpm: settled, backward precession …
// Hz"); false, with a failure in the context, when it shows no backward precession at the first
// contact (no frame to solve its `what` in).
bool ReportTransient(const std::string& prefix, const std::string& what, const Scene& scene,
                     const RubStructure& structure, double speed_rpm, double seconds,
                     const RubSettledSpeed& transient, double elapsed_seconds,
                     StageContext& context);

// The family through the orbit [analysis.orbits.transient]'s transient settles on, for the stages
// "orbits" and "tori": the transient (SceneTransient, ReportTransient), its orbit solved and
// continued over the range (ContinueTransientOrbits with the plan's options; the side branches
// where `side_branches`), the orbit's line printed, and the steps on the progress line as
// "<prefix> <name>: …"; t0 when the work began. Empty, with a failure in the context, where the
// transient shows no backward precession or its orbit does not converge.
struct SceneTransientOrbits {
  RubSettledSpeed transient;
  RubTransientOrbits orbits;
};
std::optional<SceneTransientOrbits> SolveSceneTransientOrbits(
    const Scene& scene, const RubOrbitsPlan& plan, const std::string& prefix,
    const std::string& name, bool side_branches, SteadyClock::time_point t0, StageContext& context);

// The attributes both stages give a family from a transient: transient_speed_rpm,
// transient_seconds, transient_settled (1 / 0) and frame_precession_hz (the frame's rate).
void WriteTransientAttributes(ResultWriter& writer, const std::string& group, double speed_rpm,
                              double seconds, const RubSettledSpeed& transient);

// What an orbit's trust is judged by: the structure's clearances and the largest penetration
// allowed as a share of them ([analysis.sweep] max_penetration).
struct OrbitTrust {
  const RubStructure& structure;
  double max_penetration;
};

// The largest defect (or that there was no defect check: defect_check = "off") and unresolved
// multiplier of a family of modulated orbits (RubFamilyMeasures), printed, and a note when either
// is over its limit; the orbits that penetrate beyond the trust limit (UntrustedOrbits): the
// column `untrusted` of the group and a note with the speeds.
void ReportOrbitChecks(const Branch& branch, const std::string& group, const OrbitTrust& trust,
                       ResultWriter& writer, std::ostream& out);

// One line per special point of a family of modulated orbits: name, speed, carrier, modulation.
void PrintSpecialPoints(const Branch& branch, std::ostream& out);

// Each appends a line to the context's failures when a branch ends on a numerical failure or
// cannot start, and sends one progress line per finished run.
void RunRubOrbits(const Scene& scene, StageContext& context);           // model two_point
void RunDuffingOrbits(const Scene& scene, StageContext& context);       // model duffing
void RunStuartLandauOrbits(const Scene& scene, StageContext& context);  // model stuart_landau
void RunVanDerPolOrbits(const Scene& scene, StageContext& context);     // model van_der_pol
void RunForcedVanDerPolOrbits(const Scene& scene, StageContext& context);  // forced_van_der_pol

}  // namespace rubcont
