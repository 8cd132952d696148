#include "fretbem/io/checkpoint.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <sstream>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/fingerprint.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/hdf5.hpp"
#include "fretbem/core/rank_zero.hpp"
#include "fretbem/core/text_file.hpp"
#include "fretbem/history/slab_state.hpp"
#include "fretbem/io/result_metadata.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

// The checkpoint's own format version (a dataset); older checkpoints used the second name,
// which the root attribute format_version (the result-file layout) shares.
constexpr const char* kFormatDataset = "checkpoint_format";
constexpr const char* kOldFormatDataset = "format_version";

}  // namespace

namespace {

constexpr const char* kFile = "checkpoint.h5";

// ---- the checksum block ----------------------------------------------------------------
// The file starts with a block of kSumBlock bytes holding kSumMagic, the fingerprint of
// every byte after the block and their count. A damaged checkpoint is then
// refused before HDF5 parses it: HDF5 1.10.8 itself crashes on some damaged files (fuzz_checkpoint
// found a local heap whose size made it memcpy from a failed allocation). Checkpoints written
// before the block start with the HDF5 signature and are read unchecked.
constexpr std::size_t kSumBlock = 512;
constexpr char kSumMagic[] = "fretbem checkpoint sum 1\n";
constexpr char kHdf5Signature[] = "\x89HDF\r\n\x1a\n";

std::string sum_line(const char* data, std::size_t n) {
  Fingerprint fp;
  fp.add_bytes(data, n);
  return std::string(kSumMagic) + fp.hex() + " " + std::to_string(n) + "\n";
}

// The block, then the HDF5 image: HDF5 finds its superblock at offset kSumBlock and takes
// what precedes it as a user block.
std::vector<char> sealed(const std::vector<char>& image) {
  std::vector<char> out(kSumBlock, '\0');
  const std::string line = sum_line(image.data(), image.size());
  std::copy(line.begin(), line.end(), out.begin());
  out.insert(out.end(), image.begin(), image.end());
  return out;
}

// Refuses a checkpoint whose bytes are not the ones its writer sealed; false for one written
// before the sum block (not checked).
std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw InputError(path.string() + ": cannot read the checkpoint");
  return bytes;
}

bool has_sum_block(const std::string& bytes) {
  return bytes.size() >= kSumBlock && bytes.compare(0, sizeof kSumMagic - 1, kSumMagic) == 0;
}

bool verify_sum(const fs::path& path) {
  const std::string bytes = read_bytes(path);
  if (bytes.compare(0, 8, kHdf5Signature) == 0) return false;  // written before the block
  const std::string damaged = path.string() + ": damaged checkpoint (";
  if (!has_sum_block(bytes))
    throw InputError(damaged + "no checksum block; not written by fretbem, or overwritten)");
  const std::string want = sum_line(bytes.data() + kSumBlock, bytes.size() - kSumBlock);
  if (bytes.compare(0, want.size(), want) != 0)
    throw InputError(damaged + "checksum mismatch: its bytes changed after it was written)");
  return true;
}

// ---- writing (into an in-memory HDF5 file; std::runtime_error on any failure) ----------

[[noreturn]] void write_failed(const std::string& what) {
  throw std::runtime_error("checkpoint: cannot write " + what + ": " + hdf5::last_error());
}

void write_array(hid_t file, const std::string& name, hid_t file_type, hid_t mem_type,
                 const void* data, std::vector<hsize_t> dims) {
  hdf5::Space space(H5Screate_simple(int(dims.size()), dims.data(), nullptr));
  if (!space.valid()) write_failed(name);
  hdf5::Dataset set(H5Dcreate2(file, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT,
                               H5P_DEFAULT));
  hsize_t n = 1;
  for (auto d : dims) n *= d;
  if (!set.valid() || (n && H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0))
    write_failed(name);
  if (set.close() < 0 || space.close() < 0) write_failed(name);
}

void write_field(hid_t file, const std::string& name, const Field& f) {
  write_array(file, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, f.data(),
              {hsize_t(f.cols()), hsize_t(f.rows())});
}

void write_vector(hid_t file, const std::string& name, const std::vector<double>& v) {
  write_array(file, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), {hsize_t(v.size())});
}

