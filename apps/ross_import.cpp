#include "apps/ross_import.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "apps/atomic_file.h"
#include "apps/guarded.h"
#include "apps/models.h"
#include "apps/scene_schema.h"
#include "models/flexible.h"

namespace rubcont {
namespace {

// One element's table, with the messages that name it by its table header as the file writes
// it: ["BearingElement_Bearing 1"], ["ShaftElement_ShaftElement 3".material].
class Element {
 public:
  Element(const std::filesystem::path& file, std::string header, const toml::table& table)
      : file_(file.string()), header_(std::move(header)), table_(table) {}

  const std::string& header() const { return header_; }

  [[noreturn]] void Refuse(const std::string& key, const std::string& rule) const {
    const std::string separator = rule.rfind("= ", 0) == 0 ? " " : ": ";
    throw std::invalid_argument(fmt::format("{}: [{}] {}{}", file_, header_,
                                            key.empty() ? "" : key + separator, rule));
  }

  bool Has(const std::string& key) const { return table_.contains(key); }

  // A number, or a list of numbers over `frequency` (a coefficient); `otherwise` when absent.
  std::vector<double> Numbers(const std::string& key, std::optional<double> otherwise) const {
    const toml::node* node = table_.get(key);
    if (node == nullptr) {
      if (!otherwise) Refuse(key, "missing");
      return {*otherwise};
    }
    std::vector<double> out;
    auto read = [&](const toml::node& n) {
      if (const auto* f = n.as_floating_point()) return out.push_back(f->get());
      if (const auto* i = n.as_integer()) return out.push_back(static_cast<double>(i->get()));
      Refuse(key, "must be a number or a list of numbers");
    };
    if (const toml::array* list = node->as_array()) {
      for (const toml::node& n : *list) read(n);
      if (out.empty()) Refuse(key, "an empty list");
    } else {
      read(*node);
    }
    return out;
  }

  // A number that does not vary with frequency.
  double Number(const std::string& key, std::optional<double> otherwise = std::nullopt) const {
    const std::vector<double> values = Numbers(key, otherwise);
    if (std::any_of(values.begin(), values.end(), [&](double v) { return v != values[0]; })) {
      Refuse(key, fmt::format("varies with frequency ({} values, {:.6g} … {:.6g}): rubcont's "
                              "supports have constant coefficients",
                              values.size(), *std::min_element(values.begin(), values.end()),
                              *std::max_element(values.begin(), values.end())));
    }
    if (!std::isfinite(values[0])) Refuse(key, "must be finite");
    return values[0];
  }

  int Node(int nodes) const {
    const double n = Number("n");
    if (n != std::floor(n) || n < 0 || n >= nodes)
      Refuse("n", fmt::format("= {}: must be a node of the shaft (0 to {})", n, nodes - 1));
    return static_cast<int>(n);
  }

  void RequireZero(const std::string& key, const std::string& rule) const {
    if (Has(key) && Number(key, 0.0) != 0.0)
      Refuse(key, fmt::format("= {}: {}", schema::FormatFloat(Number(key, 0.0), true), rule));
  }

  void RequireFlag(const std::string& key, bool expected, const std::string& rule) const {
    const toml::node* node = table_.get(key);
    if (node == nullptr) return;
    const auto* flag = node->as_boolean();
    if (flag == nullptr || flag->get() != expected)
      Refuse(key, fmt::format("must be {}: {}", expected ? "true" : "false", rule));
  }

  const toml::table& table() const { return table_; }
  const std::string& File() const { return file_; }

