#include "apps/dataset_description.h"
#include "apps/hdf5_file.h"
#include "solvers/constants.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <H5Cpp.h>
#include <catch2/catch.hpp>
#include <hdf5_hl.h>

#include "cli_support.h"
#include "describe_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;
using Kind = DatasetDescription::Kind;
using testing::CreationOrder;
using testing::FlagValues;
using testing::ScaleOf;
using testing::StringAttribute;

TEST_CASE("Dataset descriptions: units by name, codes of the flags", "[hdf5][describe]") {
  CHECK(DescribeDataset("/branches/branch2/speed_rpm").unit == "rpm");
  CHECK(DescribeDataset("/branches/branch2/precession_hz").unit == "Hz");
  CHECK(DescribeDataset("/branches/branch2/normal_force_left").unit == "N");
  CHECK(DescribeDataset("/sweeps/up/slip_velocity_max_right").unit == "m/s");
  CHECK(DescribeDataset("/sweeps/up/penetration_max_contact").unit == "m");
  CHECK(DescribeDataset("/sweeps/up/simulated_time").unit == "s");
  CHECK(DescribeDataset("/branches/branch1/leading_growth_rate").unit == "1/s");
  CHECK(DescribeDataset("/branches/branch1/normal_phase_deg").unit == "degree");
  CHECK(DescribeDataset("/branches/branch1/mu_ratio_left").kind == Kind::kDimensionless);
  CHECK(DescribeDataset("/maps/friction/eta").kind == Kind::kContext);
  // "period": seconds for the rub's orbits, the model's own time for a textbook model.
  CHECK(DescribeDataset("/orbits/whip1/period").unit == "s");
  CHECK(DescribeDataset("/branches/periodic_orbits/duffing/period").kind == Kind::kDimensionless);

  const DatasetDescription mode = DescribeDataset("/branches/branch3/mode_right");
  CHECK(mode.kind == Kind::kFlag);
  CHECK(mode.flag_values == std::vector<int>{0, 1, 2, 3});
  CHECK(mode.flag_meanings == "free stick slip+ slip-");
  const DatasetDescription stable = DescribeDataset("/branches/branch3/stable");
  CHECK(stable.flag_values == std::vector<int>{-1, 0, 1});
  CHECK(stable.flag_meanings == "not_computed unstable stable");
  CHECK(DescribeDataset("/ensemble/regime_left").flag_meanings ==
        "unknown no_contact intermittent whirl whip");

  CHECK(DescribeDataset("/branches/branch1/no_such_measure").kind == Kind::kUnknown);
  CHECK(DesignParameterUnits(DesignParameter::kFriction) == "1");
  CHECK(DesignParameterUnits(DesignParameter::kCenterDamping) == "N s/m");
  CHECK(DesignParameterUnits(DesignParameter::kSupportStiffness) == "N/m");
}

// Every dataset of every committed result file (results/**/*.h5, read from the repository root)
// has a description, and every value of a committed flag is one of its codes: a dataset added to
// a writer without a line in the table, or a code the table does not know, fails here.
TEST_CASE("Dataset descriptions: every committed result's datasets are described, its flags' "
          "values among their codes", "[hdf5][describe]") {
  std::set<std::string> unknown, bad_codes;
  int files = 0, datasets = 0, flags = 0;
  for (const auto& entry : fs::recursive_directory_iterator("results")) {
    if (entry.path().extension() != ".h5") continue;
    ++files;
    const H5::H5File file(entry.path().string(), H5F_ACC_RDONLY);
    struct Walk {
      const H5::H5File* file;
      std::string name;
      std::set<std::string>* unknown;
      std::set<std::string>* bad_codes;
      int* datasets;
      int* flags;
    } walk{&file, entry.path().string(), &unknown, &bad_codes, &datasets, &flags};
    auto visit = [](hid_t, const char* name, const H5O_info_t* info, void* data) -> herr_t {
      auto& w = *static_cast<Walk*>(data);
      if (info->type != H5O_TYPE_DATASET) return 0;
      ++*w.datasets;
      const std::string path = std::string("/") + name;
      const DatasetDescription d = DescribeDataset(path);
      if (d.kind == Kind::kUnknown) w.unknown->insert(path + " (" + w.name + ")");
      const H5::DataSet set = w.file->openDataSet(path);
      const H5T_class_t type = set.getTypeClass();
      if (d.kind != Kind::kFlag || (type != H5T_INTEGER && type != H5T_FLOAT)) return 0;
      ++*w.flags;
      std::vector<double> values(static_cast<std::size_t>(set.getSpace().getSimpleExtentNpoints()));
      if (!values.empty()) set.read(values.data(), H5::PredType::NATIVE_DOUBLE);
      for (double v : values) {
        if (std::isnan(v)) continue;
        if (std::find(d.flag_values.begin(), d.flag_values.end(), v) == d.flag_values.end()) {
          w.bad_codes->insert(path + " holds " + std::to_string(v) + " (" + w.name + ")");
        }
      }
      return 0;
    };
    H5Ovisit(file.getId(), H5_INDEX_NAME, H5_ITER_INC, visit, &walk);
  }
  INFO(files << " files, " << datasets << " datasets, " << flags << " numeric flags");
  CHECK(files > 20);
  for (const std::string& u : unknown) UNSCOPED_INFO("not described: " << u);
  CHECK(unknown.empty());
  for (const std::string& b : bad_codes) UNSCOPED_INFO("not a code: " << b);
  CHECK(bad_codes.empty());
}

