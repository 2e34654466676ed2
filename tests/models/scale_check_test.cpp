#include "models/scale_check.h"

#include <cmath>

#include <catch2/catch.hpp>

#include "models/jeffcott.h"
#include "models/two_point_params.h"
#include "models/units.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

TEST_CASE("Scale check: the pinned natural frequency and knee against closed forms", "[scale_check]") {
  // Case A(a): symmetric bodies, so the pinned translation ω² = (k_L + k_R)/(m_r + m_s) lies below
  // the tilt's k/(2(I_r/l² + I_s/l_s²)) = 7.4e5 (rad/s)².
  const TwoPointParams aa = ThesisCaseAa();
  const double translation = std::sqrt((aa.support_stiffness[0] + aa.support_stiffness[1]) /
                                       (aa.rotor_mass + aa.stator_mass));
  const RubStructure two_point = TwoPointStructure(aa);
  CHECK(PinnedNaturalFrequency(two_point) == Approx(translation).epsilon(1e-12));
  // The knee (C/R)·ω_n: 52.2 rpm, where the whirl's knee of A(a) lies at 50.96 rpm.
  CHECK(RadPerSecondToRpm(RollingKneeSpeed(two_point)) == Approx(RadPerSecondToRpm(translation) / 100.0).epsilon(1e-12));
  CHECK(RadPerSecondToRpm(RollingKneeSpeed(two_point)) == Approx(52.2).margin(0.05));
  // Jeffcott: rotor and stator pinned together, √((k_r + k_s)/(m_r + m_s)).
  const JeffcottParams j;
  CHECK(RadPerSecondToHz(PinnedNaturalFrequency(JeffcottStructure(j))) ==
        Approx(JeffcottNaturalFrequencies(j).combined_hz).epsilon(1e-12));
}

TEST_CASE("Scale check: each rule fires outside its limits only", "[scale_check]") {
  CHECK(LengthScaleMistake(0.29).empty());
  CHECK(LengthScaleMistake(0.0).empty());
  CHECK(LengthScaleMistake(-0.1).empty());
  CHECK_THAT(LengthScaleMistake(290.0), Contains("mm written as m"));
  CHECK_THAT(LengthScaleMistake(-290.0), Contains("mm written as m"));
  CHECK_THAT(LengthScaleMistake(3.81e-7), Contains("1 µm"));
  CHECK(ClearanceRatioMistake(0.0381, 3.81e-4).empty());
  CHECK_THAT(ClearanceRatioMistake(0.0381, 0.381), Contains("R/C = 0.1"));
  CHECK_THAT(ClearanceRatioMistake(1e6, 3.81e-4), Contains("different units"));
  CHECK(SurfaceSpeedMistake(0.0381, RpmToRadPerSecond(260.0)).empty());
  CHECK_THAT(SurfaceSpeedMistake(0.0381, RpmToRadPerSecond(1e9)), Contains("burst speed"));
  const double knee = RpmToRadPerSecond(52.2);
  CHECK(SpeedRangeMistake(knee, RpmToRadPerSecond(20.0), RpmToRadPerSecond(260.0)).empty());
  CHECK(SpeedRangeMistake(knee, RpmToRadPerSecond(500.0), RpmToRadPerSecond(520.0)).empty());
  CHECK_THAT(SpeedRangeMistake(knee, RpmToRadPerSecond(530.0), RpmToRadPerSecond(600.0)), Contains("above"));
  CHECK_THAT(SpeedRangeMistake(knee, RpmToRadPerSecond(1.0), RpmToRadPerSecond(5.0)), Contains("below"));
}

}  // namespace
}  // namespace rubcont
