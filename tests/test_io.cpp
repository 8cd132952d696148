// Output writers: CSV rows read back exactly (and `nan`); HDF5 fields, text, step groups and
// the time series read back with the HDF5 C API, in the documented orientation.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <hdf5_hl.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "fretbem/io/csv_writer.hpp"
#include "fretbem/io/hdf5_writer.hpp"
#include "support/temp_dir.hpp"

namespace fs = std::filesystem;
using fretbem::Field;
using fretbem::InputError;
using fretbem::io::CsvWriter;
using fretbem::io::Hdf5Writer;
using fretbem_test::TempDir;

namespace {

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
  return out;
}

/// Read-only access for checking what the writer produced.
struct H5Reader {
  hid_t file;
  explicit H5Reader(const fs::path& p) : file(H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {}
  ~H5Reader() { H5Fclose(file); }

  std::vector<hsize_t> dims(const std::string& name) const {
    const hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    const hid_t s = H5Dget_space(d);
    std::vector<hsize_t> out(static_cast<std::size_t>(H5Sget_simple_extent_ndims(s)));
    H5Sget_simple_extent_dims(s, out.data(), nullptr);
    H5Sclose(s);
    H5Dclose(d);
    return out;
  }
  std::vector<double> doubles(const std::string& name) const {
    std::size_t n = 1;
    for (auto d : dims(name)) n *= d;
    std::vector<double> out(n);
    const hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    EXPECT_GE(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), 0);
    H5Dclose(d);
    return out;
  }
  std::string text(const std::string& name) const {
    const hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, H5T_CSET_UTF8);  // HDF5 converts no character sets: match the file's
    char* p = nullptr;
    EXPECT_GE(H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, &p), 0);
    std::string out = p ? p : "";
    H5free_memory(p);
    H5Tclose(t);
    H5Dclose(d);
    return out;
  }
  std::vector<std::string> string_attribute(const std::string& obj, const char* name) const {
    const hid_t a = H5Aopen_by_name(file, obj.c_str(), name, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t s = H5Aget_space(a);
    std::vector<char*> raw(static_cast<std::size_t>(H5Sget_simple_extent_npoints(s)));
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, H5T_CSET_UTF8);  // HDF5 converts no character sets: match the file's
    EXPECT_GE(H5Aread(a, t, raw.data()), 0);
    std::vector<std::string> out;
    for (char* c : raw) out.emplace_back(c ? c : ""), H5free_memory(c);
    H5Tclose(t);
    H5Sclose(s);
    H5Aclose(a);
    return out;
  }
  /// A scalar fixed-length string attribute (units, coordinates).
  std::string text_attribute(const std::string& obj, const char* name) const {
    const hid_t a = H5Aopen_by_name(file, obj.c_str(), name, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t t = H5Aget_type(a);
    std::string out(H5Tget_size(t), '\0');
    EXPECT_GE(H5Aread(a, t, out.data()), 0);
    H5Tclose(t);
    H5Aclose(a);
    return out.substr(0, out.find('\0'));
  }
  template <class T>
  T scalar_attribute(const std::string& obj, const char* name, hid_t mem_type) const {
    T v{};
    const hid_t a = H5Aopen_by_name(file, obj.c_str(), name, H5P_DEFAULT, H5P_DEFAULT);
    EXPECT_GE(H5Aread(a, mem_type, &v), 0);
    H5Aclose(a);
    return v;
  }
  bool chunked_and_deflated(const std::string& name) const {
    const hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    const hid_t p = H5Dget_create_plist(d);
    bool deflate = false;
    for (int k = 0; k < H5Pget_nfilters(p); ++k) {
      unsigned flags = 0, conf = 0;
      size_t n = 0;
      deflate |= H5Pget_filter2(p, static_cast<unsigned>(k), &flags, &n, nullptr, 0, nullptr,
                                &conf) == H5Z_FILTER_DEFLATE;
    }
    const bool chunked = H5Pget_layout(p) == H5D_CHUNKED;
    H5Pclose(p);
    H5Dclose(d);
    return chunked && deflate;
  }
};

Field ramp_field(int nx, int ny) {
  Field f(nx, ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) f(i, j) = 1000.0 * i + j + 0.125;
  return f;
}

}  // namespace

