#include "models/flexible.h"

#include <cmath>
#include <complex>
#include <string>

#include <catch2/catch.hpp>

#include "models/analytic.h"
#include "models/two_point_params.h"
#include "models/units.h"

namespace rubcont {
namespace {

ShaftElement SteelSection(double outer, double inner, double stiffening = 1.0) {
  ShaftElement e;
  e.outer_diameter = outer;
  e.inner_diameter = inner;
  e.youngs_modulus = 2.11e11 * stiffening;
  e.shear_modulus = 8.12e10 * stiffening;
  e.density = 7810.0;
  return e;
}

double RelativeDifference(const Matrix& a, const Matrix& b) { return (a - b).norm() / b.norm(); }

TEST_CASE("flexible two-point model: Guyan condensation is the rigid model, whatever E",
          "[flexible]") {
  // Held at its two contact planes a free–free shaft moves rigidly, so the static constraint
  // modes are rigid-body motions and M, C, K and the imbalance weights are the rigid model's.
  // Beyond the right contact (scenes/overhung_beyond_right.toml): the shaft goes on to the disk.
  TwoPointParams beyond = ThesisCaseAa();
  beyond.rotor_mass_center = 0.35;
  beyond.rotor_inertia = 0.07;
  for (const TwoPointParams& p : {ThesisCaseAa(), ThesisCaseCa(), beyond}) {
    TwoPointParams imbalanced = p;
    imbalanced.imbalance = 3.43e-5;
    const RubStructure rigid = TwoPointStructure(imbalanced);
    const FlexibleRub flexible = BuildFlexibleRub(FlexibleTwoPoint(
        imbalanced, SteelSection(0.02, 0.0), SteelSection(0.16, 0.13), 8, 0));
    const RubStructure& s = flexible.structure;
    REQUIRE(s.Coordinates() == 4);
    CHECK(RelativeDifference(s.mass, rigid.mass) < 1e-12);
    CHECK(RelativeDifference(s.stiffness, rigid.stiffness) < 1e-12);
    CHECK(RelativeDifference(s.damping, rigid.damping) < 1e-12);
    CHECK((s.imbalance_weights - rigid.imbalance_weights).norm() < 1e-12);
    CHECK(s.coordinate_names == rigid.coordinate_names);
    CHECK(s.contacts[1].rotor == rigid.contacts[1].rotor);
    CHECK(s.contacts[1].stator == rigid.contacts[1].stator);
  }
}

TEST_CASE("flexible two-point model: the rigid limit E → ∞ with modes, to 1e-4", "[flexible]") {
  const TwoPointParams p = ThesisCaseAa();
  const RubStructure rigid = TwoPointStructure(p);
  // Pinned, undamped: the closed form eig((M_r + M_s)⁻¹K_s) (87.04 and 137.0 Hz).
  TwoPointParams undamped = p;
  undamped.support_damping = {0.0, 0.0};
  undamped.center_damping = 0.0;
  const NaturalFrequencies closed = ComputeNaturalFrequencies(p);
  const std::vector<StructureMode> undamped_modes = StructureModes(TwoPointStructure(undamped), true);
  REQUIRE(undamped_modes.size() == 2);
  CHECK(undamped_modes[0].frequency_hz == Approx(closed.pinned_bounce.frequency_hz).epsilon(1e-12));
  CHECK(undamped_modes[1].frequency_hz == Approx(closed.pinned_pitch.frequency_hz).epsilon(1e-12));
  CHECK(undamped_modes[0].damping_ratio == 0.0);
  CHECK(closed.pinned_bounce.frequency_hz == Approx(87.04).epsilon(0).margin(0.005));
  const std::vector<StructureMode> rigid_modes = StructureModes(rigid, true);
  REQUIRE(rigid_modes.size() == 2);
  for (double stiffening : {1e4, 1e6}) {
    FlexibleRubModel model = FlexibleTwoPoint(p, SteelSection(0.03, 0.0, stiffening),
                                              SteelSection(0.16, 0.13, stiffening), 8, 4);
    model.gyroscopic = false;  // the rigid model has none
    const RubStructure s = BuildFlexibleRub(model).structure;
    REQUIRE(s.Coordinates() == 8);
    const std::vector<StructureMode> modes = StructureModes(s, true);
    INFO("E × " << stiffening);
    for (std::size_t i = 0; i < 2; ++i) {
      CHECK(modes[i].frequency_hz == Approx(rigid_modes[i].frequency_hz).epsilon(1e-4));
      CHECK(modes[i].damping_ratio == Approx(rigid_modes[i].damping_ratio).epsilon(1e-4));
    }
    CHECK(modes[2].frequency_hz > 1e4);  // bending moved far up
    // Mode 1 / Mode 2 circular orbits (L0's closed form on the structure): forces to 1e-4.
    for (double hz : {70.0, 84.5, 120.0}) {
      for (double sign : {1.0, -1.0}) {
        const auto a = SolveRigidContactOrbit(rigid, kTwoPi * hz, {1.0, sign}).force;
        const auto b = SolveRigidContactOrbit(s, kTwoPi * hz, {1.0, sign}).force;
        for (std::size_t k = 0; k < 2; ++k) CHECK(std::abs(b[k] - a[k]) < 1e-4 * std::abs(a[k]));
      }
    }
  }
}

TEST_CASE("flexible two-point model: steel shafts soften the pinned modes, spin splits them",
          "[flexible]") {
  const RubStructure s = BuildFlexibleRub(FlexibleTwoPoint(
      ThesisCaseAa(), SteelSection(0.03, 0.0), SteelSection(0.16, 0.13), 8, 4)).structure;
  const std::vector<StructureMode> rigid = StructureModes(TwoPointStructure(ThesisCaseAa()), true);
  const std::vector<StructureMode> rest = StructureModes(s, true);
  CHECK(rest[0].frequency_hz < rigid[0].frequency_hz);
  CHECK(rest[1].frequency_hz < rigid[1].frequency_hz);
  // The thin (30 mm) shaft's pitch mode moves most; spin stiffens forward whirl, softens backward.
  const double spin = RpmToRadPerSecond(3000.0);
  const std::vector<StructureMode> forward = StructureModes(s, true, spin);
  const std::vector<StructureMode> backward = StructureModes(s, true, spin, true);
  CHECK(forward[1].frequency_hz > rest[1].frequency_hz);
  CHECK(backward[1].frequency_hz < rest[1].frequency_hz);
}

TEST_CASE("flexible rub model validation names the entry and the rule", "[flexible]") {
  const FlexibleRubModel good = FlexibleTwoPoint(ThesisCaseAa(), SteelSection(0.03, 0.0),
                                                 SteelSection(0.16, 0.13), 4, 2);
  CHECK_NOTHROW(BuildFlexibleRub(good));
  FlexibleRubModel bad = good;
  bad.contacts[1].stator_shaft = 0;
  CHECK_THROWS_WITH(BuildFlexibleRub(bad), "contacts[1].stator_shaft = 0: must differ from "
                                           "rotor_shaft (a contact joins two shafts)");
  bad = good;
  bad.contacts[0].rotor_node = 99;
  CHECK_THROWS_WITH(BuildFlexibleRub(bad), Catch::StartsWith("contacts[0].rotor_node = 99: must "
                                                             "name a node of shafts[0]"));
  bad = good;
  bad.contacts[1].rotor_node = 0;
  bad.contacts[1].stator_node = 0;
  CHECK_THROWS_WITH(BuildFlexibleRub(bad),
                    "contacts[1]: touches at a node another contact already uses");
  bad = good;
  bad.modal_damping = -0.1;
  CHECK_THROWS_WITH(BuildFlexibleRub(bad), Catch::StartsWith("modal_damping = -0.1"));
  CHECK_THROWS_WITH(FlexibleTwoPoint(ThesisCaseAa(), SteelSection(0.1, 0.0),
                                     SteelSection(0.16, 0.13), 4, 2),
                    Catch::StartsWith("rotor shaft: 17.79") &&
                        Catch::EndsWith("is not lighter than the body (9.99 kg): take a thinner "
                                        "section"));
  // Typed, so that a caller can name its own input: the section, the modes.
  try {
    FlexibleTwoPoint(ThesisCaseAa(), SteelSection(0.03, 0.0), SteelSection(0.2, 0.0), 4, 2);
    FAIL("a stator tube heavier than the stator was accepted");
  } catch (const ModelInputError& e) {
    CHECK(e.input() == "stator section");
  }
  try {
    BuildFlexibleRub(FlexibleTwoPoint(ThesisCaseAa(), SteelSection(0.03, 0.0),
                                      SteelSection(0.16, 0.13), 2, 900));
    FAIL("900 modes of a 2-element model were accepted");
  } catch (const ModelInputError& e) {
    CHECK(e.input() == "modes");
  }
}

TEST_CASE("a body shaft's rigid-body data: a uniform body completes to the rigid model's, a listed "
          "one is the sum of its pieces", "[flexible]") {
  TwoPointParams beyond = ThesisCaseAa();
  beyond.rotor_mass_center = 0.35;
  beyond.rotor_inertia = 0.07;
  for (const TwoPointParams& p : {ThesisCaseAa(), ThesisCaseCa(), beyond}) {
    const RigidBodyData r = RigidBodyOf(UniformBody("rotor", SteelSection(0.02, 0.0), p.contact_span,
                                                    8, p.rotor_mass, p.rotor_inertia,
                                                    p.rotor_mass_center, {}));
    CHECK(r.mass == Approx(p.rotor_mass).epsilon(1e-13));
    CHECK(r.span == Approx(p.contact_span).epsilon(1e-13));
    CHECK(r.mass_center == Approx(p.rotor_mass_center).epsilon(1e-12));
    CHECK(r.inertia == Approx(p.rotor_inertia).epsilon(1e-12));
  }
  // A solid rod of length 0.4 m in two elements, contacts at its ends, then a 2 kg disk at the
  // middle (I_d 0.01) with the contacts at stations 1 and 2: the rod's m, L/2, m(L²/12 + D²/16).
  BodyShaft rod;
  ShaftElement half = SteelSection(0.05, 0.0);
  half.length = 0.2;
  rod.shaft.name = "rod";
  rod.shaft.elements = {half, half};
  rod.contact_stations = {0, 2};
  const double m = 7810.0 * kPi * 0.05 * 0.05 / 4 * 0.4;
  RigidBodyData r = RigidBodyOf(rod);
  CHECK(r.mass == Approx(m).epsilon(1e-14));
  CHECK(r.span == Approx(0.4).epsilon(1e-14));
  CHECK(r.mass_center == Approx(0.2).epsilon(1e-14));
  CHECK(r.inertia == Approx(m * (0.4 * 0.4 / 12 + 0.05 * 0.05 / 16)).epsilon(1e-14));
  rod.shaft.disks = {{1, 2.0, 0.01, 0.02}};
  rod.contact_stations = {1, 2};
  r = RigidBodyOf(rod);
  CHECK(r.mass == Approx(m + 2.0).epsilon(1e-14));
  CHECK(r.span == Approx(0.2).epsilon(1e-14));
  CHECK(r.mass_center == Approx(0.0).epsilon(0).margin(1e-15));
  CHECK(r.inertia == Approx(m * (0.4 * 0.4 / 12 + 0.05 * 0.05 / 16) + 0.01).epsilon(1e-14));

  rod.contact_stations = {2, 1};
  CHECK_THROWS_WITH(RigidBodyOf(rod), "rod shaft: contact_stations = [2, 1]: the right contact "
                                      "must lie beyond the left one");
  rod.contact_stations = {0, 3};
  CHECK_THROWS_WITH(RigidBodyOf(rod),
                    "rod shaft: contact_stations[1] = 3: must name a station (0 to 2)");
}

TEST_CASE("flexible two-point model on listed shafts: Guyan condensation is the rigid model of "
          "their rigid-body data", "[flexible]") {
  // A stepped rotor overhanging both contacts (stations 1 and 4 of six elements), a disk on
  // station 5; a stator tube with its contacts one element in from each end. Held at the four
  // contact planes the shafts move rigidly: M, C, K are those of the rigid model whose bodies
  // have RigidBodyOf's data.
  auto section = [](double length, double outer, double inner) {
    ShaftElement e = SteelSection(outer, inner);
    e.length = length;
    return e;
  };
  BodyShaft rotor;
  rotor.shaft.name = "rotor";
  rotor.shaft.elements = {section(0.03, 0.04, 0.0), section(0.1, 0.05, 0.02),
                          section(0.1, 0.05, 0.02), section(0.1, 0.045, 0.02),
                          section(0.05, 0.04, 0.0), section(0.02, 0.04, 0.0)};
  rotor.shaft.disks = {{5, 3.0, 0.004, 0.008}};
  rotor.contact_stations = {1, 4};
  BodyShaft stator;
  stator.shaft.name = "stator";
  stator.shaft.elements = {section(0.02, 0.16, 0.13), section(0.125, 0.16, 0.1),
                           section(0.125, 0.16, 0.1), section(0.02, 0.16, 0.13)};
  stator.contact_stations = {1, 3};
  TwoPointParams p = ThesisCaseAa();
  const RigidBodyData r = RigidBodyOf(rotor), s = RigidBodyOf(stator);
  p.rotor_mass = r.mass;
  p.contact_span = r.span;
  p.rotor_mass_center = r.mass_center;
  p.rotor_inertia = r.inertia;
  p.stator_mass = s.mass;
  p.stator_span = s.span;
  p.stator_mass_center = s.mass_center;
  p.stator_inertia = s.inertia;
  p.center_damping = 0.0;  // the rotor has no station at the mid-span of its contacts
  const RubStructure rigid = TwoPointStructure(p);
  const RubStructure guyan = BuildFlexibleRub(FlexibleTwoPoint(p, rotor, stator, 0)).structure;
  CHECK(RelativeDifference(guyan.mass, rigid.mass) < 1e-12);
  CHECK(RelativeDifference(guyan.stiffness, rigid.stiffness) < 1e-12);
  CHECK(RelativeDifference(guyan.damping, rigid.damping) < 1e-12);

  p.center_damping = 52.0;
  CHECK_THROWS_WITH(FlexibleTwoPoint(p, rotor, stator, 0),
                    Catch::StartsWith("rotor shaft: center_damping = 52 N·s/m acts at the mid-span "
                                      "of the contacts, 0.15 m from the left one, where the shaft "
                                      "has no station (the nearest, "));
  rotor.shaft.elements[2].length = 0.05;  // stations at 0.1 m and 0.15 m from the left contact
  rotor.shaft.elements.insert(rotor.shaft.elements.begin() + 3, section(0.05, 0.05, 0.02));
  rotor.contact_stations = {1, 5};
  rotor.shaft.disks[0].node = 6;
  CHECK_NOTHROW(BuildFlexibleRub(FlexibleTwoPoint(p, rotor, stator, 4)));
}

}  // namespace
}  // namespace rubcont
