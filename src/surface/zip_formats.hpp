// Private to surface/: height maps inside zip archives (ISO 25178-72 x3p, NumPy .npz), read
// with libzip; x3p's main.xml with pugixml.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "fretbem/surface/formats.hpp"

namespace fretbem::surface_detail {

/// A zip archive opened read-only. Refuses (InputError naming the file) archives with an
/// entry whose name could escape a folder (absolute, "..", backslash, drive letter), so no
/// name from the archive is ever trusted, even though nothing is extracted to disk.
class ZipArchive {
 public:
  explicit ZipArchive(const std::filesystem::path& file);
  ~ZipArchive();
  ZipArchive(const ZipArchive&) = delete;
  ZipArchive& operator=(const ZipArchive&) = delete;

  const std::vector<std::string>& names() const { return names_; }
  bool contains(const std::string& name) const;
  /// The uncompressed bytes of entry `name`; refuses entries larger than `max_bytes` (by the
  /// size the directory declares and by what inflating actually yields).
  std::string read(const std::string& name, unsigned long long max_bytes) const;

 private:
  struct Impl;
  std::filesystem::path file_;
  std::unique_ptr<Impl> impl_;
  std::vector<std::string> names_;
};

/// "a, b, c" (at most eight names, then "..."): the arrays a file holds, in one line.
std::string name_list(const std::vector<std::string>& names);

/// ISO 25178-72 x3p (FeatureType SUR): heights (m) with x fastest in the binary data, the
/// spacing from the CX/CY increments; MD5 of the point data and of main.xml checked.
HeightMap load_x3p(const std::filesystem::path& file);

/// NumPy .npz: the entry `member` (with or without ".npy"), or the only entry besides
/// `spacing` (the grid spacing in m, read into dx and dy when present).
HeightMap load_npz(const std::filesystem::path& file, const std::string& member);

}  // namespace fretbem::surface_detail