// Text as a 1-D byte dataset: no string-type or character-set conversions to get wrong.
void write_text(hid_t file, const std::string& name, const std::string& text) {
  write_array(file, name, H5T_STD_U8LE, H5T_NATIVE_UCHAR, text.data(), {hsize_t(text.size())});
}

void write_vecfield(hid_t file, const std::string& name, const VecField& v) {
  for (std::size_t c = 0; c < v.size(); ++c) write_field(file, name + std::to_string(c), v[c]);
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

// The Stepper's per-node memory, whatever it names: the names one a line in memory_fields, each
// field as memory_field_<name>. Checkpoints written without them resume from the bound
// recomputed from the state.
constexpr const char* kMemoryFields = "memory_fields";
constexpr const char* kMemoryFieldPrefix = "memory_field_";

void write_memory_fields(hid_t f, const std::map<std::string, Field>& fields) {
  if (fields.empty()) return;
  std::string names;
  for (const auto& [name, field] : fields) {
    names += name + "\n";
    write_field(f, kMemoryFieldPrefix + name, field);
  }
  write_text(f, kMemoryFields, names);
}

void write_memory(hid_t f, const StepperMemory& m) {
  const auto& n = m.last_normal;
  write_vector(f, "memory",
               {double(m.next_step), m.dissipation, m.wear_volume, n ? 1.0 : 0.0,
                n && n->force_control ? 1.0 : 0.0, n ? n->value : 0.0});
  std::vector<double> t(m.last_target.data(), m.last_target.data() + m.last_target.size());
  t.insert(t.begin(), double(t.size()));
  write_vector(f, "last_target", t);
  write_memory_fields(f, m.fields);
  if (!m.masing.empty()) write_vector(f, "masing", m.masing);
  if (!m.step_estimate.empty()) write_vector(f, "step_estimate", m.step_estimate);
  if (!m.step_period.empty()) write_vector(f, "step_period", m.step_period);
  if (!m.step_before.empty()) write_vector(f, "step_before", m.step_before);
}

// The k-th evaluation (oldest first) of the warm start's path: its worn depth or pressure.
std::string warm_path_name(const char* what, std::size_t k) {
  return std::string("wear_warm_path_") + what + "_" + std::to_string(k);
}

// The wear part (wear runs only): scalars in one vector, the worn depth as a field.
void write_wear(hid_t f, const WearCheckpoint& w) {
  const WearCounters& c = w.counters;
  write_vector(f, "wear_scalars",
               {w.N, w.h_next, w.h_max, c.simulated, double(c.evaluations), double(c.rows),
                double(c.index), double(w.steps), double(w.rejected), double(w.next_snapshot),
                double(w.cycles_rows), double(w.snapshots), w.implicit ? 1.0 : 0.0});
  write_field(f, "wear_worn", w.worn);
  if (w.state_has_row) write_vector(f, "wear_state_row", {1.0});
  write_vector(f, "wear_stretch", {w.stretch, w.stretched ? 1.0 : 0.0});
  write_vector(f, "wear_stretch_left", {w.stretch_left, w.step_cost, w.step_unpaid ? 1.0 : 0.0});
  if (w.atol > 0.0) write_vector(f, "wear_atol", {w.atol});
  if (w.warm.pressure.size() > 0) write_field(f, "wear_warm_pressure", w.warm.pressure);
  if (w.warm.corrective.size() > 0) write_field(f, "wear_warm_corrective", w.warm.corrective);
  for (std::size_t k = 0; k < w.warm.worn_path.size(); ++k) {
    write_field(f, warm_path_name("worn", k), w.warm.worn_path[k]);
    write_field(f, warm_path_name("pressure", k), w.warm.pressure_path[k]);
  }
  if (w.warm.predicted_worn.size() > 0) {
    write_field(f, "wear_warm_predicted_worn", w.warm.predicted_worn);
    write_field(f, "wear_warm_predicted_pressure", w.warm.predicted_pressure);
  }
}

// The whole checkpoint as the bytes of an HDF5 file, built with the in-memory (core) driver:
// nothing touches the disk until write_file_atomically, whose every system call is checked.
// What a checkpoint holds of the stepper; the memory and the predictor's flat form are made
// when written, one at a time (each as large as the state).
struct StepperParts {
  const InterfaceState& state;
  std::function<StepperMemory()> memory;
  std::function<std::vector<double>()> predictor;
};

std::vector<char> checkpoint_image(const Model& model, const StepperParts& stepper,
                                   const WearCheckpoint* wear) {
  hdf5::Plist fapl(H5Pcreate(H5P_FILE_ACCESS));
  if (!fapl.valid() || H5Pset_fapl_core(fapl.get(), 1 << 20, 0) < 0) write_failed("(set-up)");
  hdf5::File f(H5Fcreate("fretbem-checkpoint-image", H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()));
  if (!f.valid()) write_failed("(in memory)");
  // Named apart from the root attribute format_version (the result-file layout shared with
  // result.h5): one file, two versions, two names. Checkpoints written before carry it as the
  // dataset format_version, still read.
  const std::vector<double> version{double(kCheckpointFormat)};
  write_vector(f.get(), kFormatDataset, version);
  write_text(f.get(), "run_id", model.run_id);
  io::write_file_attributes(f.get(), model.scenario.grid, model.scenario.output.dir,
                            "fretbem checkpoint", "checkpoint");
  write_text(f.get(), "scenario", model.scenario.resolved_text);
  write_state(f.get(), stepper.state);
  write_memory(f.get(), stepper.memory());
  write_field(f.get(), "surface", model.surface);
  if (const std::vector<double> p = stepper.predictor(); !p.empty())
    write_vector(f.get(), "predictor", p);
  const InputDigest inputs = input_digest(model);
  write_text(f.get(), "input_digest_path", inputs.path);
  write_text(f.get(), "input_digest_surface", inputs.surface);
  if (wear) write_wear(f.get(), *wear);
  if (H5Fflush(f.get(), H5F_SCOPE_GLOBAL) < 0) write_failed("(flush)");
  const ssize_t size = H5Fget_file_image(f.get(), nullptr, 0);
  if (size <= 0) write_failed("(image size)");
  std::vector<char> image(std::size_t(size), '\0');
  if (H5Fget_file_image(f.get(), image.data(), image.size()) != size) write_failed("(image)");
  if (f.close() < 0) write_failed("(close)");
  return sealed(image);
}

// ---- reading (InputError naming the file and dataset on anything unexpected) ------------

class Reader {
 public:
  Reader(hid_t file, fs::path path, std::uintmax_t bytes)
      : file_(file), path_(std::move(path)), bytes_(bytes) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_.string() + ": " + what + " (not a usable checkpoint)");
  }
  bool exists(const std::string& name) const {
    return H5Lexists(file_, name.c_str(), H5P_DEFAULT) > 0;
  }

  // Any 1-D or 2-D numeric dataset; its element count is bounded by the file size (the
  // checkpoint writer stores contiguous, uncompressed data), so a damaged header cannot
  // make the reader allocate without bound.
  std::vector<double> array(const std::string& name, std::vector<hsize_t>* dims,
                            hid_t mem_type = H5T_NATIVE_DOUBLE, std::size_t elem = 8) const {
    if (!exists(name)) fail("missing dataset " + name);
    hdf5::Dataset set(H5Dopen2(file_, name.c_str(), H5P_DEFAULT));
    if (!set.valid()) fail("cannot open dataset " + name);
    hdf5::Space space(H5Dget_space(set.get()));
    const int rank = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
    if (rank < 1 || rank > 2) fail(name + " has rank " + std::to_string(rank));
    std::vector<hsize_t> d(std::size_t(rank), 0);
    if (H5Sget_simple_extent_dims(space.get(), d.data(), nullptr) < 0) fail("bad shape of " + name);
    hsize_t n = 1;
    for (auto x : d) {
      if (x > bytes_ || (x && n > bytes_ / x)) fail(name + " is larger than the file");
      n *= x;
    }
    if (n * elem > bytes_ + 4096) fail(name + " is larger than the file");
    std::vector<double> out(n);
    if (n && H5Dread(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
      fail("cannot read " + name + ": " + hdf5::last_error());
    if (dims) *dims = d;
    return out;
  }

  std::string text(const std::string& name) const {
    if (!exists(name)) fail("missing dataset " + name);
    hdf5::Dataset set(H5Dopen2(file_, name.c_str(), H5P_DEFAULT));
    if (!set.valid()) fail("cannot open dataset " + name);
    hdf5::Space space(H5Dget_space(set.get()));
    const hssize_t n = space.valid() ? H5Sget_simple_extent_npoints(space.get()) : -1;
    if (n < 0 || std::uintmax_t(n) > bytes_ || H5Sget_simple_extent_ndims(space.get()) != 1)
      fail("bad shape of " + name);
    std::string s(std::size_t(n), '\0');
    if (n && H5Dread(set.get(), H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data()) < 0)
      fail("cannot read " + name + ": " + hdf5::last_error());
    return s;
  }

  std::vector<double> vector(const std::string& name, std::size_t size) const {
    const auto v = array(name, nullptr);
    if (v.size() != size)
      fail(name + " holds " + std::to_string(v.size()) + " values, not " + std::to_string(size));
    for (double x : v)
      if (std::isnan(x)) fail(name + " holds NaN");
    return v;
  }

  Field field(const std::string& name) const {
    std::vector<hsize_t> d;
    const auto v = array(name, &d);
    if (d.size() != 2) fail(name + " is not 2-D");
    Field f(static_cast<Eigen::Index>(d[1]), static_cast<Eigen::Index>(d[0]));
    std::copy(v.begin(), v.end(), f.data());
    return f;
  }

 private:
  hid_t file_;
  fs::path path_;
  std::uintmax_t bytes_;
};

// A stored count: a finite integer in [lo, hi].
long count(const Reader& r, const std::string& what, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi) || v != std::floor(v))
    r.fail(what + " = " + std::to_string(v) + " is not a count in [" + std::to_string(long(lo)) +
           ", " + std::to_string(long(hi)) + "]");
  return long(v);
}

