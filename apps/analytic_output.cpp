#include "apps/analytic_output.h"
#include "apps/level.h"

#include <stdexcept>
#include <vector>

namespace rubcont {
namespace {

const char* kContactNames[2] = {"left", "right"};

// The name of contact k in dataset names: "left"/"right", or "contact" for a single contact.
std::string ContactName(const AnalyticCurve& curve, int k) {
  return curve.mode == CircularMode::kSingleContact ? "contact" : kContactNames[k];
}

int ContactCount(const AnalyticCurve& curve) {
  return curve.mode == CircularMode::kSingleContact ? 1 : 2;
}

void WriteCurve(ResultWriter& writer, const std::string& group, const AnalyticCurve& curve,
                bool with_grid) {
  writer.CreateGroup(group);
  if (with_grid) {
    writer.WriteDoubles(group + "/precession_hz", curve.precession_hz);
    writer.SetDimensionScales(group, "precession_hz");  // xarray: the grid is the coordinate
  }
  for (int k = 0; k < ContactCount(curve); ++k) {
    const std::string side = ContactName(curve, k);
    writer.WriteDoubles(group + "/normal_force_" + side, curve.normal_force[k]);
    writer.WriteDoubles(group + "/friction_force_" + side, curve.friction_force[k]);
    writer.WriteDoubles(group + "/mu_required_" + side, curve.mu_required[k]);
  }
  writer.SetAttribute(group, "status", ToString(curve.status));
  if (!curve.message.empty()) writer.SetAttribute(group, "message", curve.message);

  std::vector<std::string> type, contact;
  std::vector<int> direction, through_pole;
  std::vector<double> precession_hz, normal_force;
  for (const Transition& t : curve.transitions) {
    type.push_back(ToString(t.type));
    contact.push_back(ContactName(curve, t.contact));
    direction.push_back(t.direction);
    through_pole.push_back(t.through_pole ? 1 : 0);
    precession_hz.push_back(t.precession_hz);
    normal_force.push_back(t.normal_force);
  }
  const std::string transitions = group + "/transitions";
  writer.WriteStrings(transitions + "/type", type);
  writer.WriteStrings(transitions + "/contact", contact);
  writer.WriteInts(transitions + "/direction", direction);
  writer.WriteDoubles(transitions + "/precession_hz", precession_hz);
  writer.WriteDoubles(transitions + "/normal_force", normal_force);
  writer.WriteInts(transitions + "/through_pole", through_pole);
}

Vector ToVector(const std::vector<double>& values) {
  return Eigen::Map<const Vector>(values.data(), static_cast<Index>(values.size()));
}

}  // namespace

void WriteAnalytic(ResultWriter& writer, const TwoPointParams& params, const AnalyticResult& result,
                   const AnalyticResult* without_damper) {
  writer.CreateGroup("/analytic");
  writer.SetAttribute("/analytic", "level", ToString(Level::kL0));
  writer.SetAttribute("/analytic", "friction", params.friction);
  writer.SetAttribute("/analytic", "center_damping", params.center_damping);
  const std::string nf = "/analytic/natural_frequencies";
  writer.CreateGroup(nf);
  writer.SetAttribute(nf, "stator_bounce_hz", result.natural_frequencies.stator_bounce.frequency_hz);
  writer.SetAttribute(nf, "stator_pitch_hz", result.natural_frequencies.stator_pitch.frequency_hz);
  writer.SetAttribute(nf, "pinned_bounce_hz", result.natural_frequencies.pinned_bounce.frequency_hz);
  writer.SetAttribute(nf, "pinned_pitch_hz", result.natural_frequencies.pinned_pitch.frequency_hz);
  for (const AnalyticCurve* curve : {&result.mode1, &result.mode2}) {
    const std::string group = std::string("/analytic/") + ToString(curve->mode);
    WriteCurve(writer, group, *curve, true);
    writer.SetAttribute(group, "contact_sign", static_cast<double>(ContactSign(curve->mode)));
    if (without_damper != nullptr) {
      const AnalyticCurve& other =
          curve->mode == CircularMode::kMode1 ? without_damper->mode1 : without_damper->mode2;
      WriteCurve(writer, group + "/without_center_damper", other, false);
    }
  }
}

void WriteJeffcottAnalytic(ResultWriter& writer, const JeffcottParams& params,
                           const AnalyticCurve& curve) {
  writer.CreateGroup("/analytic");
  writer.SetAttribute("/analytic", "level", ToString(Level::kL0));
  writer.SetAttribute("/analytic", "friction", params.friction);
  const JeffcottFrequencies f = JeffcottNaturalFrequencies(params);
  const std::string nf = "/analytic/natural_frequencies";
  writer.CreateGroup(nf);
  writer.SetAttribute(nf, "rotor_hz", f.rotor_hz);
  writer.SetAttribute(nf, "stator_hz", f.stator_hz);
  writer.SetAttribute(nf, "combined_hz", f.combined_hz);
  WriteCurve(writer, "/analytic/single", curve, true);
}

AnalyticCurve ReadAnalyticCurve(const ResultReader& reader, const std::string& group) {
  AnalyticCurve curve;
  const bool nested = group.size() > 22 && group.substr(group.size() - 22) == "/without_center_damper";
  const std::string mode_group = nested ? group.substr(0, group.size() - 22) : group;
  const std::string tail = mode_group.substr(mode_group.rfind('/') + 1);
  curve.mode = tail == "mode2"    ? CircularMode::kMode2
               : tail == "single" ? CircularMode::kSingleContact
                                  : CircularMode::kMode1;
  curve.precession_hz = ToVector(reader.ReadDoubles(mode_group + "/precession_hz"));
  for (int k = 0; k < ContactCount(curve); ++k) {
    const std::string side = ContactName(curve, k);
    curve.normal_force[k] = ToVector(reader.ReadDoubles(group + "/normal_force_" + side));
    curve.friction_force[k] = ToVector(reader.ReadDoubles(group + "/friction_force_" + side));
    curve.mu_required[k] = ToVector(reader.ReadDoubles(group + "/mu_required_" + side));
  }
  curve.status = reader.ReadStringAttribute(group, "status") == ToString(AnalyticStatus::kSuccess)
                     ? AnalyticStatus::kSuccess
                     : AnalyticStatus::kNonFinite;
  if (reader.HasAttribute(group, "message")) curve.message = reader.ReadStringAttribute(group, "message");
  const std::string t = group + "/transitions";
  const auto type = reader.ReadStrings(t + "/type");
  const auto contact = reader.ReadStrings(t + "/contact");
  const auto direction = reader.ReadInts(t + "/direction");
  const auto precession_hz = reader.ReadDoubles(t + "/precession_hz");
  const auto normal_force = reader.ReadDoubles(t + "/normal_force");
  const auto through_pole = reader.ReadInts(t + "/through_pole");
  for (std::size_t i = 0; i < type.size(); ++i) {
    Transition transition;
    bool known = false;
    for (TransitionType candidate :
         {TransitionType::kMuCrossing, TransitionType::kNegativeMuCrossing, TransitionType::kZeroMuCrossing,
          TransitionType::kContactLoss, TransitionType::kContactRegain}) {
      if (type[i] == ToString(candidate)) {
        transition.type = candidate;
        known = true;
      }
    }
    if (!known) throw std::runtime_error(t + "/type: unknown transition type \"" + type[i] + "\"");
    transition.contact = contact[i] == "right" ? 1 : 0;
    transition.direction = direction[i];
    transition.precession_hz = precession_hz[i];
    transition.normal_force = normal_force[i];
    transition.through_pole = through_pole[i] != 0;
    curve.transitions.push_back(transition);
  }
  return curve;
}

NaturalFrequencies ReadNaturalFrequencies(const ResultReader& reader) {
  const std::string nf = "/analytic/natural_frequencies";
  NaturalFrequencies result;
  result.stator_bounce.frequency_hz = reader.ReadDoubleAttribute(nf, "stator_bounce_hz");
  result.stator_pitch.frequency_hz = reader.ReadDoubleAttribute(nf, "stator_pitch_hz");
  result.pinned_bounce.frequency_hz = reader.ReadDoubleAttribute(nf, "pinned_bounce_hz");
  result.pinned_pitch.frequency_hz = reader.ReadDoubleAttribute(nf, "pinned_pitch_hz");
  return result;
}

}  // namespace rubcont