TEST_CASE("A result file describes itself: units, flags, dimension scales, creation order",
          "[hdf5][describe]") {
  TempDir dir;
  const fs::path path = dir.path / "described.h5";
  {
    ResultWriter writer(path);
    for (int b = 1; b <= 10; ++b) {  // text order would be branch1, branch10, branch2, …
      const std::string g = "/branches/branch" + std::to_string(b);
      writer.CreateGroup(g);
      writer.WriteDoubles(g + "/speed_rpm", std::vector<double>{40.0, 50.0, 60.0, 70.0});
      writer.SetDimensionScales(g, "speed_rpm");
      writer.WriteInts(g + "/stable", {1, 1, 0, -1});
      writer.WriteInts(g + "/mode_left", {0, 1, 2, 3});
      writer.WriteDoubles(g + "/normal_force_left", std::vector<double>{0.0, 1.0, 2.0, 3.0});
      writer.WriteStrings(g + "/piece", {"a", "b", "c", "d"});
      writer.WriteDoubles(g + "/speed_range_rpm", std::vector<double>{40.0, 70.0});  // not 4 long
      writer.WriteMatrix(g + "/multipliers_real", Matrix::Zero(4, 2));  // no second axis named
    }
    // A sweep whose spectra have as many bins as speeds: the frequencies label axis 1 and are not
    // labelled by the speeds themselves.
    const std::string s = "/sweeps/up";
    writer.WriteDoubles(s + "/speed_rpm", std::vector<double>{40.0, 44.0, 48.0});
    writer.SetDimensionScales(s, "speed_rpm");
    Matrix spectrum(3, 3);
    spectrum << 1, 2, 3, 4, 5, 6, 7, 8, 9;
    writer.WriteMatrix(s + "/spectrum_magnitude_left", spectrum);
    writer.NameSecondAxis(s + "/spectrum_magnitude_left", "spectrum_frequency_hz");
    writer.WriteDoubles(s + "/spectrum_frequency_hz", std::vector<double>{-10.0, 0.0, 10.0});
    writer.WriteDoubles(s + "/wall_seconds", std::vector<double>{0.1, 0.2, 0.3});
    writer.WriteDoubles("/maps/friction/eta", std::vector<double>{0.3, 0.4});
    writer.SetUnits("/maps/friction/eta", DesignParameterUnits(DesignParameter::kFriction));
    CHECK_THROWS_AS(writer.SetUnits("/maps/friction/eta", ""), std::invalid_argument);
    writer.Commit();
  }
  const H5::H5File file(path.string(), H5F_ACC_RDONLY);
  std::vector<std::string> order;
  for (int b = 1; b <= 10; ++b) order.push_back("branch" + std::to_string(b));
  CHECK(CreationOrder(file, "/branches") == order);
  CHECK(CreationOrder(file, "/") == std::vector<std::string>{"branches", "sweeps", "maps"});

  const std::string g = "/branches/branch10";
  CHECK(StringAttribute(file.openDataSet(g + "/speed_rpm"), "units") == "rpm");
  CHECK(StringAttribute(file.openDataSet(g + "/normal_force_left"), "units") == "N");
  CHECK(StringAttribute(file.openDataSet(g + "/piece"), "units") == "<none>");  // text
  const H5::DataSet mode = file.openDataSet(g + "/mode_left");
  CHECK(StringAttribute(mode, "units") == "1");
  CHECK(FlagValues(mode) == std::vector<double>{0, 1, 2, 3});
  CHECK(StringAttribute(mode, "flag_meanings") == "free stick slip+ slip-");
  CHECK(mode.openAttribute("flag_values").getTypeClass() == H5T_INTEGER);  // the data's type
  CHECK(StringAttribute(file.openDataSet(g + "/stable"), "flag_meanings") ==
        "not_computed unstable stable");

  CHECK(H5DSis_scale(file.openDataSet(g + "/speed_rpm").getId()) > 0);
  for (const char* name : {"stable", "mode_left", "normal_force_left", "piece"}) {
    CHECK(ScaleOf(file, g + "/" + name, 0) == "speed_rpm");
  }
  CHECK(ScaleOf(file, g + "/speed_range_rpm", 0).empty());
  // Labelled on both axes or on none: h5netcdf refuses a half-labelled variable.
  CHECK(ScaleOf(file, g + "/multipliers_real", 0).empty());
  CHECK(ScaleOf(file, g + "/multipliers_real", 1).empty());

  const std::string s = "/sweeps/up";
  CHECK(ScaleOf(file, s + "/spectrum_magnitude_left", 0) == "speed_rpm");
  CHECK(ScaleOf(file, s + "/spectrum_magnitude_left", 1) == "spectrum_frequency_hz");
  CHECK(H5DSis_scale(file.openDataSet(s + "/spectrum_frequency_hz").getId()) > 0);
  CHECK(ScaleOf(file, s + "/spectrum_frequency_hz", 0).empty());
  CHECK(ScaleOf(file, s + "/wall_seconds", 0) == "speed_rpm");
  CHECK(StringAttribute(file.openDataSet(s + "/wall_seconds"), "units") == "s");
  CHECK(StringAttribute(file.openDataSet("/maps/friction/eta"), "units") == "1");
}

