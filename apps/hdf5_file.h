// Result files (HDF5): a small writer with atomic commit, and a reader.
//
// ResultWriter writes `<target>.tmp` next to the target; Commit() closes it and renames it onto the
// target (atomic on one file system). If the writer is destroyed without Commit() — an exception,
// an early return — the temporary is deleted and the target is left as it was: a crash never
// leaves a half-written result under the target name.
//
// Paths are absolute HDF5 paths ("/analytic/mode1/precession_hz"); missing parent groups are
// created. Datasets: double 1-D / 2-D (row-major on disk, as h5py and MATLAB expect), int 1-D,
// variable-length UTF-8 string 1-D. Attributes: double or string scalars, or 1-D double lists (may
// be empty), on any group or dataset.
// Object modification times are not recorded, so equal content gives equal bytes.
//
// The file describes itself (apps/dataset_description.h): each numeric dataset gets, when it is
// written, the `units` attribute of its name ("1" for a dimensionless number or a code), and a
// coded integer `flag_values` / `flag_meanings` too; groups keep their links in creation order
// (h5py lists branch1, branch2, …, branch10 as written, not sorted as text); and groups declared
// with SetDimensionScales get HDF5 dimension scales at Commit, so that xarray (engine
// "h5netcdf") opens them with, e.g., speed_rpm as the coordinate.
//
// Errors (HDF5 failures, I/O) throw std::runtime_error naming the file and the object.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "solvers/types.h"

namespace rubcont {

class ResultWriter {
 public:
  // Creates (truncates) `<target>.tmp`. The parent directory must exist.
  explicit ResultWriter(std::filesystem::path target);
  ~ResultWriter();
  ResultWriter(const ResultWriter&) = delete;
  ResultWriter& operator=(const ResultWriter&) = delete;

  void CreateGroup(const std::string& path);
  void WriteDoubles(const std::string& path, const std::vector<double>& values);
  void WriteDoubles(const std::string& path, const Vector& values);
  void WriteMatrix(const std::string& path, const Matrix& values);  // rows × cols
  void WriteInts(const std::string& path, const std::vector<int>& values);
  void WriteStrings(const std::string& path, const std::vector<std::string>& values);
  void SetAttribute(const std::string& object, const std::string& name, double value);
  void SetAttribute(const std::string& object, const std::string& name, const std::string& value);
  void SetAttribute(const std::string& object, const std::string& name,
                    const std::vector<double>& values);  // a 1-D attribute
  void SetAttribute(const std::string& object, const std::string& name, const char* value) {
    SetAttribute(object, name, std::string(value));
  }
  // The `units` of a dataset whose unit depends on the run (DatasetDescription::kContext: a map's
  // η), replacing any. `units` must not be empty.
  void SetUnits(const std::string& dataset, const std::string& units);

  // At Commit, `<group>/<scale>` (a 1-D dataset) becomes a dimension scale and labels axis 0 of
  // every dataset of `group` (not of its subgroups) whose axis 0 has its length, the datasets
  // written after this call too. Axis 1 of a 2-D dataset is labelled by the 1-D dataset of the
  // same group that NameSecondAxis named for it (its name relative to the group), when its length
  // fits; otherwise neither axis is labelled (netCDF readers refuse a half-labelled variable;
  // xarray opens such a group with phony_dims="sort").
  void SetDimensionScales(const std::string& group, const std::string& scale);
  void NameSecondAxis(const std::string& dataset, const std::string& dimension);

  // Closes the file and renames the temporary onto the target. After it, no more writes.
  void Commit();

  const std::filesystem::path& target() const { return target_; }
  // Whether `<target>.tmp` existed when this writer was made (left by a run that was killed before
  // it committed): it is truncated and written anew, and the caller says so.
  bool replaces_leftover() const { return replaces_leftover_; }
  const std::filesystem::path& temporary() const { return temporary_; }

 private:
  struct Impl;
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  bool replaces_leftover_ = false;
  std::unique_ptr<Impl> impl_;
};

class ResultReader {
 public:
  explicit ResultReader(const std::filesystem::path& file);
  ~ResultReader();
  ResultReader(const ResultReader&) = delete;
  ResultReader& operator=(const ResultReader&) = delete;

  bool Exists(const std::string& path) const;  // group or dataset
  std::vector<std::string> Children(const std::string& group) const;  // names, sorted
  std::vector<double> ReadDoubles(const std::string& path) const;     // 1-D
  Matrix ReadMatrix(const std::string& path) const;                   // 2-D
  std::vector<int> ReadInts(const std::string& path) const;
  std::vector<std::string> ReadStrings(const std::string& path) const;
  bool HasAttribute(const std::string& object, const std::string& name) const;
  double ReadDoubleAttribute(const std::string& object, const std::string& name) const;
  std::string ReadStringAttribute(const std::string& object, const std::string& name) const;

 private:
  struct Impl;
  std::filesystem::path file_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rubcont
