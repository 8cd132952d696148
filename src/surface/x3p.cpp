// ISO 25178-72 (XML 3D surface profile, x3p) reader: a zip with main.xml (pugixml) and the
// binary point data, little endian, x fastest. Untrusted input: no DTD or entity is ever
// expanded, entry names and sizes are checked before anything is allocated, and the MD5
// checksums the format carries are verified.
#include <bit>
#include <boost/uuid/detail/md5.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <pugixml.hpp>
#include <type_traits>

#include "npy.hpp"
#include "zip_formats.hpp"

namespace fretbem::surface_detail {

namespace {

constexpr unsigned long long kMaxXmlBytes = 16ull << 20;

std::string md5_hex(const std::string& data) {
  using boost::uuids::detail::md5;
  md5 h;
  h.process_bytes(data.data(), data.size());
  md5::digest_type d;
  h.get_digest(d);
  std::string hex;
  char buf[9];
  // Boost <= 1.85: four 32-bit words, most significant byte first; later: 16 bytes.
  if constexpr (sizeof(d[0]) == 4) {
    for (auto w : d) std::snprintf(buf, sizeof buf, "%08x", unsigned(w)), hex += buf;
  } else {
    for (auto b : d) std::snprintf(buf, sizeof buf, "%02x", unsigned(b)), hex += buf;
  }
  return hex;
}

std::string lower(std::string s) {
  for (auto& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

struct Axis {
  char type = 'D';
  double increment = 1.0, offset = 0.0;
  bool has_increment = false;
};

double number(const std::filesystem::path& file, const pugi::xml_node& n, const char* what) {
  const std::string t = n.text().as_string();
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || !std::isfinite(v))
    file_error(file, std::string("main.xml: ") + what + " '" + t + "' is not a number");
  return v;
}

Axis read_axis(const std::filesystem::path& file, const pugi::xml_node& axes, const char* name) {
  const pugi::xml_node a = axes.child(name);
  if (!a) file_error(file, std::string("main.xml: no Record1/Axes/") + name);
  Axis ax;
  const std::string type = a.child_value("DataType");
  if (type.size() == 1) ax.type = type[0];
  if (a.child("Increment")) {
    ax.increment = number(file, a.child("Increment"), "Increment"), ax.has_increment = true;
  }
  if (a.child("Offset")) ax.offset = number(file, a.child("Offset"), "Offset");
  if (std::string(name) != "CZ") {
    if (std::string(a.child_value("AxisType")) != "I")
      file_error(file, std::string("main.xml: ") + name +
                           " is not an incremental (equally spaced) axis; only those are read");
    if (!(ax.increment > 0)) file_error(file, std::string("main.xml: ") + name + " Increment <= 0");
  }
  return ax;
}

unsigned long long size_of(const std::filesystem::path& file, const pugi::xml_node& dim,
                           const char* name) {
  const std::string t = dim.child_value(name);
  char* end = nullptr;
  const unsigned long long v = std::strtoull(t.c_str(), &end, 10);
  if (t.empty() || *end != '\0' || t[0] == '-')
    file_error(file,
               std::string("main.xml: MatrixDimension/") + name + " '" + t + "' is not a count");
  return v;
}

template <class U>
U little_endian(const char* p) {
  U v = 0;
  for (std::size_t b = 0; b < sizeof(U); ++b) v |= U(static_cast<unsigned char>(p[b])) << (8 * b);
  return v;
}

double sample(const char* p, char type) {
  switch (type) {
    case 'I':
      return double(std::bit_cast<std::int16_t>(little_endian<std::uint16_t>(p)));
    case 'L':
      return double(std::bit_cast<std::int32_t>(little_endian<std::uint32_t>(p)));
    case 'F':
      return double(std::bit_cast<float>(little_endian<std::uint32_t>(p)));
    default:
      return std::bit_cast<double>(little_endian<std::uint64_t>(p));
  }
}

std::size_t item_size(const std::filesystem::path& file, char type) {
  switch (type) {
    case 'I':
      return 2;
    case 'L':
    case 'F':
      return 4;
    case 'D':
      return 8;
  }
  file_error(file, std::string("main.xml: CZ DataType '") + type + "' (expected I, L, F or D)");
}

pugi::xml_document parse_main_xml(const std::filesystem::path& file, const std::string& xml) {
  // A DTD can declare entities (billion laughs, external files): refuse any, parsed or not.
  if (xml.find("<!DOCTYPE") != std::string::npos || xml.find("<!ENTITY") != std::string::npos)
    file_error(file, "main.xml declares a DTD or entities: refused");
  pugi::xml_document doc;
  const auto r = doc.load_buffer(xml.data(), xml.size(), pugi::parse_default | pugi::parse_doctype);
  if (!r) file_error(file, std::string("main.xml is not well-formed XML: ") + r.description());
  for (const auto& n : doc.children())
    if (n.type() == pugi::node_doctype) file_error(file, "main.xml declares a DTD: refused");
  return doc;
}

void check_main_xml_checksum(const std::filesystem::path& file, const ZipArchive& zip,
                             const pugi::xml_node& root, const std::string& xml) {
  const std::string name = root.child("Record4").child_value("ChecksumFile");
  if (name.empty() || !zip.contains(name)) return;  // optional in practice
  const std::string line = zip.read(name, 4096);
  if (lower(line.substr(0, 32)) != md5_hex(xml))
    file_error(file, "main.xml does not match its MD5 checksum in " + name);
}

}  // namespace

HeightMap load_x3p(const std::filesystem::path& file) {
  const ZipArchive zip(file);
  const std::string xml = zip.read("main.xml", kMaxXmlBytes);
  const pugi::xml_document doc = parse_main_xml(file, xml);
  const pugi::xml_node root = doc.document_element();
  const pugi::xml_node r1 = root.child("Record1"), r3 = root.child("Record3");
  if (!r1 || !r3) file_error(file, "main.xml has no Record1/Record3 (not an ISO 25178-72 file)");
  if (std::string(r1.child_value("FeatureType")) != "SUR")
    file_error(file, std::string("main.xml: FeatureType '") + r1.child_value("FeatureType") +
                         "' (only areal surfaces, SUR, are height maps)");
  check_main_xml_checksum(file, zip, root, xml);
  const pugi::xml_node axes = r1.child("Axes");
  const Axis cx = read_axis(file, axes, "CX"), cy = read_axis(file, axes, "CY"),
             cz = read_axis(file, axes, "CZ");
  const pugi::xml_node dim = r3.child("MatrixDimension");
  const auto nx = size_of(file, dim, "SizeX"), ny = size_of(file, dim, "SizeY");
  if (size_of(file, dim, "SizeZ") != 1) file_error(file, "main.xml: SizeZ must be 1 (one layer)");
  require_sane_shape(file, ny, nx);
  const pugi::xml_node link = r3.child("DataLink");
  if (!link) file_error(file, "main.xml: no Record3/DataLink (inline DataList is not read)");
  const std::string bin = link.child_value("PointDataLink");
  const std::size_t item = item_size(file, cz.type);
  const std::string data = zip.read(bin, nx * ny * item);
  if (data.size() != nx * ny * item)
    file_error(file, bin + " holds " + std::to_string(data.size()) +
                         " bytes, SizeX x SizeY = " + std::to_string(nx) + " x " +
                         std::to_string(ny) + " points need " + std::to_string(nx * ny * item));
  const std::string sum = lower(link.child_value("MD5ChecksumPointData"));
  if (sum.empty()) file_error(file, "main.xml: no MD5ChecksumPointData for " + bin);
  if (sum != md5_hex(data)) file_error(file, bin + " does not match its MD5 checksum");
  HeightMap m{Field(Eigen::Index(nx), Eigen::Index(ny)), cx.increment, cy.increment};
  const bool scaled = cz.type == 'I' || cz.type == 'L' || cz.has_increment;
  for (std::size_t k = 0; k < nx * ny; ++k) {  // x fastest: Eigen's column-major (nx, ny)
    const double v = sample(data.data() + k * item, cz.type);
    m.z.data()[k] = scaled ? v * cz.increment + cz.offset : v + cz.offset;
  }
  return m;
}

}  // namespace fretbem::surface_detail