TEST(Csv, RoundTripsFullPrecisionAndNan) {
  const TempDir tmp("io");
  const fs::path dir = tmp.path() / "a" / "b";  // created on demand
  const std::vector<double> row1 = {0.0, 1.0 / 3.0, std::nan(""), 1e-300, -2.5e17};
  const std::vector<double> row2 = {1.0, -std::nan(""), std::numeric_limits<double>::infinity(),
                                    std::nextafter(1.0, 2.0), -0.0};
  {
    CsvWriter csv(dir, "series", {"step", "x", "kx", "tiny", "big"});
    EXPECT_EQ(csv.path(), dir / "series.csv");
    csv.row(row1);
    // Flushed per row: readable before the writer closes.
    EXPECT_EQ(lines_of(dir / "series.csv").size(), 2u);
    csv.row(row2);
    EXPECT_THROW(csv.row({1.0}), std::invalid_argument);
  }
  const auto lines = lines_of(dir / "series.csv");
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "step,x,kx,tiny,big");
  EXPECT_EQ(split(lines[1])[2], "nan");
  EXPECT_EQ(split(lines[2])[1], "nan");
  EXPECT_EQ(split(lines[2])[2], "inf");
  for (int r = 0; r < 2; ++r) {
    const auto cells = split(lines[r + 1]);
    const auto& expect = r == 0 ? row1 : row2;
    ASSERT_EQ(cells.size(), expect.size());
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const double v = std::strtod(cells[k].c_str(), nullptr);
      if (std::isnan(expect[k]))
        EXPECT_TRUE(std::isnan(v));
      else
        EXPECT_EQ(v, expect[k]) << cells[k];
    }
  }
}

TEST(Csv, AppendContinuesAndCutsATornLine) {
  const TempDir tmp("io");
  { CsvWriter(tmp.path(), "t", {"a", "b"}).row({1, 2}); }
  { std::ofstream(tmp.path() / "t.csv", std::ios::app) << "3,4"; }  // killed mid-row
  {
    CsvWriter csv(tmp.path(), "t", {"a", "b"}, /*append=*/true);
    csv.row({5, 6});
  }
  EXPECT_EQ(lines_of(tmp.path() / "t.csv"), (std::vector<std::string>{"a,b", "1,2", "5,6"}));
  EXPECT_THROW(CsvWriter(tmp.path(), "t", {"a", "c"}, true), InputError);
}

TEST(Csv, UnopenablePathIsAnInputErrorNamingIt) {
  const TempDir tmp("io");
  std::ofstream(tmp.path() / "file") << "x";
  try {
    CsvWriter(tmp.path() / "file", "t", {"a"});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((tmp.path() / "file").string()), std::string::npos);
  }
}

TEST(Hdf5, FieldOrientationValuesAndCompression) {
  const TempDir tmp("io");
  const Field small = ramp_field(5, 3);
  const Field big = ramp_field(300, 200);
  {
    Hdf5Writer h5(tmp.path() / "run");
    EXPECT_EQ(h5.path(), tmp.path() / "run" / "result.h5");
    h5.write_field("/surface/initial", small);
    h5.write_field("/big", big);
    h5.write_field("/surface/initial", small * 2.0);  // replacing is allowed
  }
  H5Reader r(tmp.path() / "run" / "result.h5");
  ASSERT_GE(r.file, 0);
  EXPECT_EQ(r.dims("/surface/initial"), (std::vector<hsize_t>{3, 5}));  // {ny, nx}
  const auto v = r.doubles("/surface/initial");
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i) EXPECT_EQ(v[j * 5 + i], 2.0 * small(i, j));  // a[j, i] = f(i, j)
  const auto b = r.doubles("/big");
  EXPECT_EQ(b[199 * 300 + 299], big(299, 199));
  EXPECT_EQ(b[7 * 300 + 11], big(11, 7));
  EXPECT_TRUE(r.chunked_and_deflated("/big"));
}

TEST(Hdf5, TextStepFieldsAndTimeseries) {
  const TempDir tmp("io");
  const std::string scenario = "[material]\nE = 1e9\n# ünïcode\n";
  {
    Hdf5Writer h5(tmp.path());
    h5.write_text("/scenario", scenario);
    h5.write_step_fields(7, 0.25, {{"pressure", ramp_field(4, 2)}, {"state", Field::Ones(4, 2)}});
    h5.start_timeseries({"step", "time", "Fx"});
    h5.append_row({0, 0.0, 0.0});
    h5.append_row({1, 0.5, std::nan("")});
    EXPECT_THROW(h5.append_row({1.0, 2.0}), std::invalid_argument);
    EXPECT_EQ(h5.timeseries_rows(), 2u);
  }
  H5Reader r(tmp.path() / "result.h5");
  EXPECT_EQ(r.text("/scenario"), scenario);
  EXPECT_EQ(r.dims("/fields/step_000007/pressure"), (std::vector<hsize_t>{2, 4}));
  EXPECT_EQ(r.doubles("/fields/step_000007/pressure")[1 * 4 + 3], ramp_field(4, 2)(3, 1));
  EXPECT_EQ(r.scalar_attribute<std::int64_t>("/fields/step_000007", "step", H5T_NATIVE_INT64), 7);
  EXPECT_EQ(r.scalar_attribute<double>("/fields/step_000007", "time", H5T_NATIVE_DOUBLE), 0.25);
  EXPECT_EQ(r.dims("/timeseries"), (std::vector<hsize_t>{2, 3}));
  const auto ts = r.doubles("/timeseries");
  EXPECT_EQ(ts[3], 1.0);
  EXPECT_EQ(ts[4], 0.5);
  EXPECT_TRUE(std::isnan(ts[5]));
  EXPECT_EQ(r.string_attribute("/timeseries", "columns"),
            (std::vector<std::string>{"step", "time", "Fx"}));
}

