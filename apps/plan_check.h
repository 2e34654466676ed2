// The checks a command makes between reading its scene and starting its work (issue 50): the plan
// check, which refuses work no real study asks for (studies/work_plan.h: its estimate and limits;
// apps/stage_options.h: a scene's plan), and the warnings for scales that look like unit mistakes
// (models/scale_check.h: the rules), printed naming the scene key. Neither changes the scene.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "apps/scene.h"
#include "studies/work_plan.h"

namespace rubcont {

// Throws std::invalid_argument (exit 2) naming the first item of `plan` over the limits
// (ExcessiveWork), its key, value and estimate, and "--force to run it anyway"; with `force` it
// prints that sentence as a warning on `err` instead and returns.
void CheckPlan(const std::vector<PlannedWork>& plan, bool force, std::ostream& err);

// The scene's scales that look like unit mistakes, one sentence each naming the key, its value and
// the likely mistake: the first length key outside the rotor lengths (with how many more are),
// else each contact's R/C, the surface speed at the top of the speed ranges, and the speed range
// against the knee where a rolling contact meets the lowest natural frequency. Empty for a
// textbook model and for every committed scene.
std::vector<std::string> UnitMistakes(const Scene& scene);

// Prints UnitMistakes as "rubcont: warning: …" lines on `err`; the run goes on.
void WarnUnitMistakes(const Scene& scene, std::ostream& err);

}  // namespace rubcont
