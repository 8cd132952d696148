// Height-map files: HDF5, NumPy .npy and text, read and written in the documented layout.
#include "fretbem/surface/formats.hpp"

#include <hdf5.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string_view>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/hdf5.hpp"
#include "fretbem/core/text_file.hpp"
#include "npy.hpp"
#include "zip_formats.hpp"

namespace fretbem {

namespace surface_detail {

void file_error(const std::filesystem::path& file, const std::string& what) {
  throw InputError("height map '" + file.string() + "': " + what);
}

// Grids index with int; 2^30 nodes (8 GiB of doubles) is far beyond any BEM grid. Checked
// before allocating, since a corrupt header can declare any shape.
void require_sane_shape(const std::filesystem::path& file, unsigned long long ny,
                        unsigned long long nx) {
  constexpr unsigned long long kMaxSide = 1ull << 24, kMaxNodes = 1ull << 30;
  if (nx == 0 || ny == 0) file_error(file, "array is empty");
  if (nx > kMaxSide || ny > kMaxSide || nx * ny > kMaxNodes)
    file_error(file,
               "array shape (" + std::to_string(ny) + ", " + std::to_string(nx) + ") is too large");
}

std::string name_list(const std::vector<std::string>& names) {
  constexpr std::size_t kShown = 8;  // one line, even for a results file
  std::string list;
  for (std::size_t i = 0; i < names.size() && i < kShown; ++i) list += (i ? ", " : "") + names[i];
  if (names.size() > kShown) list += ", ...";
  return list;
}

}  // namespace surface_detail

namespace {

using surface_detail::file_error;
using surface_detail::require_sane_shape;

void require_finite(const std::filesystem::path& file, const Field& z) {
  for (int j = 0; j < z.cols(); ++j)
    for (int i = 0; i < z.rows(); ++i)
      if (!std::isfinite(z(i, j)))
        file_error(
            file, "NaN or Inf value at row " + std::to_string(j) + ", column " + std::to_string(i));
}

std::string lower_extension(const std::filesystem::path& file) {
  std::string e = file.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

std::string read_all(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) file_error(file, "cannot open for reading");
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) file_error(file, "read error");
  return data;
}

// ---------------------------------------------------------------------------------------
// HDF5 (C API). Errors are reported through return codes; HDF5's automatic printing of its
// error stack is silenced for the duration of each call into this module.

int dataset_rank(hid_t dset) {
  hdf5::Space space(H5Dget_space(dset));
  return space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
}

// H5Lvisit callback: collects the hard links to 2-D datasets, in name order.
herr_t list_2d_datasets(hid_t group, const char* name, const H5L_info_t* info, void* found) {
  if (info->type != H5L_TYPE_HARD) return 0;
  hdf5::Dataset d(H5Dopen2(group, name, H5P_DEFAULT));
  if (d.valid() && dataset_rank(d.get()) == 2)
    static_cast<std::vector<std::string>*>(found)->push_back(name);
  return 0;
}

// Without surface.dataset the file must hold one 2-D dataset: taking the first of several
// would pick a map by its name's sort order (as .npz files, refused naming them).
std::string choose_dataset(const std::filesystem::path& file, hid_t f, const std::string& name) {
  if (!name.empty()) return name;
  std::vector<std::string> found;
  if (H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, list_2d_datasets, &found) < 0 || found.empty())
    file_error(file, "no 2-D dataset in the file");
  if (found.size() > 1)
    file_error(file, "holds " + std::to_string(found.size()) + " 2-D datasets (" +
                         surface_detail::name_list(found) + "): name one with surface.dataset");
  return found.front();
}