TEST(Hdf5, ReadableWhileStillOpen) {
  const TempDir tmp("io");
  Hdf5Writer h5(tmp.path());
  h5.start_timeseries({"a"});
  h5.append_row({42.0});
  // Flushed after each write: another handle sees the row although the writer is open.
  H5Reader r(tmp.path() / "result.h5");
  ASSERT_GE(r.file, 0);
  EXPECT_EQ(r.doubles("/timeseries"), (std::vector<double>{42.0}));
}

TEST(Hdf5, OpenExistingAppendsAndTruncates) {
  const TempDir tmp("io");
  {
    Hdf5Writer h5(tmp.path());
    h5.start_timeseries({"step", "Fx"});
    for (int k = 0; k < 5; ++k) h5.append_row({double(k), 10.0 * k});
    h5.write_step_fields(3, 3.0, {{"pressure", ramp_field(2, 2)}});
  }
  {
    Hdf5Writer h5 = Hdf5Writer::open_existing(tmp.path());
    EXPECT_EQ(h5.timeseries_rows(), 5u);
    EXPECT_EQ(h5.timeseries_columns(), (std::vector<std::string>{"step", "Fx"}));
    h5.truncate_timeseries(3);
    h5.append_row({3.0, -1.0});
    h5.write_step_fields(3, 3.0, {{"pressure", ramp_field(2, 2) * 0.0}});  // replaced
  }
  H5Reader r(tmp.path() / "result.h5");
  EXPECT_EQ(r.dims("/timeseries"), (std::vector<hsize_t>{4, 2}));
  EXPECT_EQ(r.doubles("/timeseries"), (std::vector<double>{0, 0, 1, 10, 2, 20, 3, -1}));
  EXPECT_EQ(r.doubles("/fields/step_000003/pressure"), (std::vector<double>(4, 0.0)));
  // The per-column variables follow the truncation and the appended row.
  EXPECT_EQ(r.doubles("/series/timeseries/step"), (std::vector<double>{0, 1, 2, 3}));
  EXPECT_EQ(r.doubles("/series/timeseries/Fx"), (std::vector<double>{0, 10, 20, -1}));
}

