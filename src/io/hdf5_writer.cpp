#include "fretbem/io/hdf5_writer.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/hdf5.hpp"
#include "fretbem/core/text_file.hpp"
#include "fretbem/io/column_series.hpp"
#include "fretbem/io/field_series.hpp"
#include "fretbem/io/result_metadata.hpp"

namespace fretbem::io {

namespace fs = std::filesystem;

namespace {

using FileH = hdf5::File;
using GroupH = hdf5::Group;
using DatasetH = hdf5::Dataset;
using SpaceH = hdf5::Space;
using TypeH = hdf5::Type;
using PlistH = hdf5::Plist;
using AttrH = hdf5::Attribute;

TypeH utf8_string_type() {
  TypeH t(H5Tcopy(H5T_C_S1));
  H5Tset_size(t.get(), H5T_VARIABLE);
  H5Tset_cset(t.get(), H5T_CSET_UTF8);
  return t;
}

constexpr hsize_t kTimeseriesChunkRows = 64;

// A fixed metadata cache of 256 KiB: HDF5 1.10.8 walks every cached entry on each flush
// (H5C_set_slist_enabled), a run flushes after every write, and the default cache grows to
// hold the objects of every saved step, so the flushes grew quadratic (measured: 10 000 saved
// steps of an 8 x 8 grid, 46 s of CPU; 1000 and 3000 steps took 3.3 and 15.9 s; with this
// cache 2.3 and 6.0 s). Field chunks do not pass through this cache.
PlistH access_plist() {
  PlistH fapl(H5Pcreate(H5P_FILE_ACCESS));
  H5AC_cache_config_t c;
  c.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  if (!fapl.valid() || H5Pget_mdc_config(fapl.get(), &c) < 0) return fapl;
  c.set_initial_size = 1;
  c.initial_size = c.min_size = c.max_size = 256 * 1024;
  c.incr_mode = H5C_incr__off;
  c.flash_incr_mode = H5C_flash_incr__off;
  c.decr_mode = H5C_decr__off;
  H5Pset_mdc_config(fapl.get(), &c);
  return fapl;
}

// Chunk B-tree nodes of 2 x 4 entries instead of 2 x 32: each extendible dataset carries one
// node from its first write, ~2 KiB at the default, and /series/timeseries holds ~30 of them
// (measured: 98 KiB of metadata after the first row; HDF5 1.10 file format, any reader).
PlistH creation_plist() {
  PlistH fcpl(H5Pcreate(H5P_FILE_CREATE));
  if (fcpl.valid()) H5Pset_istore_k(fcpl.get(), 4);
  return fcpl;
}

}  // namespace

struct Hdf5Writer::Impl {
  fs::path path;
  FileH file;
  DatasetH timeseries;
  ColumnSeries column_series;  // the same rows, one variable per column
  std::vector<std::string> columns;
  std::size_t rows = 0;
  GridCoordinates coordinates;  // of the saved steps' scales; set by describe()

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(path.string() + ": cannot " + what + ": " + hdf5::last_error());
  }
  /// Identifiers and status codes alike are negative on failure.
  hid_t check(hid_t id, const std::string& what) const {
    if (id < 0) fail(what);
    return id;
  }
  void flush() const { check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush the file"); }

  bool exists(const std::string& name) const;
  void remove_if_exists(const std::string& name) const;
  PlistH link_plist() const;
  void write_field(hid_t loc, const std::string& name, const Field& f) const;
  void write_columns_attribute(hid_t dataset, const char* name,
                               const std::vector<std::string>& values) const;
  void open_timeseries();
};

bool Hdf5Writer::Impl::exists(const std::string& name) const {
  return hdf5::exists(file.get(), name);
}

void Hdf5Writer::Impl::remove_if_exists(const std::string& name) const {
  if (exists(name)) check(H5Ldelete(file.get(), name.c_str(), H5P_DEFAULT), "replace " + name);
}

PlistH Hdf5Writer::Impl::link_plist() const {
  PlistH lcpl(check(H5Pcreate(H5P_LINK_CREATE), "create a property list"));
  check(H5Pset_create_intermediate_group(lcpl.get(), 1), "set up group creation");
  return lcpl;
}

void Hdf5Writer::Impl::write_field(hid_t loc, const std::string& name, const Field& f) const {
  // Eigen's column-major (nx, ny) storage is C-order [ny][nx]: x fastest, as h5py expects.
  const hsize_t dims[2] = {static_cast<hsize_t>(f.cols()), static_cast<hsize_t>(f.rows())};
  SpaceH space(check(H5Screate_simple(2, dims, nullptr), "create a dataspace"));
  PlistH dcpl(check(H5Pcreate(H5P_DATASET_CREATE), "create a property list"));
  const std::string leaf = name.substr(name.find_last_of('/') + 1);
  const FieldInfo info = field_info(leaf);
  if (f.size() > 0 && !info.dense) {  // chunks must be non-empty and no larger than the dataset
    const hsize_t cols = std::min<hsize_t>(dims[1], kFieldChunkElements);
    const hsize_t chunk[2] = {std::clamp<hsize_t>(kFieldChunkElements / cols, 1, dims[0]), cols};
    check(H5Pset_chunk(dcpl.get(), 2, chunk), "set the chunk size");
    if (worth_compressing(chunk[0] * chunk[1])) {
      check(H5Pset_shuffle(dcpl.get()), "set the shuffle filter");
      check(H5Pset_deflate(dcpl.get(), 4), "set the deflate filter");
    }
  }
  const PlistH lcpl = link_plist();
  // Flag fields (state: 0 open, 1 stick, 2 slip) are stored as uint8, the rest as float64.
  const bool flag = info.flag;
  DatasetH d(check(H5Dcreate2(loc, name.c_str(), flag ? H5T_STD_U8LE : H5T_IEEE_F64LE, space.get(),
                              lcpl.get(), dcpl.get(), H5P_DEFAULT),
                   "create dataset " + name));
  if (flag) {
    const Eigen::Array<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic> v = f.cast<std::uint8_t>();
    check(H5Dwrite(d.get(), H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()),
          "write a field");
  } else {
    check(H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, f.data()),
          "write a field");
  }
  describe_field(file.get(), d.get(), leaf, path.string());
}

