// `rubcont lifetime SCENE --from RPM --to RPM`: where a state that a sweep reaches ceases to exist,
// from the lifetimes of perturbed copies (sweeps/lifetime.h). The scene's sweep in `direction` is
// run from the impulse up to the last speed of its schedule before --from (the approach, as
// `rubcont ensemble`); from its final state, at each speed --from, --from ± --step, … --to,
// `copies` copies (perturbed by `perturbation` × each state's scale, seeds seed + i·copies for the
// i-th speed) run for `duration` in stretches of two `window`s until they arrive (RubArrivals): every contact
// (`until_contacts` "any": one; or the contact it names) in the regime `until`, or, with
// `until_above_hz` > 0, precessing faster than that. Per speed: the escape rate κ with its 95 % interval (interval-censored exponential);
// over the speeds: the crisis law κ = A·(p − p_c)^γ (beyond p_c in `direction`) with p_c's
// profile-likelihood interval, or the status that says why there is none. Then the check:
// `check_copies` perturbed sweeps from the same state through --from … --to in steps of
// `check_step`, `check_dwell` seconds per speed, and where each leaves, beside the probabilities
// the fitted law predicts for that schedule.
//
// The study is studies/lifetime_study.h's; the file (its HDF5 layout) and the summary are
// apps/lifetime_output.h's.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>

namespace rubcont {

struct LifetimeRequest {
  std::string scene_file;
  double from_rpm = 0.0;                // required, > 0
  double to_rpm = 0.0;                  // required, beyond --from in `direction`
  double step_rpm = 1.0;
  std::string direction = "up";         // "up" or "down"
  int copies = 16;
  double duration = 5.0;                // [s] per copy and speed
  double window = 0.05;                 // [s]; a stretch is two windows
  double perturbation = 1e-6;
  std::uint64_t seed = 1;
  int threads = 0;
  std::string until = "whirl";
  double until_above_hz = 0.0;  // > 0: arrive when the precession exceeds it [Hz] instead of `until`
  std::string until_contacts = "every";  // every or any: the contacts that must be in `until`
  int check_copies = 4;                 // 0: no check sweeps
  double check_step_rpm = 0.5;
  double check_dwell = 5.0;             // [s] per speed of the check sweeps
  std::optional<std::string> out_file;  // default results/<scene>/lifetime.h5
  bool quiet = false;
  // Continue from `<out stem>.checkpoint.h5` (written after the approach and after every speed);
  // a checkpoint of another scene or other options is an error (exit 2).
  bool resume = false;
  // Start again although a checkpoint exists (it is overwritten). With neither flag an existing
  // checkpoint is refused (exit 2): the finished speeds of an interrupted study are never lost unasked.
  bool fresh = false;
  std::string figure_format = "png";  // the figure's file format: png, pdf or svg (--format)
  bool force = false;  // run a plan the plan check refuses (apps/plan_check.h), with a warning
};

int LifetimeCommand(const LifetimeRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