// netCDF-4 readers see one variable per column: /series/timeseries/COLUMN over the dimension
// scale `step` (int64), with the column's units, labelled by the load-path time.
TEST(Hdf5, TimeseriesColumnsAreVariablesOverStep) {
  const TempDir tmp("io");
  {
    Hdf5Writer h5(tmp.path());
    h5.start_timeseries({"step", "time", "Fx", "Ux", "contact_area"});
    h5.append_row({0, 0.0, 0.0, 0.0, 1e-8});
    h5.append_row({1, 0.5, 2.5, 1e-6, std::nan("")});
  }
  H5Reader r(tmp.path() / "result.h5");
  const std::string g = "/series/timeseries/";
  EXPECT_EQ(r.dims(g + "step"), (std::vector<hsize_t>{2}));
  EXPECT_EQ(r.doubles(g + "time"), (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(r.doubles(g + "Fx"), (std::vector<double>{0.0, 2.5}));
  EXPECT_EQ(r.doubles(g + "Ux"), (std::vector<double>{0.0, 1e-6}));
  EXPECT_TRUE(std::isnan(r.doubles(g + "contact_area")[1]));
  const hid_t step = H5Dopen2(r.file, (g + "step").c_str(), H5P_DEFAULT);
  const hid_t type = H5Dget_type(step);
  EXPECT_TRUE(H5Tequal(type, H5T_STD_I64LE) > 0);
  EXPECT_EQ(H5DSis_scale(step), 1);
  const hid_t fx = H5Dopen2(r.file, (g + "Fx").c_str(), H5P_DEFAULT);
  EXPECT_EQ(H5DSis_attached(fx, step, 0), 1);
  H5Dclose(fx), H5Tclose(type), H5Dclose(step);
  EXPECT_EQ(r.text_attribute(g + "Fx", "units"), "N");
  EXPECT_EQ(r.text_attribute(g + "Ux", "units"), "m");
  EXPECT_EQ(r.text_attribute(g + "contact_area", "units"), "m2");
  EXPECT_EQ(r.text_attribute(g + "Fx", "coordinates"), "time");
}

// A file without the per-column variables (format 3) gets them from /timeseries on reopening.
TEST(Hdf5, OpenExistingRebuildsTheColumnVariables) {
  const TempDir tmp("io");
  {
    Hdf5Writer h5(tmp.path());
    h5.start_timeseries({"step", "Fx"});
    for (int k = 0; k < 3; ++k) h5.append_row({double(k), 10.0 * k});
  }
  {
    const hid_t f = H5Fopen((tmp.path() / "result.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(H5Ldelete(f, "/series/timeseries", H5P_DEFAULT), 0);
    H5Fclose(f);
  }
  {
    Hdf5Writer h5 = Hdf5Writer::open_existing(tmp.path());
    h5.append_row({3.0, 30.0});
  }
  H5Reader r(tmp.path() / "result.h5");
  EXPECT_EQ(r.doubles("/series/timeseries/step"), (std::vector<double>{0, 1, 2, 3}));
  EXPECT_EQ(r.doubles("/series/timeseries/Fx"), (std::vector<double>{0, 10, 20, 30}));
}

// A run may save any number of steps: 10 000 saved steps of an 8 x 8 grid (with the x/y
// scales of a run's file) are written, and every one reads back as written, from the series
// that stacks them and from step groups on both sides of 4096 (attaching shared scales to
// every step's fields failed near there).
TEST(Hdf5, TenThousandSavedStepsReadBack) {
  const TempDir tmp("io");
  const int steps = 10000, n = 8;
  const auto pressure = [&](int k) { return Field(ramp_field(n, n) + 1e-3 * k); };
  const auto state = [&](int k) { return Field(Field::Constant(n, n, double(k % 3))); };
  {
    Hdf5Writer h5(tmp.path() / "run");
    h5.describe(fretbem::Grid::square(n, 1e-3), tmp.path() / "run");
    for (int k = 0; k < steps; ++k)
      h5.write_step_fields(k, 0.5 * k, {{"pressure", pressure(k)}, {"state", state(k)}});
  }
  std::vector<std::string> groups;
  for (int k = 0; k < steps; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "/fields/step_%06d", k);
    groups.emplace_back(name);
  }
  for (const char* dir : {"run"}) {
    H5Reader r(tmp.path() / dir / "result.h5");
    ASSERT_GE(r.file, 0);
    EXPECT_EQ(r.dims("/series/fields/pressure"), (std::vector<hsize_t>{hsize_t(steps), 8, 8}));
    const auto index = r.doubles("/series/fields/step"), time = r.doubles("/series/fields/time");
    const auto all = r.doubles("/series/fields/pressure");
    for (int k = 0; k < steps; ++k) {
      ASSERT_EQ(index[k], double(k)) << dir;
      ASSERT_EQ(time[k], 0.5 * k) << dir;
      const Field p = pressure(k);
      ASSERT_TRUE(std::equal(p.data(), p.data() + p.size(), all.begin() + k * n * n)) << k;
    }
    for (int k : {0, 4095, 4096, steps - 1}) {
      const Field p = pressure(k), st = state(k);
      EXPECT_EQ(r.doubles(groups[k] + "/pressure"),
                std::vector<double>(p.data(), p.data() + p.size()));
      EXPECT_EQ(r.doubles(groups[k] + "/state"),
                std::vector<double>(st.data(), st.data() + st.size()));
      EXPECT_EQ(r.scalar_attribute<double>(groups[k], "time", H5T_NATIVE_DOUBLE), 0.5 * k);
    }
  }
}

TEST(Hdf5, ErrorsNameThePath) {
  const TempDir tmp("io");
  std::ofstream(tmp.path() / "file") << "x";
  const auto message = [](auto&& make) {
    try {
      make();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(
      message([&] { Hdf5Writer w(tmp.path() / "file"); }).find((tmp.path() / "file").string()),
      std::string::npos);
  EXPECT_NE(message([&] {
              Hdf5Writer::open_existing(tmp.path() / "none");
            }).find((tmp.path() / "none" / "result.h5").string()),
            std::string::npos);
  std::ofstream(tmp.path() / "result.h5") << "not hdf5";
  EXPECT_THROW(Hdf5Writer::open_existing(tmp.path()), InputError);
  Hdf5Writer h5(tmp.path() / "ok");
  EXPECT_THROW(h5.append_row({1.0}), std::invalid_argument);
  h5.write_field("/a", ramp_field(2, 2));
  EXPECT_THROW(h5.write_field("/a/b", ramp_field(2, 2)), std::runtime_error);  // /a is a dataset
}