void Hdf5Writer::Impl::write_columns_attribute(hid_t dataset, const char* name,
                                               const std::vector<std::string>& values) const {
  std::vector<const char*> names;
  for (const auto& c : values) names.push_back(c.c_str());
  const hsize_t n = names.size();
  SpaceH space(check(H5Screate_simple(1, &n, nullptr), "create a dataspace"));
  const TypeH type = utf8_string_type();
  AttrH a(check(H5Acreate2(dataset, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
                std::string("create attribute ") + name));
  check(H5Awrite(a.get(), type.get(), names.data()), std::string("write attribute ") + name);
}

void Hdf5Writer::Impl::open_timeseries() {
  timeseries =
      DatasetH(check(H5Dopen2(file.get(), "/timeseries", H5P_DEFAULT), "open /timeseries"));
  SpaceH space(check(H5Dget_space(timeseries.get()), "read /timeseries"));
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.get()) != 2) fail("use /timeseries (not 2-D)");
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  rows = dims[0];
  AttrH a(check(H5Aopen(timeseries.get(), "columns", H5P_DEFAULT), "open /timeseries columns"));
  SpaceH aspace(check(H5Aget_space(a.get()), "read /timeseries columns"));
  const hssize_t n = H5Sget_simple_extent_npoints(aspace.get());
  if (n != static_cast<hssize_t>(dims[1])) fail("use /timeseries (columns do not match)");
  std::vector<char*> names(static_cast<std::size_t>(n), nullptr);
  const TypeH type = utf8_string_type();
  check(H5Aread(a.get(), type.get(), names.data()), "read /timeseries columns");
  columns.clear();
  for (char* s : names) {
    columns.emplace_back(s ? s : "");
    H5free_memory(s);
  }
  std::vector<double> table(rows * columns.size());
  if (!table.empty())
    check(H5Dread(timeseries.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, table.data()),
          "read /timeseries");
  column_series = ColumnSeries::open_or_rebuild(file.get(), columns, table, path.string());
}

namespace {

template <typename T>
T read_scalar_attribute(hid_t loc, const char* name, hid_t mem_type) {
  AttrH a(H5Aopen(loc, name, H5P_DEFAULT));
  T value{};
  if (!a.valid() || H5Aread(a.get(), mem_type, &value) < 0)
    throw std::runtime_error(std::string("attribute ") + name + " unreadable");
  return value;
}

}  // namespace

// A group of write_step_fields' layout read whole into memory: any damage (an unreadable
// attribute, field or chunk, a name that is not PREFIX%06d of its step) throws.
struct StepGroup {
  std::int64_t step = 0;
  double time = 0.0;
  std::string prefix;
  std::map<std::string, Field> fields;
};

