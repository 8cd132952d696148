// Work of an ODE wear run counted in FFT convolutions, which load does not change: where a
// wear-map evaluation's products go (the measured loop's steps, the implicit method's inner CG
// of the Newton matrix, and the rest: the normal solve, the virgin step and its corrective
// solve, the unworn indentation probe) and the run's end state, worn volume (m^3) and largest
// worn depth (m), to compare two programs or tolerances. CPU seconds are the process's.
//
// Usage: bench_wear_map SCENARIO.ini [--set section.key=value ...]
//   e.g. bench_wear_map scenarios/rough_fretting_wear.ini --set grid.n=128
//        --set wear.cycles=1e5 --set wear.rtol=1e-2 --set solver.threads=1
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "fretbem/core/progress.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/wear/integrator.hpp"

using namespace fretbem;

namespace {

// Products of the rows a run emits: the measured loops of its evaluations.
struct LoopProducts final : Observer {
  long products = 0;
  void on_step(const StepRecord& r, const InterfaceState&, const Model&) override {
    products += r.convolutions;
  }
};

void usage(int status) {
  bench::exit_with_usage(status,
                         "usage: bench_wear_map SCENARIO.ini [--set section.key=value ...]\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help")) usage(argc < 2 ? 2 : 0);
  std::vector<std::string> sets;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--set") || i + 1 >= argc) usage(2);
    sets.emplace_back(argv[++i]);
  }
  const double load = bench::load_average();
  const double cpu0 = process_cpu_seconds();
  auto model = build_model(load_scenario(argv[1], sets));
  Stepper stepper(*model);
  LoopProducts loop;
  WearCycles cycles(*model, stepper, {&loop});
  Observer quiet;
  const WearReport r = integrate_wear(*model, cycles, quiet);
  const double cpu = process_cpu_seconds() - cpu0;
  const long total = long(model->half_space->convolutions());
  const double e = std::max(1, r.rhs_evaluations);
  const double h2 = model->scenario.grid.cell_area();
  std::printf(
      "load average %.1f (start)\nN = %g: %.1f simulated cycles, %d evaluations, %ld steps, %ld "
      "Newton iterations\nproducts: %ld in all, %.1f per evaluation (loop %.1f, inner CG %.1f, "
      "rest %.1f)\nworn volume %.6e m^3, max worn depth %.6e m\nCPU %.2f s\n",
      load, r.N, r.simulated_cycles, r.rhs_evaluations, r.steps, r.newton_iterations, total,
      total / e, loop.products / e, r.inner_iterations / e,
      (total - loop.products - r.inner_iterations) / e, r.worn.sum() * h2, r.worn.maxCoeff(), cpu);
  return 0;
}