VecField read_vecfield(const Reader& r, const std::string& name, int nc) {
  VecField v;
  for (int c = 0; c < nc; ++c) v.push_back(r.field(name + std::to_string(c)));
  return v;
}

InterfaceState read_state(const Reader& r) {
  InterfaceState s;
  const auto sc = r.vector("scalars", 5);
  const int nc = int(count(r, "scalars[4] (tangential components)", sc[4], 1, 2));
  s.pressure = r.field("pressure");
  s.traction = read_vecfield(r, "traction", nc);
  s.displacement = read_vecfield(r, "displacement", nc);
  s.slip = read_vecfield(r, "slip", nc);
  s.slip_path = r.field("slip_path");
  s.dissipation = r.field("dissipation");
  s.wear = r.field("wear");
  // Every NodeState, stuck_at_bound (3) included: the checkpoint holds the state as the last
  // step left it (the stiffness solve tells stick from stuck_at_bound), so a resumed run is the
  // uninterrupted one; only result.h5's `state` field counts 3 as stick.
  const Field state = r.field("state");
  for (double x : state.reshaped())
    if (!(x == 0 || x == 1 || x == 2 || x == 3)) r.fail("state holds " + std::to_string(x));
  s.state = state.cast<std::uint8_t>();
  s.shift = Vec2(sc[0], sc[1]);
  s.normal_force = sc[2];
  s.indentation = sc[3];
  return s;
}

