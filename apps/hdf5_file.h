// Result files (HDF5): a small writer with atomic commit, and a reader.
//
// ResultWriter builds the file in memory (HDF5's core driver) and Commit() writes it with
// WriteFileAtomically (apps/atomic_file.h): a temporary name unique to the process, fsync, rename
// onto the target. So HDF5 never writes to the disk itself (a full disk used to fail inside
// H5Fclose, and the half-closed file crashed the process when it was closed again), every I/O error
// is one line with the file and the system's reason, two writers of one target never share a
// temporary, and a writer destroyed without Commit() — an exception, an early return — leaves the
// disk as it was: a crash never leaves a half-written result under the target name.
// The writer's memory is the file's size (the largest committed result: under 5 MB).
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
// Errors (HDF5 failures, I/O) throw std::runtime_error naming the file and the object or the
// system's reason ("cannot read a.h5: No such file or directory", "cannot read a.h5: unable to lock
// file, errno = 11, ..." when another process writes it with HDF5 file locking).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "solvers/types.h"

namespace rubcont {

class ResultWriter {
 public:
  // Checks that the target can be written (its directory exists and takes a new file, the target
  // is not a directory; throws otherwise, so a long run fails before its work) and removes the
  // temporaries of the target that killed runs left (RemoveStaleTemporaries).
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

  // Writes the file onto the target (atomically). After it, no more writes. On an I/O error it
  // throws and the target is as it was.
  void Commit();

  const std::filesystem::path& target() const { return target_; }
  // The temporaries of the target that runs killed while writing left behind, removed when this
  // writer was made (the caller says so).
  const std::vector<std::filesystem::path>& removed_leftovers() const { return removed_leftovers_; }

 private:
  struct Impl;
  std::filesystem::path target_;
  std::vector<std::filesystem::path> removed_leftovers_;
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
  std::vector<double> ReadDoublesAttribute(const std::string& object,
                                           const std::string& name) const;  // 1-D
  std::string ReadStringAttribute(const std::string& object, const std::string& name) const;

 private:
  struct Impl;
  std::filesystem::path file_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rubcont