// The dataset's attribute `spacing`, if it has one: 1 or 2 numbers (m).
std::vector<double> h5_spacing(const std::filesystem::path& file, hid_t d) {
  if (H5Aexists(d, "spacing") <= 0) return {};
  hdf5::Attribute a(H5Aopen(d, "spacing", H5P_DEFAULT));
  hdf5::Space space(a.valid() ? H5Aget_space(a.get()) : H5I_INVALID_HID);
  const hssize_t n = space.valid() ? H5Sget_simple_extent_npoints(space.get()) : -1;
  if (n < 1 || n > 2) file_error(file, "attribute 'spacing' must hold 1 or 2 numbers (m)");
  std::vector<double> v(static_cast<std::size_t>(n));
  if (H5Aread(a.get(), H5T_NATIVE_DOUBLE, v.data()) < 0)
    file_error(file, "attribute 'spacing' could not be read as numbers");
  return v;
}

Field read_h5_dataset(const std::filesystem::path& file, hid_t d, const std::string& name) {
  const std::string where = "dataset '" + name + "' ";
  hdf5::Space space(H5Dget_space(d));
  if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 2)
    file_error(file, where + "is not 2-D");
  hsize_t dims[2];
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  hdf5::Type type(H5Dget_type(d));
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls != H5T_FLOAT && cls != H5T_INTEGER) file_error(file, where + "is not numeric");
  // A damaged header can declare a 4 GiB "float" (found by fuzz_surface): HDF5 would allocate
  // a conversion buffer of that size per element. No numeric type is wider than 16 bytes.
  if (const std::size_t bytes = H5Tget_size(type.get()); bytes == 0 || bytes > 16)
    file_error(file,
               where + "has elements of " + std::to_string(bytes) + " bytes (not a number type)");
  require_sane_shape(file, dims[0], dims[1]);
  Field z(static_cast<Eigen::Index>(dims[1]), static_cast<Eigen::Index>(dims[0]));  // {ny, nx}
  if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, z.data()) < 0)
    file_error(file, where + "could not be read");
  return z;
}

HeightMap load_h5(const std::filesystem::path& file, const std::string& dataset) {
  hdf5::Quiet quiet;
  if (H5Fis_hdf5(file.c_str()) <= 0) file_error(file, "not an HDF5 file");
  hdf5::File f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!f.valid()) file_error(file, "cannot open HDF5 file");
  const std::string name = choose_dataset(file, f.get(), dataset);
  hdf5::Dataset d(H5Dopen2(f.get(), name.c_str(), H5P_DEFAULT));
  if (!d.valid()) file_error(file, "no dataset '" + name + "'");
  HeightMap m{read_h5_dataset(file, d.get(), name), {}, {}};
  if (const auto v = h5_spacing(file, d.get()); !v.empty())
    surface_detail::set_spacing(file, v, "attribute 'spacing' of dataset '" + name + "'", m);
  return m;
}

