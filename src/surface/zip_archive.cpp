// ZipArchive: libzip, read-only, with the entry-name and size checks of zip_formats.hpp.
#include <zip.h>

#include "npy.hpp"
#include "zip_formats.hpp"

namespace fretbem::surface_detail {

namespace {

// Names that would leave the extraction folder if anyone extracted them ("zip slip").
bool escapes(const std::string& name) {
  if (name.empty() || name[0] == '/' || name.find('\\') != std::string::npos) return true;
  if (name.size() > 1 && name[1] == ':') return true;  // C:...
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t end = std::min(name.find('/', start), name.size());
    if (name.compare(start, end - start, "..") == 0 && end - start == 2) return true;
    start = end + 1;
  }
  return false;
}

}  // namespace

struct ZipArchive::Impl {
  zip_t* za = nullptr;
  ~Impl() {
    if (za) zip_discard(za);
  }
};

ZipArchive::ZipArchive(const std::filesystem::path& file)
    : file_(file), impl_(std::make_unique<Impl>()) {
  int err = 0;
  impl_->za = zip_open(file.c_str(), ZIP_RDONLY, &err);
  if (!impl_->za) {
    zip_error_t e;
    zip_error_init_with_code(&e, err);
    const std::string msg = zip_error_strerror(&e);
    zip_error_fini(&e);
    file_error(file, "not a readable zip archive (" + msg + ")");
  }
  const zip_int64_t n = zip_get_num_entries(impl_->za, 0);
  constexpr zip_int64_t kMaxEntries = 4096;
  if (n < 0 || n > kMaxEntries) file_error(file, "implausible number of zip entries");
  for (zip_int64_t k = 0; k < n; ++k) {
    const char* name = zip_get_name(impl_->za, zip_uint64_t(k), ZIP_FL_ENC_GUESS);
    if (!name || escapes(name))
      file_error(file, std::string("zip entry '") + (name ? name : "?") +
                           "' points outside the archive (path traversal): refused");
    names_.emplace_back(name);
  }
}

ZipArchive::~ZipArchive() = default;

bool ZipArchive::contains(const std::string& name) const {
  return std::find(names_.begin(), names_.end(), name) != names_.end();
}

std::string ZipArchive::read(const std::string& name, unsigned long long max_bytes) const {
  if (escapes(name)) file_error(file_, "entry name '" + name + "' is a path traversal: refused");
  zip_stat_t st;
  zip_stat_init(&st);
  if (!contains(name) || zip_stat(impl_->za, name.c_str(), 0, &st) != 0 ||
      !(st.valid & ZIP_STAT_SIZE))
    file_error(file_, "no entry '" + name + "' in the archive");
  if (st.size > max_bytes)
    file_error(file_, "entry '" + name + "' declares " + std::to_string(st.size) +
                          " bytes, more than the " + std::to_string(max_bytes) + " expected");
  zip_file_t* zf = zip_fopen(impl_->za, name.c_str(), 0);
  if (!zf) file_error(file_, "cannot open entry '" + name + "'");
  std::string data(std::size_t(st.size), '\0');
  const zip_int64_t got = zip_fread(zf, data.data(), st.size);
  char extra = 0;
  const zip_int64_t more = zip_fread(zf, &extra, 1);  // a lying size field
  zip_fclose(zf);
  if (got != zip_int64_t(st.size) || more != 0)
    file_error(file_, "entry '" + name + "' is corrupt (size or CRC mismatch)");
  return data;
}

HeightMap load_npz(const std::filesystem::path& file, const std::string& member) {
  const ZipArchive zip(file);
  constexpr const char* kSpacing = "spacing.npy";  // metadata, not a height map
  std::vector<std::string> maps;
  for (const auto& n : zip.names())
    if (n != kSpacing) maps.push_back(n);
  std::string entry = member;
  if (entry.empty()) {
    if (maps.size() != 1)
      file_error(file, "holds " + std::to_string(maps.size()) + " arrays (" + name_list(maps) +
                           "): name one with surface.dataset");
    entry = maps[0];
  } else if (!entry.ends_with(".npy")) {
    entry += ".npy";
  }
  // 2^30 doubles (the largest sane map) plus a header.
  HeightMap m{parse_npy(file, zip.read(entry, (1ull << 33) + 65536), entry), {}, {}};
  if (zip.contains(kSpacing))
    set_spacing(file, parse_npy_values(file, zip.read(kSpacing, 4096), kSpacing), "entry 'spacing'",
                m);
  return m;
}

}  // namespace fretbem::surface_detail
