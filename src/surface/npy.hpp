// Private to surface/: the .npy parser, shared by the .npy and .npz height-map readers.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "fretbem/elastic/grid.hpp"
#include "fretbem/surface/formats.hpp"

namespace fretbem::surface_detail {

/// Parses the bytes of a .npy file (v1-v3, 2-D '<f8'/'<f4', C or Fortran order) into
/// z(i, j) = array[j][i]. `file` (and `member`, for an .npz entry) name it in messages.
Field parse_npy(const std::filesystem::path& file, const std::string& data,
                const std::string& member = "");

/// Parses the bytes of a .npy file holding a grid spacing: a '<f8' scalar, or 1 or 2 values.
std::vector<double> parse_npy_values(const std::filesystem::path& file, const std::string& data,
                                     const std::string& member);

/// Sets m.dx and m.dy from stored spacing values: one value (square cells) or two in the
/// array's index order (first index, second index; layout yx: y then x). Refuses values that
/// are not lengths within [1e-100, 1e100] m, the bound of every dimensional input.
void set_spacing(const std::filesystem::path& file, const std::vector<double>& values,
                 const std::string& where, HeightMap& m);

/// Throws InputError "height map 'FILE': WHAT".
[[noreturn]] void file_error(const std::filesystem::path& file, const std::string& what);
/// Refuses empty arrays and shapes beyond 2^24 per side or 2^30 nodes (before allocating).
void require_sane_shape(const std::filesystem::path& file, unsigned long long ny,
                        unsigned long long nx);

}  // namespace fretbem::surface_detail