StepGroup read_step_group(hid_t source, const std::string& name) {
  GroupH from(H5Gopen2(source, name.c_str(), H5P_DEFAULT));
  if (!from.valid()) throw std::runtime_error("cannot open " + name);
  StepGroup g;
  g.step = read_scalar_attribute<std::int64_t>(from.get(), "step", H5T_NATIVE_INT64);
  g.time = read_scalar_attribute<double>(from.get(), "time", H5T_NATIVE_DOUBLE);
  char num[32];
  std::snprintf(num, sizeof num, "%06lld", static_cast<long long>(g.step));
  if (name.size() < std::strlen(num) || name.substr(name.size() - std::strlen(num)) != num)
    throw std::runtime_error(name + " is not the group of its step");
  g.prefix = name.substr(0, name.size() - std::strlen(num));
  for (const auto& f : saved_field_names(from.get()))
    g.fields.emplace(f, read_saved_field(source, from.get(), f));
  return g;
}

Hdf5Writer::Hdf5Writer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Hdf5Writer::Hdf5Writer(const fs::path& dir, const std::string& name)
    : impl_(std::make_unique<Impl>()) {
  hdf5::silence();
  impl_->path = dir / name;
  create_output_folder(dir);
  const hid_t f =
      H5Fcreate(impl_->path.c_str(), H5F_ACC_TRUNC, creation_plist().get(), access_plist().get());
  if (f < 0) throw InputError(impl_->path.string() + ": cannot create: " + hdf5::last_error());
  impl_->file = FileH(f);
}

Hdf5Writer Hdf5Writer::open_existing(const fs::path& dir) {
  hdf5::silence();
  auto impl = std::make_unique<Impl>();
  impl->path = dir / file_name;
  const hid_t f = H5Fopen(impl->path.c_str(), H5F_ACC_RDWR, access_plist().get());
  if (f < 0)
    throw InputError(impl->path.string() + ": cannot open to append: " + hdf5::last_error());
  impl->file = FileH(f);
  if (impl->exists("/timeseries")) impl->open_timeseries();
  return Hdf5Writer(std::move(impl));
}

Hdf5Writer::~Hdf5Writer() = default;
Hdf5Writer::Hdf5Writer(Hdf5Writer&&) noexcept = default;
Hdf5Writer& Hdf5Writer::operator=(Hdf5Writer&&) noexcept = default;

const fs::path& Hdf5Writer::path() const {
  return impl_->path;
}

void Hdf5Writer::close() {
  impl_->timeseries.close();
  impl_->column_series = ColumnSeries();
  if (impl_->file.close() < 0) impl_->fail("close");
}

void Hdf5Writer::describe(const Grid& grid, const fs::path& output_dir) {
  const std::string what = impl_->path.string();
  write_file_attributes(impl_->file.get(), grid, output_dir, "fretbem result", what);
  write_grid_scales(impl_->file.get(), grid, what);
  impl_->coordinates = {cell_centres(grid.nx, grid.h), cell_centres(grid.ny, grid.h)};
  impl_->flush();
}