// The real writers, through `rubcont run` on case A(a) (< 1 s: closed form and branches).
TEST_CASE("CLI: a run's file describes its branches (units, mode flags, speed as the dimension)",
          "[cli][describe]") {
  TempDir dir;
  const auto run =
      testing::RubcontNoPython("run scenes/thesis_A_a.toml --out " + dir.path.string() + " --quiet");
  REQUIRE(run.exit_code == 0);
  const H5::H5File file((dir.path / "thesis_A_a" / "thesis_A_a.h5").string(), H5F_ACC_RDONLY);
  const std::vector<std::string> branches = CreationOrder(file, "/branches");
  REQUIRE(branches.size() >= 3);
  CHECK(branches[0] == "speed_range_rpm");
  CHECK(branches[1] == "branch1");
  CHECK(branches[2] == "branch2");
  const std::string g = "/branches/branch1";
  CHECK(StringAttribute(file.openDataSet(g + "/speed_rpm"), "units") == "rpm");
  CHECK(StringAttribute(file.openDataSet(g + "/precession_hz"), "units") == "Hz");
  CHECK(StringAttribute(file.openDataSet(g + "/mode_left"), "flag_meanings") ==
        "free stick slip+ slip-");
  CHECK(ScaleOf(file, g + "/precession_hz", 0) == "speed_rpm");
  CHECK(ScaleOf(file, g + "/mode_left", 0) == "speed_rpm");
  CHECK(ScaleOf(file, g + "/special_points/frequency_hz", 0) == "speed_rpm");
  CHECK(ScaleOf(file, "/analytic/mode1/normal_force_left", 0) == "precession_hz");
  // Every numeric dataset of the file carries units.
  std::vector<std::string> without;
  auto visit = [](hid_t object, const char* name, const H5O_info_t* info, void* data) -> herr_t {
    if (info->type != H5O_TYPE_DATASET) return 0;
    const hid_t set = H5Dopen2(object, name, H5P_DEFAULT);
    const hid_t type = H5Dget_type(set);
    if (H5Tget_class(type) != H5T_STRING && H5Aexists(set, "units") <= 0) {
      static_cast<std::vector<std::string>*>(data)->push_back(name);
    }
    H5Tclose(type);
    H5Dclose(set);
    return 0;
  };
  H5Ovisit(file.getId(), H5_INDEX_NAME, H5_ITER_INC, visit, &without);
  for (const std::string& w : without) UNSCOPED_INFO("no units: " << w);
  CHECK(without.empty());
}

}  // namespace
}  // namespace rubcont
