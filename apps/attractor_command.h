// `rubcont attractor SCENE --from RPM --to RPM --step RPM`: what the motion is at each speed of a
// schedule, from long transients (sweeps/attractor.h): the leading Lyapunov exponents by the
// variational equations, the verdict they give (sweeps/rub_sweep.h RubMotion: rotating wave,
// relative periodic orbit, relative 2-torus, chaotic) and a Poincaré section of each contact's
// successive penetration maxima, one per modulation or impact, with the normal force there
// (sampled every `sample_interval` seconds: RubPenetrations, RubSectionMaxima). The scene's
// sweep in `direction` is run from the impulse up to the last speed of its schedule before the
// first speed (the approach, as `rubcont ensemble`); each speed then starts from the state the
// previous one ended in, integrates `discard` seconds uncounted and `duration` seconds counted,
// re-orthonormalizing the `exponents` tangent directions every `interval` seconds. The integrator
// is the scene's sweep integrator (CVODES BDF), at `tolerance` when given.
//
// The study is studies/attractor_study.h's; the file (its HDF5 layout) and the summary are
// apps/attractor_output.h's.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace rubcont {

struct AttractorRequest {
  std::string scene_file;
  double from_rpm = 0.0;               // required, > 0
  std::optional<double> to_rpm;        // default: from_rpm (one speed)
  double step_rpm = 4.0;               // > 0
  std::string direction = "up";        // "up" or "down": the order of speeds (and the approach)
  // "up" or "down": the sweep that reaches the state before the first speed; default direction.
  // The other one steps back from where a sweep arrived (e.g. down from the speed-up whip).
  std::optional<std::string> approach;
  double duration = 2.0;               // [s] counted per speed
  double discard = 0.5;                // [s] uncounted per speed
  double interval = 0.005;             // [s] re-orthonormalization
  double sample_interval = 2e-6;       // [s] the section's samples: ~20 per period of the contact's
                                       // ~20 kHz oscillation (see RubPenetrations)
  int exponents = 4;
  std::optional<double> tolerance;     // relative = absolute; default the scene's sweep integrator's
  std::optional<std::string> out_file; // default results/<scene>/attractor.h5
  bool quiet = false;
  std::string figure_format = "png";  // the figure's file format: png, pdf or svg (--format)
  bool force = false;  // run a plan the plan check refuses (apps/plan_check.h), with a warning
};

int AttractorCommand(const AttractorRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
