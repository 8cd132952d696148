// Attributes, units and dimension scales of result.h5 / checkpoint.h5 (HDF5 C and high-level
// H5DS APIs). The conventions follow CF where one exists (units, long_name, flag_values,
// flag_meanings), so that xarray and ParaView users need no README.
#include "fretbem/io/result_metadata.hpp"

#include <hdf5_hl.h>

#include <map>
#include <stdexcept>
#include <vector>

#include "fretbem/core/hdf5.hpp"
#include "fretbem/core/output_fields.hpp"

namespace fretbem::io {

namespace {

using hdf5::checked;

void remove_attribute(hid_t loc, const char* name, const std::string& what) {
  if (checked(H5Aexists(loc, name), what, std::string("look up attribute ") + name) > 0)
    checked(H5Adelete(loc, name), what, std::string("replace attribute ") + name);
}

void write_attribute(hid_t loc, const char* name, hid_t file_type, hid_t mem_type,
                     const void* value, hsize_t count, const std::string& what) {
  remove_attribute(loc, name, what);
  hdf5::Space space(
      checked(count == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &count, nullptr), what,
              "create a dataspace"));
  hdf5::Attribute a(checked(H5Acreate2(loc, name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                            what, std::string("create attribute ") + name));
  checked(H5Awrite(a.get(), mem_type, value), what, std::string("write attribute ") + name);
}

void write_doubles(hid_t loc, const char* name, std::vector<double> v, const std::string& what) {
  write_attribute(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), v.size(), what);
}

void write_int(hid_t loc, const char* name, long long v, const std::string& what) {
  const std::int64_t x = v;
  write_attribute(loc, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &x, 0, what);
}

hsize_t scale_length(hid_t scale) {
  hdf5::Space s(H5Dget_space(scale));
  return s.valid() ? hsize_t(H5Sget_simple_extent_npoints(s.get())) : 0;
}

}  // namespace

std::vector<double> cell_centres(int n, double h) {
  std::vector<double> c(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) c[i] = (i + 0.5 - 0.5 * n) * h;
  return c;
}

void write_coordinate(hid_t loc, const char* name, const std::vector<double>& c,
                      const std::string& what) {
  if (checked(H5Lexists(loc, name, H5P_DEFAULT), what, std::string("look up ") + name) > 0) return;
  const hsize_t n = c.size();
  hdf5::Space space(checked(H5Screate_simple(1, &n, nullptr), what, "create a dataspace"));
  hdf5::Dataset d(checked(
      H5Dcreate2(loc, name, H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      what, std::string("create ") + name));
  checked(H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.data()), what,
          std::string("write ") + name);
  const std::string axis = std::string(name).substr(std::string(name).find_last_of('/') + 1);
  checked(H5DSset_scale(d.get(), axis.c_str()), what,
          std::string("make ") + name + " a dimension scale");
  write_string_attribute(d.get(), "units", "m", what);
  write_string_attribute(d.get(), "long_name", "cell centre " + axis + " coordinate", what);
}

hdf5::Dataset create_extendible_vector(hid_t loc, const std::string& name, hid_t type,
                                       const std::string& what) {
  // 64 entries (512 B) per chunk: a run appends one entry per saved step or row, and a file
  // holds ~30 of these vectors from its first row on.
  const hsize_t dims = 0, maxdims = H5S_UNLIMITED, chunk = 64;
  hdf5::Space space(checked(H5Screate_simple(1, &dims, &maxdims), what, "create a dataspace"));
  hdf5::Plist dcpl(checked(H5Pcreate(H5P_DATASET_CREATE), what, "create a property list"));
  checked(H5Pset_chunk(dcpl.get(), 1, &chunk), what, "set the chunk size");
  return hdf5::Dataset(checked(
      H5Dcreate2(loc, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), what,
      "create " + name));
}

bool worth_compressing(hsize_t chunk_values) {
  return chunk_values >= 4096 && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0;
}

FieldInfo field_info(const std::string& name) {
  for (const OutputField& f : output_field_table())
    if (f.name == name) return {f.units, f.long_name, f.flag, f.dense};
  return {};
}

