#include "apps/analytic_output.h"

#include <filesystem>
#include <string>

#include <catch2/catch.hpp>
#include <unistd.h>

namespace rubcont {
namespace {

namespace fs = std::filesystem;

void CheckSame(const AnalyticCurve& a, const AnalyticCurve& b) {
  CHECK(a.mode == b.mode);
  CHECK(a.precession_hz == b.precession_hz);
  for (int k = 0; k < 2; ++k) {
    CHECK(a.normal_force[k] == b.normal_force[k]);
    CHECK(a.friction_force[k] == b.friction_force[k]);
    CHECK(a.mu_required[k] == b.mu_required[k]);
  }
  CHECK(a.status == b.status);
  REQUIRE(a.transitions.size() == b.transitions.size());
  for (std::size_t i = 0; i < a.transitions.size(); ++i) {
    CHECK(a.transitions[i].type == b.transitions[i].type);
    CHECK(a.transitions[i].contact == b.transitions[i].contact);
    CHECK(a.transitions[i].direction == b.transitions[i].direction);
    CHECK(a.transitions[i].precession_hz == b.transitions[i].precession_hz);
    CHECK(a.transitions[i].normal_force == b.transitions[i].normal_force);
    CHECK(a.transitions[i].through_pole == b.transitions[i].through_pole);
  }
}

TEST_CASE("The analytic result survives an HDF5 round trip bit for bit, in the README's layout",
          "[hdf5][analytic]") {
  const fs::path file = fs::temp_directory_path() / ("rubcont_analytic_" + std::to_string(getpid()) + ".h5");
  TwoPointParams p = ThesisCaseAa();  // thesis A(a) with the centre damper
  p.clearance = {3.81e-4, 3.048e-4};  // unequal, so left and right differ
  AnalyticOptions options;
  options.precession_points = 500;
  const AnalyticResult result = ComputeAnalytic(p, options);
  TwoPointParams q = p;
  q.center_damping = 0.0;
  const AnalyticResult thesis_form = ComputeAnalytic(q, options);
  {
    ResultWriter writer(file);
    WriteAnalytic(writer, p, result, &thesis_form);
    writer.Commit();
  }
  const ResultReader reader(file);
  CheckSame(ReadAnalyticCurve(reader, "/analytic/mode1"), result.mode1);
  CheckSame(ReadAnalyticCurve(reader, "/analytic/mode2"), result.mode2);
  CheckSame(ReadAnalyticCurve(reader, "/analytic/mode2/without_center_damper"), thesis_form.mode2);
  const NaturalFrequencies nf = ReadNaturalFrequencies(reader);
  CHECK(nf.stator_bounce.frequency_hz == result.natural_frequencies.stator_bounce.frequency_hz);
  CHECK(nf.pinned_pitch.frequency_hz == result.natural_frequencies.pinned_pitch.frequency_hz);
  // The names users rely on (docs/result_files.md).
  for (const char* name : {"precession_hz", "normal_force_left", "normal_force_right",
                           "mu_required_left", "mu_required_right", "transitions/type",
                           "transitions/contact", "transitions/precession_hz"})
    CHECK(reader.Exists(std::string("/analytic/mode1/") + name));
  for (const char* name : {"stator_bounce_hz", "stator_pitch_hz", "pinned_bounce_hz", "pinned_pitch_hz"})
    CHECK(reader.HasAttribute("/analytic/natural_frequencies", name));
  CHECK(reader.ReadStringAttribute("/analytic", "level") == "L0");
  CHECK(reader.ReadDoubleAttribute("/analytic", "center_damping") == 52.0);
  fs::remove(file);
}

}  // namespace
}  // namespace rubcont