StepperMemory read_memory(const Reader& r) {
  const auto v = r.vector("memory", 6);
  const auto t = r.array("last_target", nullptr);
  if (t.empty()) r.fail("last_target is empty");
  StepperMemory m;
  m.next_step = std::size_t(count(r, "memory[0] (next_step)", v[0], 0, 9e15));
  m.dissipation = v[1];
  m.wear_volume = v[2];
  if (v[3] > 0) m.last_normal = NormalLoad{v[4] > 0, v[5]};
  const long nt = count(r, "last_target[0] (its length)", t[0], 0, double(t.size() - 1));
  if (std::size_t(nt) + 1 != t.size()) r.fail("last_target length does not match its count");
  m.last_target = Eigen::Map<const Eigen::VectorXd>(t.data() + 1, Eigen::Index(nt));
  if (r.exists("masing")) m.masing = r.array("masing", nullptr);
  if (r.exists("step_estimate")) m.step_estimate = r.vector("step_estimate", 2);
  if (r.exists("step_period")) m.step_period = r.vector("step_period", PeriodRate::kValues);
  if (r.exists("step_before")) m.step_before = r.vector("step_before", 2);
  if (!r.exists(kMemoryFields)) return m;
  std::istringstream names(r.text(kMemoryFields));
  for (std::string name; std::getline(names, name);)
    m.fields[name] = r.field(kMemoryFieldPrefix + name);
  return m;
}

