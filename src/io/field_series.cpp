#include "fretbem/io/field_series.hpp"

#include <hdf5_hl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "fretbem/core/hdf5.hpp"
#include "fretbem/io/result_metadata.hpp"

namespace fretbem::io {

namespace {

using hdf5::checked;

std::string group_name(const StepFamily& family, std::int64_t index) {
  char num[32];
  std::snprintf(num, sizeof num, "%06lld", static_cast<long long>(index));
  return family.prefix + num;
}

hdf5::Plist intermediate_groups(const std::string& what) {
  hdf5::Plist lcpl(checked(H5Pcreate(H5P_LINK_CREATE), what, "create a property list"));
  checked(H5Pset_create_intermediate_group(lcpl.get(), 1), what, "set up group creation");
  return lcpl;
}

// The series group with its coordinates: x, y and the empty index and time axes.
hdf5::Group open_series(hid_t file, const StepFamily& family, const GridCoordinates& grid,
                        const std::string& what) {
  const char* name = family.series.c_str();
  if (hdf5::exists(file, family.series))
    return hdf5::Group(checked(H5Gopen2(file, name, H5P_DEFAULT), what, "open " + family.series));
  const hdf5::Plist lcpl = intermediate_groups(what);
  hdf5::Group g(checked(H5Gcreate2(file, name, lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), what,
                        "create " + family.series));
  if (!grid.x.empty()) {
    write_coordinate(g.get(), "x", grid.x, what);
    write_coordinate(g.get(), "y", grid.y, what);
  }
  const hdf5::Dataset index = create_extendible_vector(g.get(), family.index, H5T_STD_I64LE, what);
  checked(H5DSset_scale(index.get(), family.index.c_str()), what, "make a dimension scale");
  write_string_attribute(index.get(), "units", "1", what);
  write_string_attribute(index.get(), "long_name", "saved " + family.index, what);
  const hdf5::Dataset time = create_extendible_vector(g.get(), family.time, H5T_IEEE_F64LE, what);
  checked(H5DSattach_scale(time.get(), index.get(), 0), what, "attach " + family.index);
  write_string_attribute(time.get(), "units", "1", what);
  write_string_attribute(time.get(), "long_name", family.time_name, what);
  return g;
}

hsize_t extent(hid_t dataset, const std::string& what) {
  hdf5::Space s(checked(H5Dget_space(dataset), what, "read a dataspace"));
  hsize_t dims[3] = {0, 0, 0};
  checked(H5Sget_simple_extent_dims(s.get(), dims, nullptr), what, "read a dataspace");
  return dims[0];
}

// Where step `index` goes: its old place when saved before, else after the last one. Runs
// save steps in increasing order, so only a replaced step reads the whole index.
hsize_t place_of(hid_t series, const StepFamily& family, std::int64_t index,
                 const std::string& what) {
  hdf5::Dataset d(
      checked(H5Dopen2(series, family.index.c_str(), H5P_DEFAULT), what, "open " + family.index));
  const hsize_t n = extent(d.get(), what);
  if (n == 0) return 0;
  std::int64_t last = 0;
  {
    hdf5::Space file_space(checked(H5Dget_space(d.get()), what, "read " + family.index));
    const hsize_t start = n - 1, count = 1;
    checked(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &start, nullptr, &count, nullptr),
            what, "read " + family.index);
    hdf5::Space mem(checked(H5Screate_simple(1, &count, nullptr), what, "create a dataspace"));
    checked(H5Dread(d.get(), H5T_NATIVE_INT64, mem.get(), file_space.get(), H5P_DEFAULT, &last),
            what, "read " + family.index);
  }
  if (index > last) return n;
  std::vector<std::int64_t> saved(n);
  checked(H5Dread(d.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, saved.data()), what,
          "read " + family.index);
  return hsize_t(std::find(saved.begin(), saved.end(), index) - saved.begin());
}

bool is_flag(const std::string& name) {
  return field_info(name).flag;
}

hid_t file_type(const std::string& name) {
  return is_flag(name) ? H5T_STD_U8LE : H5T_IEEE_F64LE;
}

void attach(hid_t dataset, hid_t loc, const char* scale, unsigned dim, const std::string& what) {
  if (!hdf5::exists(loc, scale)) return;
  hdf5::Dataset s(checked(H5Dopen2(loc, scale, H5P_DEFAULT), what, std::string("open ") + scale));
  checked(H5DSattach_scale(dataset, s.get(), dim), what, std::string("attach ") + scale);
}

// SERIES/NAME [saved][ny][nx], one step per chunk (split further past kFieldChunkElements),
// shuffle + deflate as the single fields; steps not saved read NaN (state: 255).
hdf5::Dataset create_series_field(hid_t series, const StepFamily& family, const std::string& name,
                                  hsize_t ny, hsize_t nx, const std::string& what) {
  const hsize_t dims[3] = {0, ny, nx}, maxdims[3] = {H5S_UNLIMITED, ny, nx};
  hdf5::Space space(checked(H5Screate_simple(3, dims, maxdims), what, "create a dataspace"));
  hdf5::Plist dcpl(checked(H5Pcreate(H5P_DATASET_CREATE), what, "create a property list"));
  const hsize_t cols = std::max<hsize_t>(1, std::min<hsize_t>(nx, kFieldChunkElements));
  const hsize_t chunk[3] = {1, std::clamp<hsize_t>(kFieldChunkElements / cols, 1, ny), cols};
  checked(H5Pset_chunk(dcpl.get(), 3, chunk), what, "set the chunk size");
  if (worth_compressing(chunk[1] * chunk[2])) {
    checked(H5Pset_shuffle(dcpl.get()), what, "set the shuffle filter");
    checked(H5Pset_deflate(dcpl.get(), 4), what, "set the deflate filter");
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::uint8_t unsaved = 255;
  checked(is_flag(name) ? H5Pset_fill_value(dcpl.get(), H5T_NATIVE_UINT8, &unsaved)
                        : H5Pset_fill_value(dcpl.get(), H5T_NATIVE_DOUBLE, &nan),
          what, "set the fill value");
  hdf5::Dataset d(checked(H5Dcreate2(series, name.c_str(), file_type(name), space.get(),
                                     H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                          what, "create " + family.series + "/" + name));
  write_field_attributes(d.get(), name, what);
  write_string_attribute(d.get(), "coordinates", family.time, what);
  attach(d.get(), series, family.index.c_str(), 0, what);
  attach(d.get(), series, "y", 1, what);
  attach(d.get(), series, "x", 2, what);
  return d;
}

// Every dataset over the saved steps (index, time, fields) gets `steps` entries, so that
// they stay one table even when a step saves fewer fields than another.
void extend_all(hid_t series, hsize_t steps, const std::string& what) {
  for (const auto& name : hdf5::link_names(series)) {
    hdf5::Dataset d(checked(H5Dopen2(series, name.c_str(), H5P_DEFAULT), what, "open " + name));
    hdf5::Space s(checked(H5Dget_space(d.get()), what, "read a dataspace"));
    hsize_t dims[3] = {0, 0, 0}, maxdims[3] = {0, 0, 0};
    const int rank = H5Sget_simple_extent_dims(s.get(), dims, maxdims);
    if (rank < 1 || maxdims[0] != H5S_UNLIMITED || dims[0] >= steps) continue;
    dims[0] = steps;
    checked(H5Dset_extent(d.get(), dims), what, "extend " + name);
  }
}

// Writes `data` (rank-1 trailing dims `row`) at entry `at` of a dataset over the saved steps.
void write_entry(hid_t dataset, hsize_t at, const std::vector<hsize_t>& row, hid_t mem_type,
                 const void* data, const std::string& what) {
  hdf5::Space file_space(checked(H5Dget_space(dataset), what, "read a dataspace"));
  std::vector<hsize_t> start(row.size() + 1, 0), count{1};
  start[0] = at;
  count.insert(count.end(), row.begin(), row.end());
  checked(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                              nullptr),
          what, "select a saved step");
  hdf5::Space mem(
      checked(H5Screate_simple(int(count.size()), count.data(), nullptr), what, "create a space"));
  checked(H5Dwrite(dataset, mem_type, mem.get(), file_space.get(), H5P_DEFAULT, data), what,
          "write a saved step");
}

void write_series_entry(hid_t series, const StepFamily& family, hsize_t at, std::int64_t index,
                        double time, const std::map<std::string, Field>& fields,
                        const std::string& what) {
  for (const auto& [name, f] : fields)
    if (!hdf5::exists(series, name))
      create_series_field(series, family, name, hsize_t(f.cols()), hsize_t(f.rows()), what);
  extend_all(series, at + 1, what);
  const auto open = [&](const std::string& name) {
    return hdf5::Dataset(
        checked(H5Dopen2(series, name.c_str(), H5P_DEFAULT), what, "open " + name));
  };
  write_entry(open(family.index).get(), at, {}, H5T_NATIVE_INT64, &index, what);
  write_entry(open(family.time).get(), at, {}, H5T_NATIVE_DOUBLE, &time, what);
  for (const auto& [name, f] : fields) {
    // Eigen's column-major (nx, ny) storage is C-order [ny][nx]: x fastest, as h5py expects.
    const std::vector<hsize_t> row{hsize_t(f.cols()), hsize_t(f.rows())};
    const hdf5::Dataset d = open(name);
    if (is_flag(name)) {
      const Eigen::Array<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic> v = f.cast<std::uint8_t>();
      write_entry(d.get(), at, row, H5T_NATIVE_UINT8, v.data(), what);
    } else {
      write_entry(d.get(), at, row, H5T_NATIVE_DOUBLE, f.data(), what);
    }
  }
}

void write_scalar(hid_t loc, const char* name, hid_t type, hid_t mem_type, const void* value,
                  const std::string& what) {
  hdf5::Space scalar(checked(H5Screate(H5S_SCALAR), what, "create a dataspace"));
  hdf5::Attribute a(checked(H5Acreate2(loc, name, type, scalar.get(), H5P_DEFAULT, H5P_DEFAULT),
                            what, std::string("create attribute ") + name));
  checked(H5Awrite(a.get(), mem_type, value), what, std::string("write attribute ") + name);
}

// GROUP/NAME: a virtual dataset [ny][nx] of entry `at` of SERIES/NAME.
void write_view(hid_t group, const StepFamily& family, const std::string& name, hsize_t at,
                hsize_t ny, hsize_t nx, const std::string& what) {
  const hsize_t dims[2] = {ny, nx}, source_dims[3] = {at + 1, ny, nx};
  const hsize_t start[3] = {at, 0, 0}, count[3] = {1, ny, nx};
  hdf5::Space space(checked(H5Screate_simple(2, dims, nullptr), what, "create a dataspace"));
  hdf5::Space source(
      checked(H5Screate_simple(3, source_dims, nullptr), what, "create a dataspace"));
  checked(H5Sselect_hyperslab(source.get(), H5S_SELECT_SET, start, nullptr, count, nullptr), what,
          "select a saved step");
  hdf5::Plist dcpl(checked(H5Pcreate(H5P_DATASET_CREATE), what, "create a property list"));
  const std::string source_name = family.series + "/" + name;
  // "." : the source is in this file.
  checked(H5Pset_virtual(dcpl.get(), space.get(), ".", source_name.c_str(), source.get()), what,
          "map " + name + " to " + source_name);
  hdf5::Dataset d(checked(H5Dcreate2(group, name.c_str(), file_type(name), space.get(), H5P_DEFAULT,
                                     dcpl.get(), H5P_DEFAULT),
                          what, "create the view " + name));
  write_field_attributes(d.get(), name, what);
  attach(d.get(), group, "y", 0, what);
  attach(d.get(), group, "x", 1, what);
}

void write_step_group(hid_t file, const StepFamily& family, hsize_t at, std::int64_t index,
                      double time, const std::map<std::string, Field>& fields,
                      const GridCoordinates& grid, const std::string& what) {
  const std::string name = group_name(family, index);
  if (hdf5::exists(file, name))
    checked(H5Ldelete(file, name.c_str(), H5P_DEFAULT), what, "replace " + name);
  const hdf5::Plist lcpl = intermediate_groups(what);
  hdf5::Group g(checked(H5Gcreate2(file, name.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), what,
                        "create group " + name));
  write_scalar(g.get(), "step", H5T_STD_I64LE, H5T_NATIVE_INT64, &index, what);
  write_scalar(g.get(), "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &time, what);
  if (!grid.x.empty()) {
    write_coordinate(g.get(), "x", grid.x, what);
    write_coordinate(g.get(), "y", grid.y, what);
  }
  for (const auto& [field, f] : fields)
    write_view(g.get(), family, field, at, hsize_t(f.cols()), hsize_t(f.rows()), what);
}

}  // namespace

const StepFamily& step_family(const std::string& prefix) {
  static const std::vector<StepFamily> known{
      {"/fields/step_", "/series/fields", "step", "time", "load-path time (period 1)"},
      {"/wear/snapshot_", "/series/wear", "snapshot", "N", "wear cycles N"},
  };
  for (const auto& f : known)
    if (f.prefix == prefix) return f;
  throw std::invalid_argument("no saved-step family named " + prefix);
}

void write_saved_step(hid_t file, const StepFamily& family, std::int64_t index, double time,
                      const std::map<std::string, Field>& fields, const GridCoordinates& grid,
                      const std::string& what) {
  const hdf5::Group series = open_series(file, family, grid, what);
  const hsize_t at = place_of(series.get(), family, index, what);
  write_series_entry(series.get(), family, at, index, time, fields, what);
  write_step_group(file, family, at, index, time, fields, grid, what);
}

Field read_saved_field(hid_t file, hid_t group, const std::string& name) {
  const std::string what = "saved field " + name;
  hdf5::Dataset d(checked(H5Dopen2(group, name.c_str(), H5P_DEFAULT), what, "open"));
  hdf5::Space space(checked(H5Dget_space(d.get()), what, "read its dataspace"));
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.get()) != 2)
    throw std::runtime_error(what + ": not a 2-D field");
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  Field out(static_cast<Eigen::Index>(dims[1]), static_cast<Eigen::Index>(dims[0]));
  hdf5::Plist dcpl(checked(H5Dget_create_plist(d.get()), what, "read its layout"));
  if (H5Pget_layout(dcpl.get()) != H5D_VIRTUAL) {
    checked(H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), what,
            "read");
    return out;
  }
  std::size_t mappings = 0;
  checked(H5Pget_virtual_count(dcpl.get(), &mappings), what, "read its mapping");
  char source_file[2] = {0, 0};
  checked(H5Pget_virtual_filename(dcpl.get(), 0, source_file, sizeof source_file), what,
          "read its mapping");
  if (mappings != 1 || std::string(source_file) != ".")
    throw std::runtime_error(what + ": not a view of one saved step of this file");
  const ssize_t len = H5Pget_virtual_dsetname(dcpl.get(), 0, nullptr, 0);
  std::string source_name(std::size_t(std::max<ssize_t>(len, 0)) + 1, '\0');
  checked(H5Pget_virtual_dsetname(dcpl.get(), 0, source_name.data(), source_name.size()), what,
          "read its mapping");
  source_name.resize(std::size_t(std::max<ssize_t>(len, 0)));
  hdf5::Space selection(checked(H5Pget_virtual_srcspace(dcpl.get(), 0), what, "read its mapping"));
  hsize_t start[3] = {0, 0, 0}, end[3] = {0, 0, 0};
  checked(H5Sget_select_bounds(selection.get(), start, end), what, "read its mapping");
  hdf5::Dataset source(
      checked(H5Dopen2(file, source_name.c_str(), H5P_DEFAULT), what, "open " + source_name));
  hdf5::Space source_space(checked(H5Dget_space(source.get()), what, "read " + source_name));
  const hsize_t count[3] = {end[0] - start[0] + 1, end[1] - start[1] + 1, end[2] - start[2] + 1};
  checked(H5Sselect_hyperslab(source_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
          what, "select its step in " + source_name);
  hdf5::Space mem(checked(H5Screate_simple(2, dims, nullptr), what, "create a dataspace"));
  checked(H5Dread(source.get(), H5T_NATIVE_DOUBLE, mem.get(), source_space.get(), H5P_DEFAULT,
                  out.data()),
          what, "read " + source_name);
  return out;
}

std::vector<std::string> saved_field_names(hid_t group) {
  std::vector<std::string> out;
  for (const auto& name : hdf5::link_names(group)) {
    hdf5::Dataset d(H5Dopen2(group, name.c_str(), H5P_DEFAULT));
    hdf5::Space s(d.valid() ? H5Dget_space(d.get()) : -1);
    // An unreadable member is kept: reading it then reports the damage.
    if (!s.valid() || H5Sget_simple_extent_ndims(s.get()) == 2) out.push_back(name);
  }
  return out;
}

}  // namespace fretbem::io