void Hdf5Writer::write_text(const std::string& name, const std::string& text) {
  impl_->remove_if_exists(name);
  const TypeH type = utf8_string_type();
  SpaceH scalar(impl_->check(H5Screate(H5S_SCALAR), "create a dataspace"));
  const PlistH lcpl = impl_->link_plist();
  DatasetH d(impl_->check(H5Dcreate2(impl_->file.get(), name.c_str(), type.get(), scalar.get(),
                                     lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
                          "create dataset " + name));
  const char* p = text.c_str();
  impl_->check(H5Dwrite(d.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &p), "write text");
  impl_->flush();
}

void Hdf5Writer::write_field(const std::string& path, const Field& field) {
  impl_->remove_if_exists(path);
  impl_->write_field(impl_->file.get(), path, field);
  impl_->flush();
}

void Hdf5Writer::link(const std::string& existing, const std::string& path) {
  impl_->remove_if_exists(path);
  const PlistH lcpl = impl_->link_plist();
  impl_->check(H5Lcreate_hard(impl_->file.get(), existing.c_str(), impl_->file.get(), path.c_str(),
                              lcpl.get(), H5P_DEFAULT),
               "link " + path + " to " + existing);
  impl_->flush();
}

void Hdf5Writer::write_step_fields(std::int64_t step, double time,
                                   const std::map<std::string, Field>& fields,
                                   const std::string& prefix) {
  write_saved_step(impl_->file.get(), step_family(prefix), step, time, fields, impl_->coordinates,
                   impl_->path.string());
  impl_->flush();
}

std::vector<std::string> Hdf5Writer::copy_step_groups(const fs::path& source,
                                                      const std::vector<std::string>& groups) {
  // Read whole, then written as a run writes them (H5Ocopy of HDF5 1.10.8 crashed in its
  // error path when the destination disk filled up): a read failure is the source's damage
  // and leaves the group out, a write failure is this file's and throws.
  std::vector<std::string> failed;
  FileH src(H5Fopen(source.c_str(), H5F_ACC_RDONLY, access_plist().get()));
  for (const auto& name : groups) {
    StepGroup g;
    try {
      if (!src.valid()) throw std::runtime_error("cannot open the source");
      g = read_step_group(src.get(), name);
    } catch (const std::exception&) {
      hdf5::last_error();  // clears the stack
      failed.push_back(name);
      continue;
    }
    write_step_fields(g.step, g.time, g.fields, g.prefix);
  }
  return failed;
}

void Hdf5Writer::start_timeseries(const std::vector<std::string>& columns) {
  if (columns.empty()) throw std::invalid_argument("start_timeseries: no columns");
  impl_->timeseries.close();
  impl_->remove_if_exists("/timeseries");
  impl_->columns = columns;
  impl_->rows = 0;
  const hsize_t ncols = columns.size();
  const hsize_t dims[2] = {0, ncols}, maxdims[2] = {H5S_UNLIMITED, ncols};
  SpaceH space(impl_->check(H5Screate_simple(2, dims, maxdims), "create a dataspace"));
  PlistH dcpl(impl_->check(H5Pcreate(H5P_DATASET_CREATE), "create a property list"));
  const hsize_t chunk[2] = {kTimeseriesChunkRows, ncols};
  impl_->check(H5Pset_chunk(dcpl.get(), 2, chunk), "set the chunk size");
  if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0)
    impl_->check(H5Pset_deflate(dcpl.get(), 4), "set the deflate filter");
  impl_->timeseries =
      DatasetH(impl_->check(H5Dcreate2(impl_->file.get(), "/timeseries", H5T_IEEE_F64LE,
                                       space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                            "create /timeseries"));
  std::vector<std::string> units;
  for (const auto& c : columns) units.push_back(column_units(c));
  impl_->write_columns_attribute(impl_->timeseries.get(), "columns", columns);
  impl_->write_columns_attribute(impl_->timeseries.get(), "units", units);
  impl_->column_series = ColumnSeries::create(impl_->file.get(), columns, impl_->path.string());
  impl_->flush();
}

void Hdf5Writer::append_row(const std::vector<double>& row) {
  if (!impl_->timeseries.valid())
    throw std::invalid_argument(impl_->path.string() +
                                ": has no /timeseries dataset to append the step's row to");
  if (row.size() != impl_->columns.size())
    throw std::invalid_argument(impl_->path.string() + ": row of " + std::to_string(row.size()) +
                                " values for " + std::to_string(impl_->columns.size()) +
                                " columns");
  const hid_t d = impl_->timeseries.get();
  const hsize_t ncols = row.size();
  const hsize_t dims[2] = {impl_->rows + 1, ncols};
  impl_->check(H5Dset_extent(d, dims), "extend /timeseries");
  SpaceH file_space(impl_->check(H5Dget_space(d), "select in /timeseries"));
  const hsize_t start[2] = {impl_->rows, 0}, count[2] = {1, ncols};
  impl_->check(
      H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
      "select in /timeseries");
  SpaceH mem_space(impl_->check(H5Screate_simple(2, count, nullptr), "create a dataspace"));
  impl_->check(
      H5Dwrite(d, H5T_NATIVE_DOUBLE, mem_space.get(), file_space.get(), H5P_DEFAULT, row.data()),
      "append to /timeseries");
  impl_->column_series.append(row);
  ++impl_->rows;
  impl_->flush();
}

void Hdf5Writer::truncate_timeseries(std::size_t rows) {
  if (!impl_->timeseries.valid() || rows >= impl_->rows) return;
  const hsize_t dims[2] = {rows, impl_->columns.size()};
  impl_->check(H5Dset_extent(impl_->timeseries.get(), dims), "truncate /timeseries");
  impl_->column_series.truncate(rows);
  impl_->rows = rows;
  impl_->flush();
}

std::size_t Hdf5Writer::timeseries_rows() const {
  return impl_->rows;
}
const std::vector<std::string>& Hdf5Writer::timeseries_columns() const {
  return impl_->columns;
}

}  // namespace fretbem::io