std::string column_units(const std::string& c) {
  static const std::map<std::string, std::string> known{{"Fz", "N"},
                                                        {"delta", "m"},
                                                        {"Fx", "N"},
                                                        {"Fy", "N"},
                                                        {"Ux", "m"},
                                                        {"Uy", "m"},
                                                        {"contact_area", "m2"},
                                                        {"stick_area", "m2"},
                                                        {"slip_area", "m2"},
                                                        {"Fx_stick", "N"},
                                                        {"kx", "N m-1"},
                                                        {"dissipation", "J"},
                                                        {"wear_volume", "m3"},
                                                        {"N", "1"}};
  const auto it = known.find(c);
  return it == known.end() ? "1" : it->second;  // step, time (load-path time), counts, flags
}

void write_string_attribute(hid_t loc, const char* name, const std::string& value,
                            const std::string& what) {
  hdf5::Type t(checked(H5Tcopy(H5T_C_S1), what, "create a string type"));
  // Fixed length, null-terminated: netCDF-4 and every HDF5 reader take these as plain text.
  checked(H5Tset_size(t.get(), value.size() + 1), what, "size a string type");
  checked(H5Tset_cset(t.get(), H5T_CSET_UTF8), what, "set a character set");
  write_attribute(loc, name, t.get(), t.get(), value.c_str(), 0, what);
}

void write_file_attributes(hid_t file, const Grid& g, const std::filesystem::path& output_dir,
                           const std::string& format, const std::string& what) {
  hdf5::Group root(checked(H5Gopen2(file, "/", H5P_DEFAULT), what, "open the root group"));
  const hid_t r = root.get();
  write_string_attribute(r, "program", "fretbem", what);
  write_string_attribute(r, "program_version", FRETBEM_VERSION, what);
  write_string_attribute(r, "format", format, what);
  write_int(r, "format_version", kResultFormatVersion, what);
  const std::int64_t shape[2] = {g.ny, g.nx};
  write_attribute(r, "grid_shape", H5T_STD_I64LE, H5T_NATIVE_INT64, shape, 2, what);
  write_doubles(r, "grid_spacing", {g.h, g.h}, what);
  write_doubles(r, "grid_origin", {g.y(0), g.x(0)}, what);
  write_doubles(r, "grid_length", {g.length_y(), g.length_x()}, what);
  write_int(r, "periodic", g.periodic ? 1 : 0, what);
  write_string_attribute(r, "array_layout",
                         "C order [y][x]: a[j, i] is the value at (x_i, y_j), x fastest", what);
  write_string_attribute(r, "cell_centred",
                         "fields are cell values; x_i = grid_origin[1] + i grid_spacing[1]", what);
  write_string_attribute(r, "output_dir", output_dir.string(), what);
  write_string_attribute(r, "Conventions", "CF-1.8", what);
}

void write_grid_scales(hid_t file, const Grid& g, const std::string& what) {
  write_coordinate(file, "/x", cell_centres(g.nx, g.h), what);
  write_coordinate(file, "/y", cell_centres(g.ny, g.h), what);
}

void write_field_attributes(hid_t dataset, const std::string& name, const std::string& what) {
  const FieldInfo info = field_info(name);
  write_string_attribute(dataset, "units", info.units, what);
  if (!info.long_name.empty()) write_string_attribute(dataset, "long_name", info.long_name, what);
  if (info.flag) {
    const std::uint8_t values[3] = {0, 1, 2};
    write_attribute(dataset, "flag_values", H5T_STD_U8LE, H5T_NATIVE_UINT8, values, 3, what);
    write_string_attribute(dataset, "flag_meanings", kStateMeanings, what);
  }
}

void describe_field(hid_t file, hid_t dataset, const std::string& name, const std::string& what) {
  write_field_attributes(dataset, name, what);
  if (H5Lexists(file, "/x", H5P_DEFAULT) <= 0 || H5Lexists(file, "/y", H5P_DEFAULT) <= 0) return;
  hdf5::Dataset x(checked(H5Dopen2(file, "/x", H5P_DEFAULT), what, "open /x"));
  hdf5::Dataset y(checked(H5Dopen2(file, "/y", H5P_DEFAULT), what, "open /y"));
  hdf5::Space space(checked(H5Dget_space(dataset), what, "read a dataspace"));
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space.get()) != 2) return;
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  if (dims[0] != scale_length(y.get()) || dims[1] != scale_length(x.get())) return;
  checked(H5DSattach_scale(dataset, y.get(), 0), what, "attach /y");
  checked(H5DSattach_scale(dataset, x.get(), 1), what, "attach /x");
}

}  // namespace fretbem::io
