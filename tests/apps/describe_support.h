// Reading a result file's self-description back with the HDF5 library itself (not ResultReader:
// what an outside reader sees): attributes, dimension scales, the links' creation order. Shared by
// the tests of tests/apps/ that check what apps/hdf5_file.h promises.
#pragma once

#include <string>
#include <vector>

#include <H5Cpp.h>
#include <hdf5_hl.h>

namespace rubcont::testing {

inline std::string StringAttribute(const H5::H5Object& object, const std::string& name) {
  if (!object.attrExists(name)) return "<none>";
  const H5::Attribute attribute = object.openAttribute(name);
  std::string value;
  attribute.read(attribute.getStrType(), value);
  return value;
}

inline std::vector<double> FlagValues(const H5::H5Object& object) {
  if (!object.attrExists("flag_values")) return {};
  const H5::Attribute attribute = object.openAttribute("flag_values");
  const auto n = attribute.getSpace().getSimpleExtentNpoints();
  std::vector<double> values(static_cast<std::size_t>(n));
  attribute.read(H5::PredType::NATIVE_DOUBLE, values.data());
  return values;
}

// The name of the dimension scale attached to axis `axis` of `dataset`, or "" for none.
inline std::string ScaleOf(const H5::H5File& file, const std::string& dataset, unsigned axis) {
  const H5::DataSet set = file.openDataSet(dataset);
  std::string found;
  auto visit = [](hid_t, unsigned, hid_t scale, void* data) -> herr_t {
    char name[256] = {};
    H5DSget_scale_name(scale, name, sizeof name);
    *static_cast<std::string*>(data) = name;
    return 1;  // the first scale of the axis
  };
  if (H5DSget_num_scales(set.getId(), axis) <= 0) return "";
  H5DSiterate_scales(set.getId(), axis, nullptr, visit, &found);
  return found;
}

// The links of `group` in creation order, as h5py lists a group whose order is tracked; empty
// when the group does not track it.
inline std::vector<std::string> CreationOrder(const H5::H5File& file, const std::string& group) {
  const H5::Group g = file.openGroup(group);
  const hid_t gcpl = H5Gget_create_plist(g.getId());
  unsigned flags = 0;
  H5Pget_link_creation_order(gcpl, &flags);
  H5Pclose(gcpl);
  if (flags != (H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED)) return {};
  std::vector<std::string> names;
  auto visit = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
    static_cast<std::vector<std::string>*>(data)->push_back(name);
    return 0;
  };
  H5Literate(g.getId(), H5_INDEX_CRT_ORDER, H5_ITER_INC, nullptr, visit, &names);
  return names;
}

}  // namespace rubcont::testing