void save_h5(const std::filesystem::path& file, const Field& z, std::optional<double> spacing) {
  hdf5::Quiet quiet;
  hdf5::File f(H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  if (!f.valid()) file_error(file, "cannot create HDF5 file");
  const hsize_t dims[2] = {hsize_t(z.cols()), hsize_t(z.rows())};  // {ny, nx}
  hdf5::Space space(H5Screate_simple(2, dims, nullptr));
  hdf5::Dataset d(H5Dcreate2(f.get(), "height", H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                             H5P_DEFAULT, H5P_DEFAULT));
  if (!space.valid() || !d.valid() ||
      H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, z.data()) < 0)
    file_error(file, "cannot write dataset 'height'");
  if (!spacing) return;
  hdf5::Space scalar(H5Screate(H5S_SCALAR));
  hdf5::Attribute a(
      H5Acreate2(d.get(), "spacing", H5T_IEEE_F64LE, scalar.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!a.valid() || H5Awrite(a.get(), H5T_NATIVE_DOUBLE, &*spacing) < 0)
    file_error(file, "cannot write attribute 'spacing'");
}

// ---------------------------------------------------------------------------------------
// NumPy .npy (format spec: numpy.lib.format / NEP 1): magic "\x93NUMPY", version bytes,
// little-endian header length (uint16 for 1.0, uint32 for 2.0/3.0), then a Python dict
// literal with 'descr', 'fortran_order', 'shape', padded with spaces to a multiple of 64.

constexpr std::string_view kNpyMagic("\x93NUMPY", 6);

// Byte-wise little-endian access: independent of the host's byte order.
template <class U>
U load_le(const char* p) {
  U v = 0;
  for (std::size_t b = 0; b < sizeof(U); ++b) v |= U(static_cast<unsigned char>(p[b])) << (8 * b);
  return v;
}

template <class U>
void append_le(std::string& out, U v) {
  for (std::size_t b = 0; b < sizeof(U); ++b) out += char((v >> (8 * b)) & 0xff);
}

struct NpyHeader {
  std::string descr;
  bool fortran = false;
  std::vector<long long> shape;
  std::size_t data_offset = 0;
};

// Text after "'key':" in the header dict, or throws.
std::string_view dict_value(const std::filesystem::path& file, std::string_view h,
                            const std::string& key) {
  const auto k = h.find("'" + key + "'");
  const auto colon = k == h.npos ? h.npos : h.find(':', k);
  if (colon == h.npos) file_error(file, "npy header has no '" + key + "'");
  auto v = h.substr(colon + 1);
  return v.substr(std::min(v.find_first_not_of(' '), v.size()));
}

std::vector<long long> parse_shape(const std::filesystem::path& file, std::string_view v) {
  const auto close = v.find(')');
  if (v.empty() || v[0] != '(' || close == v.npos) file_error(file, "npy shape is malformed");
  std::vector<long long> shape;
  std::string_view rest = v.substr(1, close - 1);
  while (!rest.empty()) {
    const auto comma = std::min(rest.find(','), rest.size());
    std::string_view tok = rest.substr(0, comma);
    tok.remove_prefix(std::min(tok.find_first_not_of(' '), tok.size()));
    if (!tok.empty()) {
      long long n = -1;
      const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), n);
      if (r.ec != std::errc() || n < 0) file_error(file, "npy shape is malformed");
      shape.push_back(n);
    }
    rest.remove_prefix(std::min(comma + 1, rest.size()));
  }
  return shape;
}

NpyHeader parse_npy_header(const std::filesystem::path& file, const std::string& data) {
  if (data.size() < 10 || std::string_view(data).substr(0, 6) != kNpyMagic)
    file_error(file, "not a NumPy .npy file");
  const int major = static_cast<unsigned char>(data[6]);
  if (major < 1 || major > 3) file_error(file, "unsupported .npy version " + std::to_string(major));
  const std::size_t lenbytes = major == 1 ? 2 : 4;
  if (data.size() < 8 + lenbytes) file_error(file, "truncated .npy header");
  const std::size_t hlen =
      major == 1 ? load_le<std::uint16_t>(&data[8]) : load_le<std::uint32_t>(&data[8]);
  NpyHeader h;
  h.data_offset = 8 + lenbytes + hlen;
  if (data.size() < h.data_offset) file_error(file, "truncated .npy header");
  const std::string_view dict(data.data() + 8 + lenbytes, hlen);
  const auto d = dict_value(file, dict, "descr");
  const auto end = d.size() > 1 ? d.find(d[0], 1) : d.npos;
  if (end == d.npos || (d[0] != '\'' && d[0] != '"')) file_error(file, "npy descr is malformed");
  h.descr = std::string(d.substr(1, end - 1));
  h.fortran = dict_value(file, dict, "fortran_order").starts_with("True");
  h.shape = parse_shape(file, dict_value(file, dict, "shape"));
  return h;
}

double npy_value(const char* p, bool f4) {
  if (f4) return std::bit_cast<float>(load_le<std::uint32_t>(p));
  return std::bit_cast<double>(load_le<std::uint64_t>(p));
}

}  // namespace