 private:
  std::string file_;
  std::string header_;
  const toml::table& table_;
};

ShaftRow ShaftRowOf(const Element& e) {
  const double idl = e.Number("idl"), odl = e.Number("odl");
  const double idr = e.Number("idr", idl), odr = e.Number("odr", odl);
  if (idl != idr || odl != odr) {
    e.Refuse("", fmt::format("tapered (idl = {}, idr = {}, odl = {}, odr = {}): rubcont's "
                             "elements are uniform; give idl = idr and odl = odr (cut a taper "
                             "into uniform steps)",
                             schema::FormatFloat(idl), schema::FormatFloat(idr),
                             schema::FormatFloat(odl), schema::FormatFloat(odr)));
  }
  e.RequireZero("axial_force", "rubcont's element has no axial load");
  e.RequireZero("torque", "rubcont's element has no torque");
  e.RequireZero("alpha", "rubcont has no proportional damping of the shaft (flexible.modal_damping "
                         "damps the kept modes)");
  e.RequireZero("beta", "rubcont has no proportional damping of the shaft (flexible.modal_damping "
                        "damps the kept modes)");
  e.RequireFlag("shear_effects", true, "rubcont's element is Timoshenko's");
  e.RequireFlag("rotary_inertia", true, "rubcont's element has rotary inertia");
  e.RequireFlag("gyroscopic", true, "rubcont keeps the gyroscopic moments of every element "
                                    "(flexible.gyroscopic = \"off\" drops them all)");
  if (const toml::node* method = e.table().get("shear_method_calc")) {
    if (method->value<std::string>() != std::optional<std::string>("cowper"))
      e.Refuse("shear_method_calc", "must be \"cowper\": rubcont's shear coefficient is Cowper's");
  }
  const toml::table* material = e.table().get_as<toml::table>("material");
  if (material == nullptr) {
    e.Refuse("material", "must be a table {name, rho, E, G_s} (as Rotor.save writes it)");
  }
  const Element m(e.File(), e.header() + ".material", *material);
  ShaftRow row;
  ShaftElement& s = row.section;
  s.length = e.Number("L");
  s.outer_diameter = odl;
  s.inner_diameter = idl;
  s.density = m.Number("rho");
  s.youngs_modulus = m.Number("E");
  s.shear_modulus = m.Has("G_s") ? m.Number("G_s")
                                 : s.youngs_modulus / (2.0 * (1.0 + m.Number("Poisson")));
  row.elements = 1;
  return row;
}

SupportRow SupportRowOf(const Element& e, int nodes) {
  for (const std::string key : {"kxy", "kyx", "cxy", "cyx"})
    e.RequireZero(key, "cross-coupled: rubcont's supports are isotropic springs and dashpots");
  for (const std::string key : {"mxx", "myy", "mxy", "myx"})
    e.RequireZero(key, "bearing mass: rubcont's supports are springs and dashpots");
  if (e.Has("n_link")) e.Refuse("n_link", "links two nodes: rubcont's rotor supports go to ground");
  const double kxx = e.Number("kxx"), cxx = e.Number("cxx");
  const double kyy = e.Number("kyy", kxx), cyy = e.Number("cyy", cxx);
  if (kxx != kyy || cxx != cyy) {
    e.Refuse("", fmt::format("anisotropic (kxx = {}, kyy = {}, cxx = {}, cyy = {}): rubcont's "
                             "supports act alike in x and y",
                             schema::FormatFloat(kxx, true), schema::FormatFloat(kyy, true),
                             schema::FormatFloat(cxx, true), schema::FormatFloat(cyy, true)));
  }
  if (kxx < 0.0 || cxx < 0.0) e.Refuse("", "kxx and cxx must be ≥ 0");
  return {e.Node(nodes), kxx, cxx};
}

Disk DiskOf(const Element& e, const std::string& kind, int nodes) {
  if (kind == "PointMass") {
    const double mx = e.Number("mx", e.Has("m") ? std::optional<double>(e.Number("m")) : std::nullopt);
    const double my = e.Number("my", mx);
    if (mx != my) {
      e.Refuse("", fmt::format("anisotropic (mx = {}, my = {}): rubcont's masses act alike in x "
                               "and y", schema::FormatFloat(mx), schema::FormatFloat(my)));
    }
    return {e.Node(nodes), mx, 0.0, 0.0};
  }
  return {e.Node(nodes), e.Number("m"), e.Number("Id"), e.Number("Ip")};
}

}  // namespace

RossRotor ReadRossRotor(const std::filesystem::path& file) {
  toml::table root;
  try {
    root = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    throw std::invalid_argument(fmt::format("{}:{}:{}: {}", file.string(), where.line,
                                            where.column, e.description()));
  }
  RossRotor rotor;
  rotor.version = root["ross_version"].value_or(std::string("unknown"));
  // The elements by class; shafts first, since they number the nodes.
  std::vector<Element> shafts, others;
  for (auto&& [key, node] : root) {
    const std::string name(key.str());
    if (name == "ross_version" || name == "parameters" || name.rfind('_', 0) == 0) continue;
    const toml::table* table = node.as_table();
    if (table == nullptr) {
      throw std::invalid_argument(fmt::format("{}: {}: not an element table \"<Class>_<tag>\"",
                                              file.string(), name));
    }
    (name.rfind("ShaftElement_", 0) == 0 ? shafts : others)
        .emplace_back(file, schema::Quote(name), *table);
  }
  if (shafts.empty()) {
    throw std::invalid_argument(fmt::format("{}: no ShaftElement: not a ROSS rotor file "
                                            "(Rotor.save)", file.string()));
  }
  // ROSS numbers each element by its left node n; the shaft runs n = 0, 1, … without a gap.
  std::map<int, const Element*> by_node;
  for (const Element& e : shafts) {
    const double n = e.Number("n");
    if (n != std::floor(n) || n < 0 || n >= static_cast<double>(shafts.size()))
      e.Refuse("n", fmt::format("= {}: the {} shaft elements must be numbered 0 to {}", n,
                                shafts.size(), shafts.size() - 1));
    const auto [at, inserted] = by_node.emplace(static_cast<int>(n), &e);
    if (!inserted) {
      e.Refuse("n", fmt::format("= {}: [{}] starts at node {} too: rubcont's shaft is one line "
                                "of elements (no layered or parallel elements)",
                                n, at->second->header(), n));
    }
  }
  for (const auto& [n, e] : by_node) rotor.shaft.push_back(ShaftRowOf(*e));
  const int nodes = static_cast<int>(shafts.size()) + 1;
  for (const Element& e : others) {
    const std::string kind = e.header().substr(1, e.header().find('_') - 1);  // "Class_tag"
    if (kind == "DiskElement" || kind == "PointMass") {
      rotor.disks.push_back(DiskOf(e, kind, nodes));
    } else if (kind == "BearingElement" || kind == "SealElement") {
      rotor.supports.push_back(SupportRowOf(e, nodes));
    } else {
      e.Refuse("", fmt::format("class {}: not one rubcont reads (ShaftElement, DiskElement, "
                               "PointMass, BearingElement, SealElement): its coefficients are not "
                               "in the file", kind));
    }
  }
  std::stable_sort(rotor.disks.begin(), rotor.disks.end(),
                   [](const Disk& a, const Disk& b) { return a.node < b.node; });
  std::stable_sort(rotor.supports.begin(), rotor.supports.end(),
                   [](const SupportRow& a, const SupportRow& b) { return a.station < b.station; });
  return rotor;
}

int ImportRossCommand(const ImportRossRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    const RossRotor rotor = ReadRossRotor(request.ross_file);
    Scene scene = LoadScene(request.base_scene);
    if (scene.model != ModelKind::kTwoPoint) {
      throw std::invalid_argument(fmt::format("--base {}: model \"{}\": must be a two_point scene "
                                              "(its stator, contacts and analysis are kept)",
                                              request.base_scene, ToString(scene.model)));
    }
    FlexibleSettings& f = scene.flexible;
    if (f.matrices.enabled) {
      throw std::invalid_argument(fmt::format("--base {}: has [flexible.matrices], which gives the "
                                              "whole structure: a listed rotor cannot replace "
                                              "its rotor", request.base_scene));
    }
    f.enabled = true;
    f.rotor_shaft = rotor.shaft;
    f.rotor_disks = rotor.disks;
    f.rotor_supports = rotor.supports;
    f.rotor_contact_stations = request.contact_stations;
    const int nodes = static_cast<int>(rotor.shaft.size()) + 1;
    if (!(request.contact_stations[0] >= 0 && request.contact_stations[0] < request.contact_stations[1] &&
          request.contact_stations[1] < nodes)) {
      throw std::invalid_argument(fmt::format(
          "--contact-stations {} {}: must be ROSS nodes 0 ≤ left < right ≤ {} (the rotor's last)",
          request.contact_stations[0], request.contact_stations[1], nodes - 1));
    }
    // The rigid data the rows give, as the loader would supply them.
    const RigidBodyData d = RigidBodyOf(
        ListedBody("rotor", f.rotor_shaft, f.rotor_disks, f.rotor_contact_stations));
    TwoPointParams& p = scene.two_point;
    p.rotor_mass = d.mass;
    p.rotor_inertia = d.inertia;
    p.contact_span = d.span;
    p.rotor_mass_center = d.mass_center;
    const ModelEntry& model = ModelOf(scene);
    std::vector<Stage>& stages = scene.analysis.stages;
    const bool drop_analytic = model.analytic_skipped && !model.analytic_skipped(scene).empty() &&
                               schema::RunsStage(scene, Stage::kAnalytic);
    if (drop_analytic) stages.erase(std::find(stages.begin(), stages.end(), Stage::kAnalytic));
    scene.source = request.ross_file + " on " + request.base_scene;
    const std::filesystem::path target =
        request.out_file ? std::filesystem::path(*request.out_file) : std::filesystem::path();
    scene.name = request.out_file ? target.stem().string()
                                  : std::filesystem::path(request.ross_file).stem().string();
    scene.description = fmt::format("{} (ROSS {}) on {}", request.ross_file, rotor.version,
                                    scene.description.empty() ? request.base_scene : scene.description);
    std::string text = fmt::format(
        "# The ROSS rotor {} (ross_version {}) on the stator, contacts and analysis of {}, by\n"
        "# rubcont scene import-ross: {} shaft elements as [[flexible.rotor_shaft]] rows, {} disks "
        "and point masses as\n# [[flexible.rotor_disks]], {} bearings and seals as "
        "[[flexible.rotor_supports]]; the contacts at ROSS nodes {} and {}.\n",
        request.ross_file, rotor.version, request.base_scene, rotor.shaft.size(),
        rotor.disks.size(), rotor.supports.size(), request.contact_stations[0],
        request.contact_stations[1]);
    if (drop_analytic)
      text += "# Stage \"analytic\" left out: " + model.analytic_skipped(scene) + ".\n";
    text += ResolvedSceneToml(scene);
    // The scene must load as it is written: every rule of the schema, the rows' rigid data.
    ParseScene(text, request.out_file ? *request.out_file : "the imported scene", scene.name);
    if (request.out_file) {
      PrepareToWrite(target);
      WriteFileAtomically(target, text);
      fmt::print(err, "rubcont: wrote {} ({} shaft elements, {} disks, {} supports)\n",
                 target.string(), rotor.shaft.size(), rotor.disks.size(), rotor.supports.size());
    } else {
      out << text;
    }
    return kExitSuccess;
  });
}

}  // namespace rubcont
