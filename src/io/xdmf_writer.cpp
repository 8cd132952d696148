// XDMF 3 sidecar of result.h5: read the file's structure back (not the writer's memory, so a
// resumed run describes the steps of its first part too) and write the XML light data.
#include "fretbem/io/xdmf_writer.hpp"

#include <hdf5.h>

#include <array>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <vector>

#include "fretbem/core/format.hpp"
#include "fretbem/core/hdf5.hpp"

namespace fretbem::io {

namespace fs = std::filesystem;

namespace {

struct Item {
  std::string path;  ///< dataset path in the HDF5 file
  std::string name;  ///< attribute name shown by the reader
  std::array<hsize_t, 2> dims{};
  bool byte = false;  ///< uint8 (state) rather than float64
};

struct Step {
  std::string name;
  double time = 0.0;
  std::vector<Item> items;
};

struct Mesh {
  std::array<double, 2> shape{}, spacing{}, origin{};  // (y, x) order, as in the file
};

[[noreturn]] void fail(const fs::path& h5, const std::string& what) {
  throw std::runtime_error(h5.string() + ": cannot write the XDMF description: " + what + ": " +
                           hdf5::last_error());
}

std::array<double, 2> read_pair(const fs::path& h5, hid_t root, const char* name) {
  hdf5::Attribute a(H5Aopen(root, name, H5P_DEFAULT));
  std::array<double, 2> v{};
  if (!a.valid()) fail(h5, std::string("no attribute ") + name);
  hdf5::Space s(H5Aget_space(a.get()));
  if (H5Sget_simple_extent_npoints(s.get()) != 2 ||
      H5Aread(a.get(), H5T_NATIVE_DOUBLE, v.data()) < 0)
    fail(h5, std::string("bad attribute ") + name);
  return v;
}

double read_time(hid_t group) {
  double t = 0.0;
  hdf5::Attribute a(H5Aopen(group, "time", H5P_DEFAULT));
  if (a.valid()) H5Aread(a.get(), H5T_NATIVE_DOUBLE, &t);
  return t;
}

// A 2-D numeric dataset at `path` as an item, or nothing.
std::optional<Item> read_item(hid_t file, const std::string& path, const std::string& name) {
  hdf5::Dataset d(H5Dopen2(file, path.c_str(), H5P_DEFAULT));
  if (!d.valid()) return std::nullopt;
  hdf5::Space s(H5Dget_space(d.get()));
  hdf5::Type t(H5Dget_type(d.get()));
  Item it{path, name};
  if (H5Sget_simple_extent_ndims(s.get()) != 2) return std::nullopt;
  H5Sget_simple_extent_dims(s.get(), it.dims.data(), nullptr);
  const H5T_class_t cls = H5Tget_class(t.get());
  if (cls != H5T_FLOAT && cls != H5T_INTEGER) return std::nullopt;
  it.byte = cls == H5T_INTEGER && H5Tget_size(t.get()) == 1;
  return it;
}

herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

// Link names under `group`, in name order (step_000010 sorts after step_000009).
std::vector<std::string> list(hid_t file, const std::string& group) {
  std::vector<std::string> names;
  hdf5::Group g(H5Gopen2(file, group.c_str(), H5P_DEFAULT));
  if (!g.valid()) return {};
  hsize_t idx = 0;
  H5Literate(g.get(), H5_INDEX_NAME, H5_ITER_INC, &idx, collect_name, &names);
  return names;
}

std::vector<Step> read_steps(hid_t file, const std::string& parent) {
  std::vector<Step> steps;
  std::optional<Item> surface = read_item(file, "/surface/initial", "surface_initial");
  for (const auto& name : list(file, parent)) {
    const std::string gpath = parent + "/" + name;
    hdf5::Group g(H5Gopen2(file, gpath.c_str(), H5P_DEFAULT));
    if (!g.valid()) continue;  // a dataset beside the step groups (e.g. /wear/final_...)
    Step st{name, read_time(g.get()), {}};
    for (const auto& field : list(file, gpath))
      if (auto it = read_item(file, gpath + "/" + field, field)) st.items.push_back(*it);
    if (surface) st.items.push_back(*surface);
    steps.push_back(std::move(st));
  }
  return steps;
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

std::string pair(const std::array<double, 2>& v) {
  return format_number(v[0]) + " " + format_number(v[1]);
}

// The map is a 3DCoRectMesh one node thick in z, at z = 0: ParaView 5.11 puts a 2DCoRectMesh
// in its y-z plane (fretbem's x along its Y), edge-on to its default view, which looks down z.
// Flat in z, ParaView's Xdmf3 readers give a 2-D image in the x-y plane, which its default
// view shows as a map; a slab one cell thick would show as an outline. (ParaView's legacy
// Xdmf2 "XDMF Reader" counts no cells in a mesh one node thick.) Values slowest axis first:
// z, y, x.
void write_step(std::ostream& o, const Step& st, const Mesh& m, const std::string& h5name) {
  const long ny = long(m.shape[0]), nx = long(m.shape[1]);
  const double dz = m.spacing[1];  // unused by a mesh one node thick; readers want dz > 0
  o << "      <Grid Name=\"" << xml_escape(st.name) << "\" GridType=\"Uniform\">\n"
    << "        <Time Value=\"" << format_number(st.time) << "\"/>\n"
    << "        <Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"1 " << ny + 1 << " " << nx + 1
    << "\"/>\n"
    << "        <Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
    << "          <DataItem Format=\"XML\" NumberType=\"Float\" Precision=\"8\" "
       "Dimensions=\"3\">"
    << "0 " << pair(m.origin) << "</DataItem>\n"
    << "          <DataItem Format=\"XML\" NumberType=\"Float\" Precision=\"8\" "
       "Dimensions=\"3\">"
    << format_number(dz) << " " << pair(m.spacing) << "</DataItem>\n"
    << "        </Geometry>\n";
  for (const auto& it : st.items) {
    if (long(it.dims[0]) != ny || long(it.dims[1]) != nx) continue;  // not on the grid
    o << "        <Attribute Name=\"" << xml_escape(it.name)
      << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
      << "          <DataItem Format=\"HDF\" NumberType=\"" << (it.byte ? "UChar" : "Float")
      << "\" Precision=\"" << (it.byte ? 1 : 8) << "\" Dimensions=\"" << ny << " " << nx << "\">"
      << xml_escape(h5name) << ":" << xml_escape(it.path) << "</DataItem>\n"
      << "        </Attribute>\n";
  }
  o << "      </Grid>\n";
}

}  // namespace

bool write_xdmf(const fs::path& h5, const fs::path& xmf, const std::string& parent) {
  hdf5::Quiet quiet;
  hdf5::File f(H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!f.valid()) fail(h5, "cannot open");
  hdf5::Group root(H5Gopen2(f.get(), "/", H5P_DEFAULT));
  Mesh m;
  m.shape = read_pair(h5, root.get(), "grid_shape");
  m.spacing = read_pair(h5, root.get(), "grid_spacing");
  // grid_origin is the centre of cell (0, 0); the mesh origin is that cell's corner.
  const auto centre = read_pair(h5, root.get(), "grid_origin");
  m.origin = {centre[0] - 0.5 * m.spacing[0], centre[1] - 0.5 * m.spacing[1]};
  const std::vector<Step> steps = read_steps(f.get(), parent);
  if (steps.empty()) return false;
  const fs::path tmp = xmf.string() + ".tmp";
  {
    std::ofstream o(tmp, std::ios::trunc);
    o << "<?xml version=\"1.0\" ?>\n"
      << "<Xdmf Version=\"3.0\">\n  <Domain>\n"
      << "    <Grid Name=\"" << xml_escape(parent.substr(1))
      << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& st : steps) write_step(o, st, m, h5.filename().string());
    o << "    </Grid>\n  </Domain>\n</Xdmf>\n";
    if (!o.flush()) throw std::runtime_error(tmp.string() + ": cannot write");
  }
  fs::rename(tmp, xmf);
  return true;
}

}  // namespace fretbem::io
