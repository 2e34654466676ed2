// `rubcont ensemble SCENE --speed RPM`: how long the state a sweep has reached lasts at the next
// speed, as a distribution over perturbed copies (sweeps/ensemble.h, sweeps/rub_sweep.h
// RubArrivals). The scene's sweep in `direction` is run from the impulse up to the last speed of
// its schedule before RPM (the approach; none when RPM comes first); from its final state
// `copies` copies, each perturbed by `perturbation` × each state's scale, run at RPM for
// `duration` in stretches of two `window`s, each stretch classified as a sweep speed (the scene's
// regime rules); a copy arrives when every contact (`until_contacts` "any": one; or the contact it names) is in
// the regime `until`, or, with `until_above_hz` > 0, precesses faster than that. The copies run on
// `threads` threads (0: one per core) and give the same numbers on any number.
//
// The study is studies/ensemble_study.h's; the file (its HDF5 layout) and the summary are
// apps/ensemble_output.h's.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

namespace rubcont {

struct EnsembleRequest {
  std::string scene_file;
  double speed_rpm = 0.0;               // required, > 0
  std::string direction = "up";         // "up" or "down": the sweep that reaches the state
  int copies = 16;
  double duration = 2.0;                // [s] per copy
  double window = 0.05;                 // [s]; a stretch is two windows
  double perturbation = 1e-6;           // in units of each state's scale
  std::uint64_t seed = 1;
  int threads = 0;
  std::string until = "whirl";          // whirl, whip, intermittent or no_contact
  double until_above_hz = 0.0;  // > 0: arrive when the precession exceeds it [Hz] instead of `until`
  std::string until_contacts = "every";  // every or any: the contacts that must be in `until`
  std::optional<std::string> out_file;  // default results/<scene>/ensemble_<rpm>rpm.h5
  bool quiet = false;
  std::string figure_format = "png";  // the figure's file format: png, pdf or svg (--format)
  bool force = false;  // run a plan the plan check refuses (apps/plan_check.h), with a warning
};

int EnsembleCommand(const EnsembleRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