Field surface_detail::parse_npy(const std::filesystem::path& path, const std::string& data,
                                const std::string& member) {
  const std::filesystem::path file = member.empty() ? path.string() : path.string() + ":" + member;
  const NpyHeader h = parse_npy_header(file, data);
  if (h.descr != "<f8" && h.descr != "<f4")
    file_error(file, "unsupported dtype '" + h.descr + "' (expected '<f8' or '<f4')");
  if (h.shape.size() != 2)
    file_error(file, "array is " + std::to_string(h.shape.size()) + "-D, expected 2-D");
  const long long ny = h.shape[0], nx = h.shape[1];
  const bool f4 = h.descr == "<f4";
  const std::size_t item = f4 ? 4 : 8;
  require_sane_shape(file, ny, nx);
  const std::size_t avail = data.size() - h.data_offset;
  if (std::size_t(nx) * std::size_t(ny) * item != avail)
    file_error(file, "data size does not match shape (" + std::to_string(ny) + ", " +
                         std::to_string(nx) + ")");
  Field z(nx, ny);
  const char* p = data.data() + h.data_offset;
  for (long long j = 0; j < ny; ++j)
    for (long long i = 0; i < nx; ++i) {
      const long long k = h.fortran ? j + ny * i : i + nx * j;  // element [j][i]
      z(i, j) = npy_value(p + k * item, f4);
    }
  return z;
}

std::vector<double> surface_detail::parse_npy_values(const std::filesystem::path& path,
                                                     const std::string& data,
                                                     const std::string& member) {
  const std::filesystem::path file = path.string() + ":" + member;
  const NpyHeader h = parse_npy_header(file, data);
  long long count = 1;
  for (const long long n : h.shape) count *= n;
  if (h.descr != "<f8" || h.shape.size() > 1 || count < 1 || count > 2 ||
      data.size() - h.data_offset != std::size_t(count) * 8)
    file_error(file, "must be a '<f8' scalar or 1 or 2 values (the spacing in m)");
  std::vector<double> v;
  for (long long k = 0; k < count; ++k)
    v.push_back(npy_value(data.data() + h.data_offset + 8 * k, false));
  return v;
}

void surface_detail::set_spacing(const std::filesystem::path& file,
                                 const std::vector<double>& values, const std::string& where,
                                 HeightMap& m) {
  for (const double v : values)
    if (!(v >= 1e-100 && v <= 1e100))
      file_error(file, where + " = " + format_number(v) +
                           " is not a length within [1e-100, 1e100] m (the spacing, SI)");
  m.dy = values.front();
  m.dx = values.back();
}