std::optional<WearCheckpoint> read_wear(const Reader& r) {
  if (!r.exists("wear_scalars")) return std::nullopt;
  const auto v = r.vector("wear_scalars", 13);
  constexpr double big = 2e9;  // counters are stored from int / long
  WearCheckpoint w;
  w.N = v[0], w.h_next = v[1], w.h_max = v[2];
  w.counters = {v[3], int(count(r, "wear evaluations", v[4], 0, big)),
                int(count(r, "wear rows", v[5], 0, big)),
                int(count(r, "wear index", v[6], 0, big))};
  w.steps = count(r, "wear steps", v[7], 0, 9e15);
  w.rejected = count(r, "wear rejected", v[8], 0, 9e15);
  w.next_snapshot = count(r, "wear next_snapshot", v[9], 0, 9e15);
  w.cycles_rows = count(r, "wear cycles_rows", v[10], 0, 9e15);
  w.snapshots = count(r, "wear snapshots", v[11], 0, 9e15);
  w.implicit = v[12] != 0.0;
  w.state_has_row = r.exists("wear_state_row");
  if (r.exists("wear_stretch")) {
    const auto s = r.vector("wear_stretch", 2);
    w.stretch = s[0], w.stretched = s[1] != 0.0;
  }
  if (r.exists("wear_stretch_left")) {
    const auto s = r.vector("wear_stretch_left", 3);
    w.stretch_left = s[0], w.step_cost = s[1], w.step_unpaid = s[2] != 0.0;
  }
  if (r.exists("wear_atol")) w.atol = r.vector("wear_atol", 1)[0];
  w.worn = r.field("wear_worn");
  // Without it the next evaluation starts cold.
  if (r.exists("wear_warm_pressure")) w.warm.pressure = r.field("wear_warm_pressure");
  if (r.exists("wear_warm_corrective")) w.warm.corrective = r.field("wear_warm_corrective");
  // The evaluations' path the next start extrapolates from (without it: the last pressure).
  for (std::size_t k = 0; r.exists(warm_path_name("worn", k)); ++k) {
    w.warm.worn_path.push_back(r.field(warm_path_name("worn", k)));
    w.warm.pressure_path.push_back(r.field(warm_path_name("pressure", k)));
  }
  if (r.exists("wear_warm_predicted_worn")) {
    w.warm.predicted_worn = r.field("wear_warm_predicted_worn");
    w.warm.predicted_pressure = r.field("wear_warm_predicted_pressure");
  }
  return w;
}

Checkpoint read_checkpoint_file(const fs::path& path) {
  hdf5::silence();
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) throw InputError(path.string() + ": cannot read: " + ec.message());
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw InputError(path.string() + ": not an HDF5 file (damaged checkpoint)");
  hdf5::File f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!f.valid()) throw InputError(path.string() + ": cannot open checkpoint");
  const Reader r(f.get(), path, bytes);
  const char* name = r.exists(kFormatDataset)      ? kFormatDataset
                     : r.exists(kOldFormatDataset) ? kOldFormatDataset
                                                   : nullptr;
  if (!name)
    r.fail(std::string("no ") + kFormatDataset + " (written by fretbem before checkpoint format " +
           std::to_string(kCheckpointFormat) + ")");
  const auto version = r.vector(name, 1);
  if (version[0] != kCheckpointFormat)
    r.fail(std::string(name) + " " + format_number(version[0]) + ", this fretbem reads " +
           std::to_string(kCheckpointFormat));
  Checkpoint c;
  c.run_id = r.text("run_id");
  c.scenario_text = r.text("scenario");
  c.state = read_state(r);
  c.memory = read_memory(r);
  c.surface = r.field("surface");
  c.wear = read_wear(r);
  if (r.exists("predictor")) c.predictor = r.array("predictor", nullptr);
  if (r.exists("input_digest_path") && r.exists("input_digest_surface"))
    c.inputs = InputDigest{r.text("input_digest_path"), r.text("input_digest_surface")};
  return c;
}

