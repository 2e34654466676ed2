#include "apps/analytic_stage.h"

#include <cmath>
#include <optional>
#include <ostream>
#include <utility>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/analytic_output.h"
#include "apps/stage_options.h"
#include "models/jeffcott.h"
#include "solvers/stopwatch.h"

namespace rubcont {

namespace {

template <class... Args>
void StageProgress(StageContext& context, fmt::format_string<Args...> format, Args&&... args) {
  context.progress(fmt::format(format, std::forward<Args>(args)...));
}

std::string Describe(const Transition& t) {
  switch (t.type) {
    case TransitionType::kMuCrossing:
      return t.direction > 0 ? "μ_req rises through μ: rolling → slipping (whirl → whip)"
                             : "μ_req falls through μ: slipping → rolling (whip → whirl)";
    case TransitionType::kNegativeMuCrossing:
      return t.direction > 0 ? "μ_req rises through −μ" : "μ_req falls through −μ";
    case TransitionType::kZeroMuCrossing:
      return t.direction > 0 ? "μ_req rises through 0 (friction turns to drive the precession)"
                             : "μ_req falls through 0 (friction would have to oppose the precession)";
    case TransitionType::kContactLoss:
      return t.through_pole ? "N: + → − through a pole (undamped resonance): contact lost"
                            : "N falls through 0: contact lost";
    case TransitionType::kContactRegain:
      return t.through_pole ? "N: − → + through a pole (undamped resonance): contact regained"
                            : "N rises through 0: contact regained";
  }
  return "";
}

void PrintCurve(std::ostream& out, const AnalyticCurve& curve) {
  fmt::print(out, "  {} ({}):\n", ToString(curve.mode),
             curve.mode == CircularMode::kMode1   ? "normals in phase"
             : curve.mode == CircularMode::kMode2 ? "normals in antiphase"
                                                  : "one contact");
  if (curve.transitions.empty()) fmt::print(out, "    no transitions in range\n");
  const auto& t = curve.transitions;
  for (std::size_t i = 0; i < t.size(); ++i) {
    // Symmetric rotors give the same transition at both contacts: print it once.
    const bool both = i + 1 < t.size() && t[i + 1].type == t[i].type &&
                      t[i + 1].direction == t[i].direction && t[i + 1].contact != t[i].contact &&
                      std::abs(t[i + 1].precession_hz - t[i].precession_hz) <= 1e-9 * t[i].precession_hz;
    const char* where = curve.mode == CircularMode::kSingleContact ? ""
                        : both                                      ? "both"
                        : t[i].contact == 0                         ? "left"
                                                                    : "right";
    fmt::print(out, "    {:10.4f} Hz  {:<5}  {}\n", t[i].precession_hz, where, Describe(t[i]));
    if (both) ++i;
  }
  if (!curve.Succeeded()) fmt::print(out, "    status {}: {}\n", ToString(curve.status), curve.message);
}

}  // namespace

void RunTwoPointAnalytic(const Scene& scene, StageContext& context) {
  const SteadyClock::time_point start = SteadyClock::now();
  const TwoPointParams& p = scene.two_point;
  const AnalyticOptions options = AnalyticOptionsOf(scene);
  const AnalyticResult result = ComputeAnalytic(p, options);
  // The thesis's closed form (no centre damper) beside the scene's, when they differ.
  std::optional<AnalyticResult> without_damper;
  if (p.center_damping > 0.0) {
    TwoPointParams q = p;
    q.center_damping = 0.0;
    without_damper = ComputeAnalytic(q, options);
  }
  const double compute_ms = 1e3 * SecondsSince(start);
  const SteadyClock::time_point write_start = SteadyClock::now();
  WriteAnalytic(context.writer, p, result, without_damper ? &*without_damper : nullptr);
  StageProgress(context, "[analytic] L0 closed form, 2 modes × {} frequencies{}: computed in {:.1f} ms, "
                "written in {:.1f} ms", options.precession_points,
                without_damper ? ", with and without the centre damper" : "", compute_ms,
                1e3 * SecondsSince(write_start));

  const NaturalFrequencies& nf = result.natural_frequencies;
  fmt::print(context.out, "[analytic] L0 closed form, μ = {}, c_d = {} N·s/m, {} points over {}–{} Hz\n",
             p.friction, p.center_damping, options.precession_points,
             options.min_precession_hz, options.max_precession_hz);
  fmt::print(context.out, "  natural frequencies: stator bounce {:.3f} Hz, pitch {:.3f} Hz; "
                  "rotor and stator pinned: bounce {:.3f} Hz, pitch {:.3f} Hz\n",
             nf.stator_bounce.frequency_hz, nf.stator_pitch.frequency_hz,
             nf.pinned_bounce.frequency_hz, nf.pinned_pitch.frequency_hz);
  PrintCurve(context.out, result.mode1);
  PrintCurve(context.out, result.mode2);
  for (const AnalyticCurve* curve : {&result.mode1, &result.mode2})
    if (!curve->Succeeded()) context.failures.push_back("[analytic] " + curve->message);
}

void RunJeffcottAnalytic(const Scene& scene, StageContext& context) {
  const SteadyClock::time_point start = SteadyClock::now();
  const AnalyticOptions options = AnalyticOptionsOf(scene);
  const AnalyticCurve curve = ComputeJeffcottCurve(scene.jeffcott, options);
  WriteJeffcottAnalytic(context.writer, scene.jeffcott, curve);
  StageProgress(context, "[analytic] L0 closed form (Jeffcott), {} frequencies: {:.1f} ms",
                options.precession_points, 1e3 * SecondsSince(start));
  const JeffcottFrequencies f = JeffcottNaturalFrequencies(scene.jeffcott);
  fmt::print(context.out, "[analytic] L0 closed form, μ = {}, {} points over {}–{} Hz\n",
             scene.jeffcott.friction, options.precession_points, options.min_precession_hz,
             options.max_precession_hz);
  fmt::print(context.out, "  natural frequencies: rotor {:.3f} Hz, stator {:.3f} Hz, "
                  "pinned together {:.3f} Hz\n",
             f.rotor_hz, f.stator_hz, f.combined_hz);
  PrintCurve(context.out, curve);
  if (!curve.Succeeded()) context.failures.push_back("[analytic] " + curve.message);
}

}  // namespace rubcont
