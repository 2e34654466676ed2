// Level L4 against the rigid model on the thesis's cases: the flexible analogues of Kumar (2010)
// §3.2 (XLTRC², Figures 11–13) with shaft sections identified (NLopt) so that the frequencies of
// its Tables 2 and 3 are met, and how much the flexibility moves the rotating waves' jumps.
//
// The thesis gives the rigid-body data (Eq. 31) and the frequencies, not the shafts. Decisions
// (written here because nobody else can): both shafts steel (E = 2.0684e11 Pa, G = 7.929e10 Pa,
// ρ = 7833 kg/m³: 30e6 psi, 11.5e6 psi, 0.283 lb/in³), 8 elements each as the thesis's; the stator
// a tube whose bore is the rotor's contact diameter plus the clearance (2(R + C)), its outer
// diameter fitted to Table 3's first bending mode; the rotor a hollow shaft across the contact
// span, its outer diameter and bore ratio fitted to Table 2's three first bending modes (one
// rotor for the three disk positions, as the thesis says); a disk on each completes the body to
// Eq. 31 exactly (models/flexible.h FlexibleTwoPoint). Frequencies are computed as the thesis did:
// "pinned" through stiff bearings of 4.5e8 N/m and 2.1e4 N·s/m at the contacts, the stator alone
// on its supports; the first three modes are bounce, pitch and first bending.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "models/flexible.h"
#include "models/two_point_params.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {

// Bounce, pitch, first bending: damped frequency [Hz] and damping ratio of each.
struct ThreeModes {
  std::array<double, 3> hz{};
  std::array<double, 3> damping_ratio{};
};

// The thesis's procedure on a flexible two-point model: the rotor joined to the stator at each
// contact by 4.5e8 N/m and 2.1e4 N·s/m (its "pinned"), and the stator alone on its supports.
ThreeModes XltrcPinnedModes(const FlexibleRubModel& model);
ThreeModes XltrcStatorModes(const FlexibleRubModel& model);

// The rigid-body data of the thesis's cases A, B, C (its Eq. 31: the disk at the centre, ¾ and
// overhung) as their first subcases A(a), B(a), C(a) (docs/theory.md §10).
std::array<TwoPointParams, 3> ThesisCases();

// Table 2 (disk at centre, ¾, overhung) and Table 3 of the thesis.
struct ThesisTableTargets {
  std::array<ThreeModes, 3> pinned;  // cases A, B, C
  ThreeModes stator;
};
ThesisTableTargets ThesisTables();

struct ThesisGeometry {
  ShaftElement rotor;   // section and material (length unused)
  ShaftElement stator;
  int elements = 8;
  // The flexible model of one case (its TwoPointParams: A(a), B(a), … with their RCIs) with this
  // geometry and `modes` fixed-interface modes.
  FlexibleRubModel Model(const TwoPointParams& params, int modes) const;
};

struct ThesisGeometryFit {
  ThesisGeometry geometry;
  std::array<ThreeModes, 3> pinned;  // the fitted models' Table 2 (cases A, B, C)
  ThreeModes stator;                 // and Table 3
  double objective = 0.0;            // Σ (ln f/f_target)² over the four fitted bending modes
  int evaluations = 0;  // of the fit (0: evaluated, not fitted)
  int nlopt_result = 0;
  std::string message;
};

// The Tables 2–3 of a geometry (cases A, B, C) and Σ (ln f/f_target)² over the four bending modes;
// the fit fields (evaluations, nlopt_result) zero, the message naming the geometry.
ThesisGeometryFit EvaluateThesisGeometry(const ThesisGeometry& geometry,
                                         const std::array<TwoPointParams, 3>& cases);

// Fits the rotor's outer diameter and bore ratio and the stator's outer diameter (NLopt
// LN_BOBYQA from a start inside the feasible box) to the four bending frequencies of Tables 2–3;
// bounce, pitch and the damping ratios follow from Eq. 31 and are reported, not fitted.
// `cases` are the rigid-body data of cases A, B, C (the first subcase of each).
ThesisGeometryFit FitThesisGeometry(const std::array<TwoPointParams, 3>& cases);

// A special point of the rigid model's L1 branch set (fold, Hopf point, stick/slip event,
// contact loss) and the flexible model's matching one: same kind and label (up to the contact's
// name) on a branch of the same closed-form pattern, within 10 % of the speed, Hopf points also
// within a factor 1.5 of the critical frequency; nearest first (relative speed, plus |ln| of the
// frequency ratio for Hopf points), one to one (none left: `found` false).
struct MovedPoint {
  std::string branch_pattern;  // "mode1", …
  std::string label;           // "Hopf", "fold", "left stick to slip+", …
  double rigid_rpm = 0.0, rigid_hz = 0.0;
  bool found = false;
  double flexible_rpm = 0.0, flexible_hz = 0.0;
};

struct FlexibilityEffect {
  std::vector<MovedPoint> points;
  double rigid_seconds = 0.0, flexible_seconds = 0.0;  // the two branch sets' wall times
  Index rigid_coordinates = 0, flexible_coordinates = 0;
};

// The L1 branch sets of the rigid and the flexible structure over the same options, and where
// each special point of the rigid set moved.
FlexibilityEffect CompareRigidFlexible(const RubStructure& rigid, const RubStructure& flexible,
                                       FrictionLawKind law,
                                       const RotatingWaveBranchOptions& options);

}  // namespace rubcont