// An unsealed checkpoint is read first in a child process: HDF5 1.10.8 dies with SIGSEGV on
// some damaged files (fuzz_checkpoint: a local heap of 7e17 bytes, whose failed allocation it
// copies from), and a crash must become a refusal. The parent then reads the file itself.
void probe_in_child(const fs::path& path) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) return;  // no child to spare: read it directly, as before the probe
  if (pid == 0) {
    try {
      (void)read_checkpoint_file(path);
    } catch (...) {
      ::_exit(2);
    }
    ::_exit(0);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // The child ends with 0 or 2 by itself; anything else (a signal, or a sanitizer's exit
  // after one) is a death inside the reader.
  if (WIFSIGNALED(status))
    throw InputError(path.string() + ": damaged checkpoint (HDF5 died reading it, signal " +
                     std::to_string(WTERMSIG(status)) + ")");
  if (WIFEXITED(status) && WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 2)
    throw InputError(path.string() + ": damaged checkpoint (HDF5 died reading it, exit " +
                     std::to_string(WEXITSTATUS(status)) + ")");
}

}  // namespace

namespace {

void write_checkpoint(const fs::path& dir, const Model& model, const StepperParts& stepper,
                      const WearCheckpoint* wear) {
  hdf5::silence();
  const std::vector<char> bytes = checkpoint_image(model, stepper, wear);
  try {  // DIR/checkpoint.h5.tmp, every call checked, then renamed over the previous one
    write_file_atomically(dir / kFile, std::string_view(bytes.data(), bytes.size()));
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + " (the previous checkpoint, if any, is kept)");
  }
}

}  // namespace

// On a distributed grid the state is gathered to rank 0, which writes the whole grid's
// checkpoint, the same file a serial run writes (a resume may take another number of ranks).
void save_checkpoint(const fs::path& dir, const Model& model, const Stepper& stepper,
                     const WearCheckpoint* wear) {
  const HalfSpace& hs = *model.half_space;
  const Communicator& comm = hs.communicator();
  if (!comm.distributed())
    return write_checkpoint(dir, model,
                            {stepper.state(), [&stepper] { return stepper.memory(); },
                             [&stepper] { return stepper.predictor().flatten(); }},
                            wear);
  const InterfaceState state = gathered(hs, stepper.state());
  const StepperMemory memory = gathered(hs, stepper.memory());
  const std::vector<double> predictor = CyclePredictor::gathered(
      stepper.predictor().flatten(), comm, Eigen::Index(hs.first_row()) * hs.grid().nx);
  const StepperParts whole{state, [&memory] { return memory; }, [&predictor] { return predictor; }};
  on_rank_zero(comm, [&] { write_checkpoint(dir, model, whole, wear); });
}

void reseal_checkpoint(const fs::path& file) {
  const std::string bytes = read_bytes(file);
  if (!has_sum_block(bytes)) throw InputError(file.string() + ": no checksum block to renew");
  const std::string line = sum_line(bytes.data() + kSumBlock, bytes.size() - kSumBlock);
  std::ofstream out(file, std::ios::binary | std::ios::in | std::ios::out);
  out.write(line.data(), std::streamsize(line.size()));
  if (!out.flush()) throw std::runtime_error(file.string() + ": cannot renew its checksum");
}

Checkpoint load_checkpoint(const fs::path& dir) {
  const fs::path path = dir / kFile;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path.string() + ": no checkpoint to resume from");
  if (!fs::is_regular_file(path, ec)) throw InputError(path.string() + ": not a regular file");
  if (!verify_sum(path)) probe_in_child(path);
  return read_checkpoint_file(path);
}

Checkpointer::Checkpointer(fs::path dir, const Stepper& stepper, int every)
    : dir_(std::move(dir)), stepper_(stepper), every_(every) {}

void Checkpointer::on_step(const StepRecord& rec, const InterfaceState&, const Model& model) {
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_).count();
  const bool last = std::size_t(rec.step) + 1 == model.path.steps.size();
  const bool due = every_ > 0 ? (rec.step + 1) % every_ == 0 : since >= 10.0;
  // Turning points are natural restart points, but a table that reverses every few rows
  // would checkpoint every step (10 002 checkpoints, 4.4x the run time):
  // at most one turning-point checkpoint per second.
  const bool turning = rec.turning && since >= 1.0;
  // The clock and the folder are rank 0's: every rank of a distributed grid takes its answer.
  const bool save = decided_on_rank_zero(model.half_space->communicator(),
                                         [&] { return due || turning || last; });
  if (!save) return;
  save_checkpoint(dir_, model, stepper_);
  last_ = now;
}

}  // namespace fretbem
