#include "fretbem/io/checkpoint.hpp"

#include <hdf5.h>

#include <chrono>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/hdf5.hpp"
#include "fretbem/io/result_metadata.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFile = "checkpoint.h5";

void write_array(hid_t file, const std::string& name, const double* data,
                 std::vector<hsize_t> dims) {
  hdf5::Space space(H5Screate_simple(int(dims.size()), dims.data(), nullptr));
  hdf5::Dataset set(H5Dcreate2(file, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                               H5P_DEFAULT, H5P_DEFAULT));
  if (set.get() < 0 ||
      H5Dwrite(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw std::runtime_error("checkpoint: cannot write " + name);
}

void write_field(hid_t file, const std::string& name, const Field& f) {
  write_array(file, name, f.data(), {hsize_t(f.cols()), hsize_t(f.rows())});
}

void write_vector(hid_t file, const std::string& name, const std::vector<double>& v) {
  write_array(file, name, v.data(), {hsize_t(v.size())});
}

// Text as a 1-D byte dataset: no string-type or character-set conversions to get wrong.
void write_text(hid_t file, const std::string& name, const std::string& text) {
  const hsize_t n = text.size();
  hdf5::Space space(H5Screate_simple(1, &n, nullptr));
  hdf5::Dataset set(H5Dcreate2(file, name.c_str(), H5T_STD_U8LE, space.get(), H5P_DEFAULT,
                               H5P_DEFAULT, H5P_DEFAULT));
  if (set.get() < 0 ||
      (n && H5Dwrite(set.get(), H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()) < 0))
    throw std::runtime_error("checkpoint: cannot write " + name);
}

std::string read_text(hid_t file, const std::string& name) {
  hdf5::Dataset set(H5Dopen2(file, name.c_str(), H5P_DEFAULT));
  if (set.get() < 0) throw InputError("checkpoint: missing dataset " + name);
  hdf5::Space space(H5Dget_space(set.get()));
  std::string text(std::size_t(H5Sget_simple_extent_npoints(space.get())), '\0');
  if (!text.empty() &&
      H5Dread(set.get(), H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()) < 0)
    throw InputError("checkpoint: cannot read " + name);
  return text;
}

std::vector<double> read_array(hid_t file, const std::string& name, std::vector<hsize_t>* dims) {
  hdf5::Dataset set(H5Dopen2(file, name.c_str(), H5P_DEFAULT));
  if (set.get() < 0) throw InputError("checkpoint: missing dataset " + name);
  hdf5::Space space(H5Dget_space(set.get()));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  std::vector<hsize_t> d(std::max(rank, 0));
  H5Sget_simple_extent_dims(space.get(), d.data(), nullptr);
  hsize_t n = 1;
  for (auto x : d) n *= x;
  std::vector<double> out(n);
  if (n && H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    throw InputError("checkpoint: cannot read " + name);
  if (dims) *dims = d;
  return out;
}

Field read_field(hid_t file, const std::string& name) {
  std::vector<hsize_t> d;
  const auto v = read_array(file, name, &d);
  if (d.size() != 2) throw InputError("checkpoint: " + name + " is not 2-D");
  Field f(d[1], d[0]);
  std::copy(v.begin(), v.end(), f.data());
  return f;
}

void write_vecfield(hid_t file, const std::string& name, const VecField& v) {
  for (std::size_t c = 0; c < v.size(); ++c) write_field(file, name + std::to_string(c), v[c]);
}

VecField read_vecfield(hid_t file, const std::string& name, int nc) {
  VecField v;
  for (int c = 0; c < nc; ++c) v.push_back(read_field(file, name + std::to_string(c)));
  return v;
}

void write_state(hid_t f, const InterfaceState& s) {
  write_field(f, "pressure", s.pressure);
  write_vecfield(f, "traction", s.traction);
  write_vecfield(f, "displacement", s.displacement);
  write_vecfield(f, "slip", s.slip);
  write_field(f, "slip_path", s.slip_path);
  write_field(f, "dissipation", s.dissipation);
  write_field(f, "wear", s.wear);
  write_field(f, "state", s.state.cast<double>());
  write_vector(
      f, "scalars",
      {s.shift.x(), s.shift.y(), s.normal_force, s.indentation, double(s.traction.size())});
}

InterfaceState read_state(hid_t f) {
  InterfaceState s;
  const auto sc = read_array(f, "scalars", nullptr);
  if (sc.size() != 5) throw InputError("checkpoint: bad scalars");
  const int nc = int(sc[4]);
  s.pressure = read_field(f, "pressure");
  s.traction = read_vecfield(f, "traction", nc);
  s.displacement = read_vecfield(f, "displacement", nc);
  s.slip = read_vecfield(f, "slip", nc);
  s.slip_path = read_field(f, "slip_path");
  s.dissipation = read_field(f, "dissipation");
  s.wear = read_field(f, "wear");
  s.state = read_field(f, "state").cast<std::uint8_t>();
  s.shift = Vec2(sc[0], sc[1]);
  s.normal_force = sc[2];
  s.indentation = sc[3];
  return s;
}

void write_memory(hid_t f, const StepperMemory& m) {
  const auto& n = m.last_normal;
  write_vector(f, "memory",
               {double(m.next_step), m.dissipation, m.wear_volume, n ? 1.0 : 0.0,
                n && n->force_control ? 1.0 : 0.0, n ? n->value : 0.0});
  std::vector<double> t(m.last_target.data(), m.last_target.data() + m.last_target.size());
  t.insert(t.begin(), double(t.size()));
  write_vector(f, "last_target", t);
}

StepperMemory read_memory(hid_t f) {
  const auto v = read_array(f, "memory", nullptr);
  const auto t = read_array(f, "last_target", nullptr);
  if (v.size() != 6 || t.empty()) throw InputError("checkpoint: bad stepper memory");
  StepperMemory m;
  m.next_step = std::size_t(v[0]);
  m.dissipation = v[1];
  m.wear_volume = v[2];
  if (v[3] > 0) m.last_normal = NormalLoad{v[4] > 0, v[5]};
  m.last_target = Eigen::Map<const Eigen::VectorXd>(t.data() + 1, Eigen::Index(t[0]));
  return m;
}

// The wear part (wear runs only): scalars in one vector, the worn depth as a field.
void write_wear(hid_t f, const WearCheckpoint& w) {
  const WearCounters& c = w.counters;
  write_vector(f, "wear_scalars",
               {w.N, w.h_next, w.h_max, c.simulated, double(c.evaluations), double(c.rows),
                double(c.index), double(w.steps), double(w.rejected), double(w.next_snapshot),
                double(w.cycles_rows), double(w.snapshots), w.implicit ? 1.0 : 0.0});
  write_field(f, "wear_worn", w.worn);
}

std::optional<WearCheckpoint> read_wear(hid_t f) {
  if (H5Lexists(f, "wear_scalars", H5P_DEFAULT) <= 0) return std::nullopt;
  const auto v = read_array(f, "wear_scalars", nullptr);
  if (v.size() != 13) throw InputError("checkpoint: bad wear state");
  WearCheckpoint w;
  w.N = v[0], w.h_next = v[1], w.h_max = v[2];
  w.counters = {v[3], int(v[4]), int(v[5]), int(v[6])};
  w.steps = long(v[7]), w.rejected = long(v[8]), w.next_snapshot = long(v[9]);
  w.cycles_rows = long(v[10]), w.snapshots = long(v[11]), w.implicit = v[12] != 0.0;
  w.worn = read_field(f, "wear_worn");
  return w;
}

}  // namespace

void save_checkpoint(const fs::path& dir, const Model& model, const Stepper& stepper,
                     const WearCheckpoint* wear) {
  hdf5::silence();
  const fs::path tmp = dir / (std::string(kFile) + ".tmp");
  {
    hdf5::File f(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
    if (f.get() < 0) throw InputError(tmp.string() + ": cannot create checkpoint");
    io::write_file_attributes(f.get(), model.scenario.grid, dir, "fretbem checkpoint",
                              tmp.string());
    write_text(f.get(), "scenario", model.scenario.resolved_text);
    write_state(f.get(), stepper.state());
    write_memory(f.get(), stepper.memory());
    write_field(f.get(), "surface", model.surface);
    if (wear) write_wear(f.get(), *wear);
  }
  fs::rename(tmp, dir / kFile);
}

Checkpoint load_checkpoint(const fs::path& dir) {
  hdf5::silence();
  const fs::path path = dir / kFile;
  if (!fs::exists(path)) throw InputError(path.string() + ": no checkpoint to resume from");
  hdf5::File f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (f.get() < 0) throw InputError(path.string() + ": cannot open checkpoint");
  Checkpoint c;
  c.scenario_text = read_text(f.get(), "scenario");
  c.state = read_state(f.get());
  c.memory = read_memory(f.get());
  c.surface = read_field(f.get(), "surface");
  c.wear = read_wear(f.get());
  return c;
}

Checkpointer::Checkpointer(fs::path dir, const Stepper& stepper, int every)
    : dir_(std::move(dir)), stepper_(stepper), every_(every) {}

void Checkpointer::on_step(const StepRecord& rec, const InterfaceState&, const Model& model) {
  using namespace std::chrono;
  const double now = duration<double>(steady_clock::now().time_since_epoch()).count();
  const bool last = std::size_t(rec.step) + 1 == model.path.steps.size();
  const bool due = every_ > 0 ? (rec.step + 1) % every_ == 0 : now - last_ >= 10.0;
  if (!(due || rec.turning || last)) return;
  save_checkpoint(dir_, model, stepper_);
  last_ = now;
}

}  // namespace fretbem
