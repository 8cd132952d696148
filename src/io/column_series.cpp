#include "fretbem/io/column_series.hpp"

#include <hdf5_hl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "fretbem/io/result_metadata.hpp"

namespace fretbem::io {

namespace {

using hdf5::checked;

hdf5::Group create_group(hid_t file, const std::string& what) {
  if (hdf5::exists(file, ColumnSeries::group_name))
    checked(H5Ldelete(file, ColumnSeries::group_name, H5P_DEFAULT), what,
            std::string("replace ") + ColumnSeries::group_name);
  hdf5::Plist lcpl(checked(H5Pcreate(H5P_LINK_CREATE), what, "create a property list"));
  checked(H5Pset_create_intermediate_group(lcpl.get(), 1), what, "set up group creation");
  return hdf5::Group(
      checked(H5Gcreate2(file, ColumnSeries::group_name, lcpl.get(), H5P_DEFAULT, H5P_DEFAULT),
              what, std::string("create ") + ColumnSeries::group_name));
}

std::size_t step_column(const std::vector<std::string>& columns) {
  return std::size_t(std::find(columns.begin(), columns.end(), "step") - columns.begin());
}

hsize_t length(hid_t dataset) {
  hdf5::Space s(H5Dget_space(dataset));
  hsize_t n = 0;
  if (!s.valid() || H5Sget_simple_extent_ndims(s.get()) != 1) return hsize_t(-1);
  H5Sget_simple_extent_dims(s.get(), &n, nullptr);
  return n;
}

}  // namespace

ColumnSeries ColumnSeries::create(hid_t file, const std::vector<std::string>& columns,
                                  const std::string& what) {
  ColumnSeries s;
  s.what_ = what;
  s.step_column_ = step_column(columns);
  if (s.step_column_ == columns.size()) return s;
  const hdf5::Group g = create_group(file, what);
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const bool is_step = c == s.step_column_;
    s.datasets_.push_back(create_extendible_vector(g.get(), columns[c],
                                                   is_step ? H5T_STD_I64LE : H5T_IEEE_F64LE, what));
    write_string_attribute(s.datasets_.back().get(), "units", column_units(columns[c]), what);
  }
  const hid_t step = s.datasets_[s.step_column_].get();
  checked(H5DSset_scale(step, "step"), what, "make step a dimension scale");
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (c == s.step_column_) continue;
    const hid_t d = s.datasets_[c].get();
    checked(H5DSattach_scale(d, step, 0), what, "attach step to " + columns[c]);
    // The load-path time labels every row as in /series/fields (xarray: a coordinate).
    if (columns[c] != "time") write_string_attribute(d, "coordinates", "time", what);
  }
  return s;
}

ColumnSeries ColumnSeries::open_or_rebuild(hid_t file, const std::vector<std::string>& columns,
                                           const std::vector<double>& table,
                                           const std::string& what) {
  const hsize_t rows = columns.empty() ? 0 : table.size() / columns.size();
  if (step_column(columns) == columns.size()) return {};
  if (hdf5::exists(file, group_name)) {
    ColumnSeries s;
    s.what_ = what, s.step_column_ = step_column(columns), s.rows_ = rows;
    hdf5::Group g(H5Gopen2(file, group_name, H5P_DEFAULT));
    for (const auto& c : columns) {
      hdf5::Dataset d(
          g.valid() && hdf5::exists(g.get(), c) ? H5Dopen2(g.get(), c.c_str(), H5P_DEFAULT) : -1);
      if (!d.valid() || length(d.get()) != rows) break;
      s.datasets_.push_back(std::move(d));
    }
    hdf5::last_error();  // clears what a missing or torn member left on the stack
    if (s.datasets_.size() == columns.size()) return s;
  }
  ColumnSeries s = create(file, columns, what);
  for (hsize_t r = 0; r < rows; ++r)
    s.append({table.begin() + std::ptrdiff_t(r * columns.size()),
              table.begin() + std::ptrdiff_t((r + 1) * columns.size())});
  return s;
}

void ColumnSeries::append(const std::vector<double>& row) {
  if (!valid()) return;
  if (row.size() != datasets_.size())
    throw std::invalid_argument(what_ + ": row of " + std::to_string(row.size()) + " values for " +
                                std::to_string(datasets_.size()) + " columns");
  const hsize_t n = rows_ + 1, one = 1;
  hdf5::Space mem(checked(H5Screate_simple(1, &one, nullptr), what_, "create a dataspace"));
  for (std::size_t c = 0; c < row.size(); ++c) {
    const hid_t d = datasets_[c].get();
    checked(H5Dset_extent(d, &n), what_, "extend " + std::string(group_name));
    hdf5::Space file_space(checked(H5Dget_space(d), what_, "read a dataspace"));
    checked(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &rows_, nullptr, &one, nullptr),
            what_, "select a row");
    const std::int64_t step = std::llround(row[c]);
    const bool is_step = c == step_column_;
    checked(H5Dwrite(d, is_step ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE, mem.get(), file_space.get(),
                     H5P_DEFAULT,
                     is_step ? static_cast<const void*>(&step) : static_cast<const void*>(&row[c])),
            what_, "append to " + std::string(group_name));
  }
  rows_ = n;
}

void ColumnSeries::truncate(std::size_t rows) {
  if (rows >= rows_) return;
  const hsize_t n = rows;
  for (const auto& d : datasets_)
    checked(H5Dset_extent(d.get(), &n), what_, "truncate " + std::string(group_name));
  rows_ = n;
}

}  // namespace fretbem::io
