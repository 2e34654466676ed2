#include "apps/hdf5_file.h"

#include <algorithm>
#include <map>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <unistd.h>

#include <H5Cpp.h>
#include <hdf5_hl.h>

#include "apps/dataset_description.h"

#include "apps/atomic_file.h"

namespace rubcont {
namespace {

// HDF5's C++ exceptions do not derive from std::exception; translate them at every entry point.
template <class Function>
auto Guard(const std::filesystem::path& file, const std::string& what, Function&& function) {
  try {
    return function();
  } catch (const H5::Exception& e) {
    throw std::runtime_error("HDF5: " + file.string() + ": " + what + ": " + e.getCDetailMsg() +
                             " (" + e.getCFuncName() + ")");
  }
}

// The innermost description on HDF5's error stack of this thread (the system's reason, when there
// is one: "unable to lock file, errno = 11, ..."), or "" when the stack is empty.
std::string InnermostHdf5Error() {
  std::string innermost;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD,
           [](unsigned n, const H5E_error2_t* error, void* data) -> herr_t {
             if (n == 0 && error->desc != nullptr) *static_cast<std::string*>(data) = error->desc;
             return 0;
           },
           &innermost);
  return innermost;
}

void CheckAbsolute(const std::string& path) {
  if (path.empty() || path[0] != '/' || (path.size() > 1 && path.back() == '/'))
    throw std::invalid_argument("HDF5 path \"" + path + "\": must be absolute, e.g. \"/analytic/mode1\"");
}

std::string ParentPath(const std::string& path) {
  const auto slash = path.rfind('/');
  return slash == 0 ? std::string("/") : path.substr(0, slash);
}

// Calls f(H5::H5Object&) on the group or dataset at `path` (attributes hang on either).
template <class Function>
auto WithObject(const H5::H5File& file, const std::string& path, Function&& f) {
  if (path == "/" || file.childObjType(path) == H5O_TYPE_GROUP) {
    H5::Group group = file.openGroup(path);
    return f(static_cast<H5::H5Object&>(group));
  }
  if (file.childObjType(path) == H5O_TYPE_DATASET) {
    H5::DataSet set = file.openDataSet(path);
    return f(static_cast<H5::H5Object&>(set));
  }
  throw std::runtime_error(path + " is not a group or a dataset");
}

const H5::StrType& Utf8String() {
  static const H5::StrType type = [] {
    H5::StrType t(H5::PredType::C_S1, H5T_VARIABLE);
    t.setCset(H5T_CSET_UTF8);
    return t;
  }();
  return type;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

struct ResultWriter::Impl {
  H5::H5File file;
  bool open = true;
  std::map<std::string, std::string> scales;        // group → its axis-0 dimension scale
  std::map<std::string, std::string> second_axes;   // dataset → the dimension of its axis 1

  // Creation property lists that do not record modification times.
  static H5::DSetCreatPropList DatasetProperties() {
    H5::DSetCreatPropList properties;
    H5Pset_obj_track_times(properties.getId(), false);
    return properties;
  }
  // The root group's links in creation order, as every other group's (EnsureGroup).
  static H5::FileCreatPropList FileProperties() {
    H5::FileCreatPropList properties;
    H5Pset_link_creation_order(properties.getId(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
    return properties;
  }

  bool Exists(const std::string& path) const {
    if (path == "/") return true;
    std::string prefix;
    for (std::size_t start = 1; start <= path.size();) {
      const std::size_t slash = std::min(path.find('/', start), path.size());
      prefix = path.substr(0, slash);
      if (H5Lexists(file.getId(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
      start = slash + 1;
    }
    return true;
  }

  void EnsureGroup(const std::string& path) {
    if (path == "/" || Exists(path)) return;
    EnsureGroup(ParentPath(path));
    const hid_t gcpl = H5Pcreate(H5P_GROUP_CREATE);
    H5Pset_obj_track_times(gcpl, false);
    H5Pset_link_creation_order(gcpl, H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
    const hid_t group = H5Gcreate2(file.getId(), path.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT);
    H5Pclose(gcpl);
    if (group < 0) throw std::runtime_error("cannot create group " + path);
    H5Gclose(group);
  }

  H5::DataSet CreateDataset(const std::string& path, const H5::DataType& type,
                            const std::vector<hsize_t>& dims) {
    CheckAbsolute(path);
    EnsureGroup(ParentPath(path));
    if (Exists(path)) throw std::runtime_error(path + " already exists");
    const H5::DataSpace space(static_cast<int>(dims.size()), dims.data());
    return file.createDataSet(path, type, space, DatasetProperties());
  }

  // The dataset's description by its name (apps/dataset_description.h): `units` ("1" for a
  // dimensionless number or a code), and flag_values (of the dataset's own type: int or double)
  // and flag_meanings for a coded integer. A unit that depends on the run (kContext) is the
  // caller's (SetUnits).
  void Describe(H5::DataSet& set, const std::string& path, bool integers) {
    const DatasetDescription d = DescribeDataset(path);
    if (d.kind == DatasetDescription::Kind::kUnit) WriteUnits(set, d.unit);
    if (d.kind == DatasetDescription::Kind::kDimensionless) WriteUnits(set, "1");
    if (d.kind != DatasetDescription::Kind::kFlag) return;
    WriteUnits(set, "1");
    const hsize_t n = d.flag_values.size();
    if (integers) {
      set.createAttribute("flag_values", H5::PredType::NATIVE_INT, H5::DataSpace(1, &n))
          .write(H5::PredType::NATIVE_INT, d.flag_values.data());
    } else {
      const std::vector<double> values(d.flag_values.begin(), d.flag_values.end());
      set.createAttribute("flag_values", H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, &n))
          .write(H5::PredType::NATIVE_DOUBLE, values.data());
    }
    set.createAttribute("flag_meanings", Utf8String(), H5::DataSpace(H5S_SCALAR))
        .write(Utf8String(), d.flag_meanings);
  }

  static void WriteUnits(H5::DataSet& set, const std::string& units) {
    if (set.attrExists("units")) set.removeAttr("units");
    set.createAttribute("units", Utf8String(), H5::DataSpace(H5S_SCALAR))
        .write(Utf8String(), units);
  }

  // The dimensions of `path` (a dataset).
  std::vector<hsize_t> Extent(const std::string& path) const {
    const H5::DataSpace space = file.openDataSet(path).getSpace();
    std::vector<hsize_t> dims(static_cast<std::size_t>(space.getSimpleExtentNdims()));
    space.getSimpleExtentDims(dims.data());
    return dims;
  }

  // `path` made a dimension scale (named by its last component) if it is a 1-D dataset of
  // `length`; else "" (the axis stays unlabelled: no dataset is invented for it).
  std::string Scale(const std::string& path, hsize_t length) {
    if (!Exists(path) || Extent(path) != std::vector<hsize_t>{length}) return "";
    H5::DataSet set = file.openDataSet(path);
    const std::string name = path.substr(path.rfind('/') + 1);
    if (H5DSis_scale(set.getId()) <= 0 && H5DSset_scale(set.getId(), name.c_str()) < 0) {
      throw std::runtime_error("cannot make " + path + " a dimension scale");
    }
    return path;
  }

  // Every dataset of `group` labelled by `scale` along axis 0 and its second dimension along
  // axis 1 (SetDimensionScales). The named second dimensions become scales first, so that a 1-D
  // one of the same length as the group's scale is not labelled by it.
  void AttachScales(const std::string& group, const std::string& scale) {
    const std::string scale_path = group + "/" + scale;
    if (!Exists(scale_path)) return;
    const std::vector<hsize_t> scale_extent = Extent(scale_path);
    if (scale_extent.size() != 1) throw std::runtime_error(scale_path + " is not 1-D: no scale");
    Scale(scale_path, scale_extent[0]);
    std::vector<std::string> datasets;
    {
      const H5::Group g = file.openGroup(group);
      for (hsize_t i = 0; i < g.getNumObjs(); ++i) {
        if (g.getObjTypeByIdx(i) != H5G_DATASET) continue;
        datasets.push_back(group + "/" + g.getObjnameByIdx(i));
      }
    }
    std::map<std::string, std::string> second;  // dataset → its axis-1 scale ("" for none)
    for (const std::string& path : datasets) {
      const std::vector<hsize_t> extent = Extent(path);
      const auto named = second_axes.find(path);
      if (extent.size() == 2 && named != second_axes.end()) {
        second[path] = Scale(group + "/" + named->second, extent[1]);
      }
    }
    for (const std::string& path : datasets) {
      const std::vector<hsize_t> extent = Extent(path);
      if (extent.empty() || extent.size() > 2 || extent[0] != scale_extent[0]) continue;
      // A 2-D dataset is labelled on both axes or on none: netCDF readers (h5netcdf) refuse a
      // variable with one axis labelled and the other not.
      if (extent.size() == 2 && second[path].empty()) continue;
      H5::DataSet set = file.openDataSet(path);
      if (H5DSis_scale(set.getId()) > 0) continue;
      Attach(set, path, scale_path, 0);
      if (extent.size() == 2) Attach(set, path, second[path], 1);
    }
  }

  void Attach(const H5::DataSet& set, const std::string& path, const std::string& scale_path,
              unsigned axis) {
    const H5::DataSet scale_set = file.openDataSet(scale_path);
    if (H5DSattach_scale(set.getId(), scale_set.getId(), axis) < 0) {
      throw std::runtime_error("cannot attach " + scale_path + " to " + path);
    }
  }
};

ResultWriter::ResultWriter(std::filesystem::path target) : target_(std::move(target)) {
  H5::Exception::dontPrint();
  CheckWritable(target_);
  removed_leftovers_ = RemoveStaleTemporaries(target_);
  impl_ = Guard(target_, "create", [&] {
    H5::FileAccPropList access;
    access.setCore(1 << 20, false);  // grows by 1 MiB; no backing store: Commit writes the image
    // The name only tells this file from the other open ones (HDF5 refuses a second of one name).
    return std::unique_ptr<Impl>(new Impl{H5::H5File(UniqueTemporaryName(target_).string(),
                                                     H5F_ACC_TRUNC, Impl::FileProperties(), access),
                                                     true, {}, {}});
  });
}

ResultWriter::~ResultWriter() = default;  // an uncommitted file lives in memory only

void ResultWriter::CreateGroup(const std::string& path) {
  CheckAbsolute(path);
  Guard(target_, path, [&] { impl_->EnsureGroup(path); });
}

void ResultWriter::WriteDoubles(const std::string& path, const std::vector<double>& values) {
  Guard(target_, path, [&] {
    H5::DataSet set = impl_->CreateDataset(path, H5::PredType::NATIVE_DOUBLE, {values.size()});
    if (!values.empty()) set.write(values.data(), H5::PredType::NATIVE_DOUBLE);
    impl_->Describe(set, path, false);
  });
}

void ResultWriter::WriteDoubles(const std::string& path, const Vector& values) {
  WriteDoubles(path, std::vector<double>(values.data(), values.data() + values.size()));
}

void ResultWriter::WriteMatrix(const std::string& path, const Matrix& values) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMajor row_major = values;
  Guard(target_, path, [&] {
    H5::DataSet set = impl_->CreateDataset(
        path, H5::PredType::NATIVE_DOUBLE,
        {static_cast<hsize_t>(values.rows()), static_cast<hsize_t>(values.cols())});
    if (values.size() > 0) set.write(row_major.data(), H5::PredType::NATIVE_DOUBLE);
    impl_->Describe(set, path, false);
  });
}

void ResultWriter::WriteInts(const std::string& path, const std::vector<int>& values) {
  Guard(target_, path, [&] {
    H5::DataSet set = impl_->CreateDataset(path, H5::PredType::NATIVE_INT, {values.size()});
    if (!values.empty()) set.write(values.data(), H5::PredType::NATIVE_INT);
    impl_->Describe(set, path, true);
  });
}

void ResultWriter::WriteStrings(const std::string& path, const std::vector<std::string>& values) {
  std::vector<const char*> pointers;
  for (const std::string& value : values) pointers.push_back(value.c_str());
  Guard(target_, path, [&] {
    H5::DataSet set = impl_->CreateDataset(path, Utf8String(), {values.size()});
    if (!values.empty()) set.write(pointers.data(), Utf8String());
  });
}

void ResultWriter::SetAttribute(const std::string& object, const std::string& name, double value) {
  CheckAbsolute(object);
  Guard(target_, object + "@" + name, [&] {
    impl_->EnsureGroup(impl_->Exists(object) ? std::string("/") : object);
    WithObject(impl_->file, object, [&](H5::H5Object& target) {
      if (target.attrExists(name)) target.removeAttr(name);
      target.createAttribute(name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(H5S_SCALAR))
          .write(H5::PredType::NATIVE_DOUBLE, &value);  // Attribute::write(type, buffer)
    });
  });
}

void ResultWriter::SetAttribute(const std::string& object, const std::string& name,
                                const std::string& value) {
  CheckAbsolute(object);
  Guard(target_, object + "@" + name, [&] {
    impl_->EnsureGroup(impl_->Exists(object) ? std::string("/") : object);
    WithObject(impl_->file, object, [&](H5::H5Object& target) {
      if (target.attrExists(name)) target.removeAttr(name);
      target.createAttribute(name, Utf8String(), H5::DataSpace(H5S_SCALAR)).write(Utf8String(), value);
    });
  });
}

void ResultWriter::SetAttribute(const std::string& object, const std::string& name,
                                const std::vector<double>& values) {
  CheckAbsolute(object);
  Guard(target_, object + "@" + name, [&] {
    impl_->EnsureGroup(impl_->Exists(object) ? std::string("/") : object);
    WithObject(impl_->file, object, [&](H5::H5Object& target) {
      if (target.attrExists(name)) target.removeAttr(name);
      const hsize_t size = values.size();
      H5::Attribute attribute =
          target.createAttribute(name, H5::PredType::NATIVE_DOUBLE, H5::DataSpace(1, &size));
      if (!values.empty()) attribute.write(H5::PredType::NATIVE_DOUBLE, values.data());
    });
  });
}

void ResultWriter::SetUnits(const std::string& dataset, const std::string& units) {
  CheckAbsolute(dataset);
  if (units.empty()) throw std::invalid_argument("SetUnits: empty units for " + dataset);
  Guard(target_, dataset + "@units", [&] {
    H5::DataSet set = impl_->file.openDataSet(dataset);
    Impl::WriteUnits(set, units);
  });
}

void ResultWriter::SetDimensionScales(const std::string& group, const std::string& scale) {
  CheckAbsolute(group);
  impl_->scales[group] = scale;
}

void ResultWriter::NameSecondAxis(const std::string& dataset, const std::string& dimension) {
  CheckAbsolute(dataset);
  impl_->second_axes[dataset] = dimension;
}

void ResultWriter::Commit() {
  if (!impl_->open) throw std::logic_error("ResultWriter::Commit called twice");
  for (const auto& [group, scale] : impl_->scales) {
    Guard(target_, group + " (dimension scales)", [&] { impl_->AttachScales(group, scale); });
  }
  const std::string image = Guard(target_, "image", [&] {
    impl_->file.flush(H5F_SCOPE_GLOBAL);
    const ssize_t size = H5Fget_file_image(impl_->file.getId(), nullptr, 0);
    std::string bytes(size > 0 ? static_cast<std::size_t>(size) : 0, '\0');
    if (size < 0 || H5Fget_file_image(impl_->file.getId(), bytes.data(), bytes.size()) != size) {
      throw std::runtime_error("cannot take the file's image");
    }
    impl_->file.close();
    return bytes;
  });
  impl_->open = false;
  WriteFileAtomically(target_, image);
}

// ---------------------------------------------------------------------------------------------

struct ResultReader::Impl {
  H5::H5File file;
};

ResultReader::ResultReader(const std::filesystem::path& file) : file_(file) {
  H5::Exception::dontPrint();
  auto fail = [&](const std::string& reason) {
    throw std::runtime_error("cannot read " + file_.string() + ": " + reason);
  };
  // The system's reason first (HDF5 says only "unable to open file" for most of them).
  const int fd = ::open(file_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail(std::strerror(errno));
  ::close(fd);
  std::error_code ignored;
  if (std::filesystem::is_directory(file_, ignored)) fail(std::strerror(EISDIR));
  try {
    impl_ = std::unique_ptr<Impl>(new Impl{H5::H5File(file_.string(), H5F_ACC_RDONLY)});
  } catch (const H5::Exception& e) {
    const std::string reason = InnermostHdf5Error();  // before any other HDF5 call clears it
    fail(reason.empty() ? e.getCDetailMsg() : reason);
  }
}

ResultReader::~ResultReader() = default;

bool ResultReader::Exists(const std::string& path) const {
  CheckAbsolute(path);
  if (path == "/") return true;
  for (std::size_t start = 1; start <= path.size();) {
    const std::size_t slash = std::min(path.find('/', start), path.size());
    if (H5Lexists(impl_->file.getId(), path.substr(0, slash).c_str(), H5P_DEFAULT) <= 0) return false;
    start = slash + 1;
  }
  return true;
}

std::vector<std::string> ResultReader::Children(const std::string& group) const {
  return Guard(file_, group, [&] {
    const H5::Group g = impl_->file.openGroup(group);
    std::vector<std::string> names;
    for (hsize_t i = 0; i < g.getNumObjs(); ++i) names.push_back(g.getObjnameByIdx(i));
    std::sort(names.begin(), names.end());
    return names;
  });
}

std::vector<double> ResultReader::ReadDoubles(const std::string& path) const {
  return Guard(file_, path, [&] {
    const H5::DataSet set = impl_->file.openDataSet(path);
    const H5::DataSpace space = set.getSpace();
    if (space.getSimpleExtentNdims() != 1) throw std::runtime_error(path + " is not 1-D");
    hsize_t n = 0;
    space.getSimpleExtentDims(&n);
    std::vector<double> values(n);
    if (n > 0) set.read(values.data(), H5::PredType::NATIVE_DOUBLE);
    return values;
  });
}

Matrix ResultReader::ReadMatrix(const std::string& path) const {
  return Guard(file_, path, [&] {
    const H5::DataSet set = impl_->file.openDataSet(path);
    const H5::DataSpace space = set.getSpace();
    if (space.getSimpleExtentNdims() != 2) throw std::runtime_error(path + " is not 2-D");
    hsize_t dims[2] = {0, 0};
    space.getSimpleExtentDims(dims);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> values(dims[0], dims[1]);
    if (values.size() > 0) set.read(values.data(), H5::PredType::NATIVE_DOUBLE);
    return Matrix(values);
  });
}

std::vector<int> ResultReader::ReadInts(const std::string& path) const {
  return Guard(file_, path, [&] {
    const H5::DataSet set = impl_->file.openDataSet(path);
    hsize_t n = 0;
    set.getSpace().getSimpleExtentDims(&n);
    std::vector<int> values(n);
    if (n > 0) set.read(values.data(), H5::PredType::NATIVE_INT);
    return values;
  });
}

std::vector<std::string> ResultReader::ReadStrings(const std::string& path) const {
  return Guard(file_, path, [&] {
    const H5::DataSet set = impl_->file.openDataSet(path);
    const H5::DataSpace space = set.getSpace();
    hsize_t n = 0;
    space.getSimpleExtentDims(&n);
    std::vector<char*> pointers(n, nullptr);
    if (n > 0) set.read(pointers.data(), Utf8String());
    std::vector<std::string> values;
    for (char* p : pointers) values.emplace_back(p == nullptr ? "" : p);
    if (n > 0) H5Dvlen_reclaim(Utf8String().getId(), space.getId(), H5P_DEFAULT, pointers.data());
    return values;
  });
}

bool ResultReader::HasAttribute(const std::string& object, const std::string& name) const {
  return Guard(file_, object, [&] {
    return WithObject(impl_->file, object, [&](H5::H5Object& target) { return target.attrExists(name); });
  });
}

double ResultReader::ReadDoubleAttribute(const std::string& object, const std::string& name) const {
  return Guard(file_, object + "@" + name, [&] {
    double value = 0.0;
    WithObject(impl_->file, object, [&](H5::H5Object& target) {
      target.openAttribute(name).read(H5::PredType::NATIVE_DOUBLE, &value);
    });
    return value;
  });
}

std::vector<double> ResultReader::ReadDoublesAttribute(const std::string& object,
                                                       const std::string& name) const {
  return Guard(file_, object + "@" + name, [&] {
    std::vector<double> values;
    WithObject(impl_->file, object, [&](H5::H5Object& target) {
      const H5::Attribute attribute = target.openAttribute(name);
      values.resize(static_cast<std::size_t>(attribute.getSpace().getSimpleExtentNpoints()));
      if (!values.empty()) attribute.read(H5::PredType::NATIVE_DOUBLE, values.data());
    });
    return values;
  });
}

std::string ResultReader::ReadStringAttribute(const std::string& object, const std::string& name) const {
  return Guard(file_, object + "@" + name, [&] {
    std::string value;
    WithObject(impl_->file, object, [&](H5::H5Object& target) {
      const H5::Attribute attribute = target.openAttribute(name);
      attribute.read(attribute.getStrType(), value);
    });
    return value;
  });
}

}  // namespace rubcont
