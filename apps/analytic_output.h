// The analytic (L0) part of a result file (docs/result_files.md):
//
//   /analytic                      attrs level = "L0", friction (μ), center_damping [N·s/m]
//   /analytic/natural_frequencies  attrs stator_bounce_hz, stator_pitch_hz, pinned_bounce_hz,
//                                        pinned_pitch_hz
//   /analytic/mode1|mode2          attrs contact_sign (+1 / −1)
//       precession_hz, normal_force_left|right [N], friction_force_left|right [N],
//       mu_required_left|right [-]                                   (one value per grid point)
//       transitions/{type, contact, direction, precession_hz, normal_force, through_pole}
//       without_center_damper/...  the same curves and transitions with c_d = 0 (the thesis's
//                                  closed form), written only when the scene's c_d > 0
#pragma once

#include <string>

#include "apps/hdf5_file.h"
#include "models/analytic.h"
#include "models/jeffcott.h"

namespace rubcont {

// The single-contact (Jeffcott) scene writes instead:
//   /analytic/natural_frequencies  attrs rotor_hz, stator_hz, combined_hz
//   /analytic/single               precession_hz, normal_force_contact, friction_force_contact,
//                                  mu_required_contact, transitions/{...} (contact = "contact")

// `without_damper` may be null (the scene has no centre damper).
void WriteAnalytic(ResultWriter& writer, const TwoPointParams& params, const AnalyticResult& result,
                   const AnalyticResult* without_damper);

void WriteJeffcottAnalytic(ResultWriter& writer, const JeffcottParams& params,
                           const AnalyticCurve& curve);

// Reads one curve group back (e.g. "/analytic/mode1" or "/analytic/mode1/without_center_damper";
// the latter takes precession_hz from its parent). Throws std::runtime_error on a missing object.
AnalyticCurve ReadAnalyticCurve(const ResultReader& reader, const std::string& group);

// Only the frequencies are stored, not the mode shapes.
NaturalFrequencies ReadNaturalFrequencies(const ResultReader& reader);

}  // namespace rubcont
