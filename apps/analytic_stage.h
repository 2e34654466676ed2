// The "analytic" stage of `rubcont run` (level L0): the closed-form circular whirl and whip of a
// rub model, computed on the scene's precession grid, written to /analytic (apps/analytic_output.h)
// and summarized on the context's `out` (natural frequencies, every located transition).
#pragma once

#include "apps/models.h"

namespace rubcont {

// Model two_point: Mode 1 and Mode 2 (models/analytic.h), and the thesis's closed form without the
// centre damper beside them when the scene has one.
void RunTwoPointAnalytic(const Scene& scene, StageContext& context);
// Model jeffcott: the single-contact closed form (models/jeffcott.h).
void RunJeffcottAnalytic(const Scene& scene, StageContext& context);

}  // namespace rubcont
