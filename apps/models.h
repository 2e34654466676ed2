// The model dispatch: every model a scene can hold, one entry each. This is the one place in
// apps/ that asks which model a scene holds; the scene loader, the stages, `rubcont scene check`
// and the map / fit commands read the entry.
//
// Adding a model (docs/architecture.md, "Where to change what"): (1) its Params and vector field in
// models/; (2) its ModelKind and its parameter struct as a field of Scene (apps/scene.h) and its
// section's keys in the schema (apps/scene_schema.cpp); (3) one entry in Models() (apps/models.cpp)
// saying which sections and stages it has and what each stage runs.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "apps/hdf5_file.h"
#include "apps/scene.h"
#include "models/flexible.h"
#include "models/rub_model.h"

namespace rubcont {

// Where a stage writes: the result file, progress lines (stderr unless --quiet), the summary on
// `out`, and one line per numerical failure.
struct StageContext {
  ResultWriter& writer;
  std::function<void(const std::string&)> progress;
  std::ostream& out;
  std::vector<std::string>& failures;
};
using StageRunner = std::function<void(const Scene&, StageContext&)>;

struct ModelEntry {
  ModelKind kind = ModelKind::kTwoPoint;
  std::string name;                    // the scene's `model = "<name>"`
  std::vector<Stage> stages;           // the stages it has: analysis.stages may list these only
  std::vector<Stage> default_stages;   // what a scene without analysis.stages runs
  // The scene sections it reads besides every model's (the top level and [analysis] itself), each
  // with its sub-tables: its own ([rotor], [jeffcott], [duffing], …, and [flexible] with its
  // [[table arrays]] for model two_point) and its stages' ([analysis.sweep], [analysis.orbits],
  // [analysis.tori]). The loader rejects the keys of any other section.
  std::vector<std::string> sections;
  // A rub model (contacts): the structure its rotating waves and sweeps integrate, and the
  // friction law of its rotating waves. Empty for the others.
  std::function<RubStructure(const Scene&)> structure;
  std::function<FrictionLawKind(const Scene&)> wave_friction;
  StageRunner analytic;                // stage "analytic" (L0), when it has it
  // Why the closed form of stage "analytic" does not describe this scene ("" when it does): the
  // stage is then not run, and says why.
  std::function<std::string(const Scene&)> analytic_skipped;
  StageRunner orbits;                  // stage "orbits" (L2), when it has it
  std::string orbits_figure;           // the module of rubcont.plots drawing its orbits stage
  // A textbook model: its continuation parameter, of the keys <model>.<parameter>_range and
  // <model>.orbits.start.
  std::string parameter;
  // `rubcont scene check`: quantities derived from the parameters ("" for none).
  std::function<std::string(const Scene&)> derived;
  bool Has(Stage stage) const;
  // Whether `section` (dotted, "" the top level) is one of its sections or a sub-table of one.
  bool HasSection(const std::string& section) const;
  bool IsRub() const { return static_cast<bool>(structure); }
};

// Every model, in the order the documentation lists them.
const std::vector<ModelEntry>& Models();
// The entry of a model; of the model a scene holds.
const ModelEntry& ModelOf(ModelKind kind);
const ModelEntry& ModelOf(const Scene& scene);
// The names of the models that have `stage`, quoted and comma-separated (for messages).
std::string ModelsWith(Stage stage);

// Model two_point's [flexible] section as the library's flexible model (models/flexible.h): of
// uniform or listed shafts (FlexibleModelOf), or of [flexible.matrices] (MatrixModelOf); either as
// full matrices with their contact coordinates (FlexibleMatricesOf: what `rubcont scene matrices`
// writes), built and reduced (FlexibleRubOf). The scene loader has checked that it builds.
FlexibleRubModel FlexibleModelOf(const Scene& scene);
MatrixRubModel MatrixModelOf(const Scene& scene);
MatrixRubModel FlexibleMatricesOf(const Scene& scene);
FlexibleRub FlexibleRubOf(const Scene& scene);
// A listed body's shaft: the rows' segments cut into their elements, the disks on their stations,
// the contacts at `contact_stations` (a right one < 0: the last station).
BodyShaft ListedBody(const std::string& name, const std::vector<ShaftRow>& rows,
                     const std::vector<Disk>& disks, const std::array<int, 2>& contact_stations);

}  // namespace rubcont