namespace {

Field load_npy(const std::filesystem::path& file) {
  return surface_detail::parse_npy(file, read_all(file));
}

void save_npy(const std::filesystem::path& file, const Field& z) {
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (" +
                     std::to_string(z.cols()) + ", " + std::to_string(z.rows()) + "), }";
  const std::size_t total = (10 + dict.size() + 1 + 63) / 64 * 64;  // incl. newline
  dict.append(total - 10 - dict.size() - 1, ' ').push_back('\n');
  std::string out(kNpyMagic);
  out += '\x01';
  out += '\x00';
  append_le(out, std::uint16_t(dict.size()));
  out += dict;
  for (Eigen::Index k = 0; k < z.size(); ++k)  // column-major (nx, ny) == C order [j][i]
    append_le(out, std::bit_cast<std::uint64_t>(z.data()[k]));
  std::ofstream os(file, std::ios::binary | std::ios::trunc);
  if (!os.write(out.data(), std::streamsize(out.size())) || !os.flush())
    file_error(file, "cannot write");
}

// ---------------------------------------------------------------------------------------
// Whitespace-separated text: one row (constant y) per line.

std::vector<double> parse_text_row(const std::filesystem::path& file, std::string_view line,
                                   int lineno) {
  std::vector<double> row;
  std::size_t pos = 0;
  while ((pos = line.find_first_not_of(" \t\r\v\f", pos)) != line.npos) {
    const std::size_t end = std::min(line.find_first_of(" \t\r\v\f", pos), line.size());
    std::string_view tok = line.substr(pos, end - pos);
    pos = end;
    const std::string_view num = tok.starts_with('+') ? tok.substr(1) : tok;
    double v = 0;
    const auto r = std::from_chars(num.data(), num.data() + num.size(), v);
    // The token is cut short (a comma-separated row is one token) and the separator named:
    // the whole row was quoted before, with no hint why it is not a number.
    if (r.ec != std::errc() || r.ptr != num.data() + num.size())
      file_error(file, "line " + std::to_string(lineno) + ": non-numeric value '" +
                           std::string(tok.substr(0, 40)) + (tok.size() > 40 ? "..." : "") +
                           "' (text height maps separate values by white space)");
    if (!std::isfinite(v))
      file_error(file, "line " + std::to_string(lineno) + ": NaN or Inf value");
    row.push_back(v);
  }
  return row;
}

Field load_text(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) file_error(file, "cannot open for reading");
  std::vector<std::vector<double>> rows;
  std::string line;
  int first_line = 0;
  for (int lineno = 1; std::getline(in, line); ++lineno) {
    if (lineno == 1) drop_utf8_bom(line);
    auto row = parse_text_row(file, std::string_view(line).substr(0, line.find('#')), lineno);
    if (row.empty()) continue;
    if (rows.empty()) first_line = lineno;
    if (!rows.empty() && row.size() != rows[0].size())
      file_error(file, "line " + std::to_string(lineno) + " has " + std::to_string(row.size()) +
                           " values, line " + std::to_string(first_line) + " has " +
                           std::to_string(rows[0].size()) + " (ragged rows)");
    rows.push_back(std::move(row));
  }
  if (in.bad()) file_error(file, "read error");
  if (rows.empty()) file_error(file, "no numbers in the file");
  Field z(Eigen::Index(rows[0].size()), Eigen::Index(rows.size()));
  for (std::size_t j = 0; j < rows.size(); ++j)
    for (std::size_t i = 0; i < rows[j].size(); ++i) z(i, j) = rows[j][i];
  return z;
}

void save_text(const std::filesystem::path& file, const Field& z) {
  std::ofstream os(file, std::ios::trunc);
  if (!os) file_error(file, "cannot open for writing");
  for (Eigen::Index j = 0; j < z.cols(); ++j) {
    for (Eigen::Index i = 0; i < z.rows(); ++i) {
      if (i) os.put(' ');
      os << format_number(z(i, j));
    }
    os.put('\n');
  }
  if (!os.flush()) file_error(file, "cannot write");
}

}  // namespace

Field load_height_map(const std::filesystem::path& file, const std::string& dataset) {
  return read_height_map(file, dataset, HeightLayout::yx).z;
}

HeightMap read_height_map(const std::filesystem::path& file, const std::string& dataset,
                          HeightLayout layout) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) file_error(file, "no such file");
  try {
    const std::string ext = lower_extension(file);
    HeightMap m;
    if (ext == ".x3p") {
      m = surface_detail::load_x3p(file);
    } else {
      m = ext == ".h5" || ext == ".hdf5" ? load_h5(file, dataset)
          : ext == ".npz"                ? surface_detail::load_npz(file, dataset)
          : ext == ".npy"                ? HeightMap{load_npy(file), {}, {}}
                                         : HeightMap{load_text(file), {}, {}};
      // Stored spacings follow the array's index order (set_spacing): yx puts y first.
      if (layout == HeightLayout::xy) m.z = Field(m.z.transpose()), std::swap(m.dx, m.dy);
    }
    require_finite(file, m.z);
    return m;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // bad_alloc for absurd shapes, filesystem errors
    file_error(file, e.what());
  }
}

void save_height_map(const std::filesystem::path& file, const Field& z,
                     std::optional<double> spacing) {
  if (z.size() == 0) file_error(file, "refusing to write an empty height map");
  require_finite(file, z);
  const std::string ext = lower_extension(file);
  if (ext == ".h5" || ext == ".hdf5")
    save_h5(file, z, spacing);
  else if (ext == ".npy")
    save_npy(file, z);
  else
    save_text(file, z);
}

}  // namespace fretbem
