// libFuzzer target: `fretbem run --resume` on checkpoints whose stored quantities are damaged.
//
// fuzz_checkpoint feeds arbitrary bytes to the reader, but HDF5's checksums and signatures
// reject nearly all of them before fretbem reads a value (coverage 109 edges at 10^4
// executions). Here the input instead names edits of a valid checkpoint made through the HDF5
// API: a value set to 0, -1, NaN, inf, 1e308, a fraction or a fuzzer-chosen double; a dataset
// reshaped, retyped, deleted or added; the scenario or run id replaced. The edited file then
// goes the way of a resume (load_checkpoint, the checkpoint's scenario, build_model,
// validate_checkpoint) and, when accepted, two steps are run from it (plain runs) or one wear
// step into a copy of the run's outputs (wear runs). Every input must end in a result or an
// InputError/SolverError: anything else (a crash, an assertion, another exception) is a finding.
#include <fuzzer/FuzzedDataProvider.h>
#include <hdf5.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/io/checkpoint.hpp"
#include "fretbem/io/result_recovery.hpp"
#include "fretbem/io/resume_check.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/run/wear_run.hpp"
#include "fretbem/wear/integrator.hpp"
#include "fuzz_input.hpp"

namespace fs = std::filesystem;

namespace {

// Small runs of the three kinds a checkpoint can hold: a 1-component sine with the cycle
// predictor (its memory is stored), a 2-component Cerruti-coupled run, and a wear run.
const char* const kScenarios[] = {
    "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 16\nlength = 2.8e-4\n"
    "[surface]\ntype = sphere\nradius = 0.01\n[load]\nnormal_force = 10\npath = sine\n"
    "control = force\namplitude = 0.6\ncycles = 3\nsteps_per_cycle = 8\n[output]\nfields = none\n",
    "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 16\nlength = 2.8e-4\n"
    "[surface]\ntype = sphere\nradius = 0.01\n[load]\nnormal_force = 10\npath = ramp\n"
    "control = force\namplitude = 0.6\nsteps = 8\n[solver]\ncoupling = cerruti\n"
    "[output]\nfields = none\n",
    "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 16\nlength = 2.8e-4\n"
    "[surface]\ntype = sphere\nradius = 0.01\n[load]\nnormal_force = 10\npath = sine\n"
    "control = force\namplitude = 0.6\ncycles = 1\nsteps_per_cycle = 4\n[solver]\n"
    "stiffness = false\ntolerance = 1e-9\n[wear]\nlaw = archard\ncoefficient = 5e-14\n"
    "cycles = 1000\nintegrator = arkode\nrtol = 1e-3\n[output]\nfields = none\n"};
constexpr int kTemplates = 3;
constexpr const char* kRunFiles[] = {"checkpoint.h5", "timeseries.csv", "cycles.csv", "result.h5"};

struct Template {
  fs::path dir;                    // the finished (stopped) run
  std::vector<std::string> names;  // its checkpoint's datasets
};
std::vector<Template> templates;

herr_t collect(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->push_back(name);
  return 0;
}

// Runs template k part of the way and leaves its outputs and checkpoint in its folder.
Template make_template(int k) {
  Template t{fretbem_fuzz::scratch_dir() / ("template" + std::to_string(k)), {}};
  fs::remove_all(t.dir);
  fs::create_directories(t.dir);
  fretbem::Scenario sc = fretbem::parse_scenario(kScenarios[k], "template", t.dir, {});
  fretbem::set_output_dir(sc, t.dir);
  auto model = fretbem::build_model(sc);
  model->run_id = "00000000000000" + std::to_string(10 + k);
  if (model->wear) {
    (void)fretbem::run_wear(*model, true, nullptr, 3);
  } else {
    fretbem::Stepper stepper(*model);
    stepper.run({}, k == 0 ? 13 : 5);  // past one cycle: the predictor holds its memory
    fretbem::save_checkpoint(t.dir, *model, stepper);
  }
  const hid_t f = H5Fopen((t.dir / "checkpoint.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  H5Literate(f, H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, collect, &t.names);
  H5Fclose(f);
  return t;
}

double special_value(FuzzedDataProvider& in) {
  static const double values[] = {0.0,  -0.0, -1.0,   1.0,   2.0,    3.0,    0.5,
                                  -5.0, 1e16, 9e15,   1e308, -1e308, 1e-308, 4.9e-324,
                                  2e9,  3e9,  65536., 1e6,   16.0,   17.0,   15.0};
  const int pick = in.ConsumeIntegralInRange(0, int(std::size(values)) + 3);
  if (pick == int(std::size(values))) return std::numeric_limits<double>::quiet_NaN();
  if (pick == int(std::size(values)) + 1) return std::numeric_limits<double>::infinity();
  if (pick == int(std::size(values)) + 2) return -std::numeric_limits<double>::infinity();
  if (pick == int(std::size(values)) + 3) return in.ConsumeFloatingPoint<double>();
  return values[pick];
}

std::vector<double> read_all(hid_t file, const std::string& name, std::vector<hsize_t>& dims) {
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(set);
  const int rank = H5Sget_simple_extent_ndims(space);
  dims.assign(std::size_t(std::max(rank, 0)), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  std::vector<double> v(std::size_t(H5Sget_simple_extent_npoints(space)));
  if (!v.empty()) H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(space);
  H5Dclose(set);
  return v;
}

// Replaces dataset `name` by `v` with shape `dims`, stored as `type`.
void write_all(hid_t file, const std::string& name, const std::vector<double>& v,
               const std::vector<hsize_t>& dims, hid_t type) {
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0) H5Ldelete(file, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Screate_simple(int(dims.size()), dims.data(), nullptr);
  const hid_t set =
      H5Dcreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (!v.empty()) H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(set);
  H5Sclose(space);
}

// One edit of dataset `name` chosen by the input.
void edit(hid_t file, const std::string& name, FuzzedDataProvider& in) {
  std::vector<hsize_t> dims;
  std::vector<double> v = read_all(file, name, dims);
  switch (in.ConsumeIntegralInRange(0, 5)) {
    case 0:  // a value (several, for the fields)
    case 1:
      for (int r = in.ConsumeIntegralInRange(1, 3); r > 0 && !v.empty(); --r)
        v[in.ConsumeIntegralInRange<std::size_t>(0, v.size() - 1)] = special_value(in);
      write_all(file, name, v, dims, H5T_IEEE_F64LE);
      return;
    case 2: {  // another shape (1-D or 2-D, sizes near the grid's)
      std::vector<hsize_t> d(std::size_t(in.ConsumeIntegralInRange(1, 3)));
      for (auto& x : d) x = in.ConsumeIntegralInRange<hsize_t>(0, 18);
      hsize_t n = 1;
      for (auto x : d) n *= x;
      v.resize(std::size_t(n), v.empty() ? 0.0 : v.front());
      write_all(file, name, v, d, H5T_IEEE_F64LE);
      return;
    }
    case 3: {  // another stored type (values converted by HDF5, text bytes included)
      const hid_t types[] = {H5T_STD_I32LE, H5T_IEEE_F32LE, H5T_STD_U8LE, H5T_STD_I64BE};
      write_all(file, name, v, dims, types[in.ConsumeIntegralInRange(0, 3)]);
      return;
    }
    case 4:  // gone
      H5Ldelete(file, name.c_str(), H5P_DEFAULT);
      return;
    default: {  // text (scenario, run id, digests): fuzzer bytes in place of the old text
      const std::string s = in.ConsumeRandomLengthString(600);
      std::vector<double> bytes;
      for (const char c : s) bytes.push_back(double(static_cast<unsigned char>(c)));
      write_all(file, name, bytes, {hsize_t(bytes.size())}, H5T_STD_U8LE);
    }
  }
}

// A copy of template t's folder with the input's edits applied to its checkpoint.
fs::path edited_copy(const Template& t, FuzzedDataProvider& in) {
  const fs::path dir = fretbem_fuzz::scratch_dir() / "run";
  fs::remove_all(dir);
  fs::create_directories(dir);
  for (const char* f : kRunFiles)
    if (fs::exists(t.dir / f)) fs::copy_file(t.dir / f, dir / f);
  const hid_t file = H5Fopen((dir / "checkpoint.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  for (int e = in.ConsumeIntegralInRange(1, 4); e > 0; --e) {
    const std::size_t pick = in.ConsumeIntegralInRange<std::size_t>(0, t.names.size());
    // One past the list: a dataset of another kind of run (wear or predictor) appears.
    const std::string name = pick < t.names.size() ? t.names[pick]
                             : in.ConsumeBool()    ? "wear_scalars"
                                                   : "predictor";
    if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0)
      write_all(file, name, std::vector<double>(13, 1.0), {13}, H5T_IEEE_F64LE);
    edit(file, name, in);
  }
  H5Fclose(file);
  fretbem::reseal_checkpoint(dir / "checkpoint.h5");  // past the checksum, to the validation
  return dir;
}

// What `fretbem run --resume DIR` does before and after its checks (run/run.cpp resume_run),
// with small bounds so that one input stays a few milliseconds.
void resume(const fs::path& dir) {
  const fretbem::Checkpoint cp = fretbem::load_checkpoint(dir);
  fretbem::Scenario sc = fretbem::parse_scenario(cp.scenario_text, "checkpoint", ".", {});
  if (sc.grid.nx * sc.grid.ny > 32 * 32) return;  // large grids are fuzz_scenario's
  fretbem::set_output_dir(sc, dir);
  auto model = fretbem::build_model(sc);
  if (model->path.steps.size() > 4096) return;
  fretbem::validate_checkpoint(cp, *model, dir / "checkpoint.h5");
  model->run_id = cp.run_id;
  if (model->wear) {
    if (!cp.wear) throw fretbem::InputError("not a wear run's checkpoint");
    (void)fretbem::prepare_result_for_resume(dir, *model, cp.run_id,
                                             {.rows = std::size_t(cp.wear->counters.rows),
                                              .field_steps = std::int64_t(model->path.steps.size()),
                                              .snapshots = cp.wear->snapshots});
    (void)fretbem::run_wear(*model, true, &cp, 1);
    return;
  }
  if (cp.wear) throw fretbem::InputError("a wear run's checkpoint");
  model->surface = cp.surface;
  fretbem::Stepper stepper(*model);
  const fretbem::Grid& g = model->scenario.grid;
  stepper.restore(cp.state, cp.memory,
                  fretbem::CyclePredictor::unflatten(cp.predictor, std::size_t(g.nx * g.ny),
                                                     model->tangential_operator->components()));
  stepper.run({}, 2);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  for (int k = 0; k < kTemplates; ++k) templates.push_back(make_template(k));
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  static const int only =
      std::getenv("FUZZ_TEMPLATE") ? std::atoi(std::getenv("FUZZ_TEMPLATE")) : -1;
  const Template& t = templates[only >= 0 ? only : in.ConsumeIntegralInRange(0, kTemplates - 1)];
  const fs::path dir = edited_copy(t, in);
  try {
    resume(dir);
  } catch (const fretbem::InputError&) {
  } catch (const fretbem::SolverError&) {
  }
  return 0;
}
