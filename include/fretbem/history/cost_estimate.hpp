// The cost model of a run, one table for every estimate made before a run (the memory guard,
// `fretbem check`, the progress ETA, the wear run's estimate in wear/cost_estimate.hpp):
// - memory: bytes per grid cell of each group of arrays, plus the program (estimate_memory);
// - time: FFT convolutions per step relative to a first step (step_cost_shares), counted and
//   timed by a ConvolutionMeter on the first steps of the path solved at the scenario's grid
//   (a calibration) and extrapolated to the whole path. Measured accuracy: docs/reliability.md
//   ("Accuracy of check's cost estimate"), docs/performance.md ("Memory").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fretbem/history/cycle_predictor.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

/// Bytes of a run's peak memory by what holds them (bytes). Per grid cell, measured as peak RSS
/// (docs/performance.md, "Memory"): the solver (FFT buffers and spectra of the padded grid,
/// the interface state, solver work fields, output buffers), the cycle predictor and the
/// Masing image (their tables and the heap they leave grown, MemoryCosts).
struct MemoryEstimate {
  double program = 0.0;    ///< libraries, FFTW and HDF5 state: independent of the grid
  double solver = 0.0;     ///< every run
  double predictor = 0.0;  ///< the cycle predictor (Model::cycle_predictor)
  double masing = 0.0;     ///< the Masing image (where it can apply, MasingImage::plan)
  double wear = 0.0;       ///< a wear run's surfaces, integrator vectors and warm starts
  double total() const { return program + solver + predictor + masing + wear; }
};

/// The table of memory costs (bytes per grid cell unless stated).
struct MemoryCosts {
  /// Peak RSS of a run at n = 16 (nothing grid-sized to speak of): 24.4 MiB, rounded up.
  static constexpr double kProgramBytes = 32.0 * (1 << 20);
  /// One tangential component under the analogy: the Mindlin cycle with solver.predictor =
  /// none measured 688 bytes per cell over the program at n = 512 (1 or 2 FFT threads, 8 or
  /// 128 steps) and 684 at n = 1024, the Cattaneo ramp 357-441 at n = 512-2048: the larger,
  /// rounded up.
  static constexpr double kSolverOneComponent = 750.0;
  /// Two tangential components or the Cerruti/coupled spectra: the Cattaneo ramp's 1.6x of
  /// one component at n = 512, on the one-component figure.
  static constexpr double kSolverTwoComponents = 1100.0;
  /// solver.monotone = shortcut: the corrective pressures and the tangent start's k_x solution
  /// kept between rows (and their checkpoint copies). A rough_monotone.ini member at n = 512
  /// peaked at 217.2 MiB with the tangent start against 209.1 MiB without, 32 bytes per cell:
  /// twice that, the margin the other shares keep.
  static constexpr double kShortcut = 64.0;
  /// The cycle predictor, measured as the peak RSS of a 2-cycle Mindlin run over the same run
  /// with solver.predictor = none less the Masing image's share: 378 (n = 128) and 516
  /// (n = 512) bytes per cell, far above its table's bound (CyclePredictor::kBytesPerCell):
  /// the heap grows at the end of the first reversal (the path's second turning point) by
  /// ~50 grid fields at n = 128 with the tables against ~18 without, and keeps that memory.
  static constexpr double kPredictor = 600.0;
  /// Per byte of the predictor's bound above CyclePredictor::kBytesPerCell (the sub-steps it
  /// remembers, predictor_bytes_per_cell): the varying-load sphere table of
  /// tools/bench/step_control_cost.py at n = 192 in 4 sub-steps a row peaked 883 bytes per cell
  /// above the same run with the sub-steps from the one before, for ~210 bytes per cell more
  /// entries (335 against the rows' ~125 on that table at n = 96): 4.2, as the rows' share
  /// above (the heap keeps what entries freed, checkpoints copy them), rounded up.
  static constexpr double kSubstepPredictorPerByte = 4.5;
  /// The Masing image (1-cycle Mindlin run over solver.predictor = none): 237 (n = 128) and
  /// 308 (n = 512) bytes per cell, its table bound MasingImage::kBytesPerCell included.
  static constexpr double kMasing = 350.0;
  /// A wear run (any wear.law) over the solver's share: rough_fretting_wear.ini to N = 1e5 at
  /// wear.rtol = 1e-2 (implicit TR-BDF2) peaked at 41.7, 83.5 and 269 MiB at n = 128, 256 and
  /// 512, 318, 186 and 226 bytes per cell above the program and the solver's share. The
  /// evaluations' path the normal solves start from (WearWarmStart::kBytesPerCell, 64 bytes) is
  /// held some four times more while a checkpoint is written (the checkpoint's copies and the
  /// HDF5 image's): with it the same run at n = 256 to N = 1e4 peaked at 107.6 MiB against
  /// 87.3 MiB without, 459 bytes per cell; the worn depth of the implicit integrator's latest
  /// evaluation, kept to answer its repeated Newton iterate (8 bytes per cell), adds to it: that,
  /// rounded up with the margin the other shares keep.
  static constexpr double kWear = 600.0;
};

/// The memory a run of `sc` needs at its peak; `cycle_predictor` as use_cycle_predictor
/// resolves solver.predictor for its path, `predictor_bytes` the predictor's memory bound
/// (bytes per cell, predictor_bytes_per_cell of the path): its part above
/// CyclePredictor::kBytesPerCell (remembered sub-steps) adds MemoryCosts::kSubstepPredictorPerByte
/// times itself to MemoryCosts::kPredictor. `repeat_bytes` (bytes per cell,
/// repeat_bytes_per_cell of the path) adds to the wear share.
MemoryEstimate estimate_memory(const Scenario& sc, bool cycle_predictor,
                               double predictor_bytes = CyclePredictor::kBytesPerCell,
                               double repeat_bytes = 0.0);

/// The ends of a carried wear cycle's steps that its coupled steps start from one cycle later
/// (Stepper::set_repeat_slot: cycle-by-cycle wear, solver.coupling = coupled, solver.predictor
/// not none), bytes per grid cell: two traction components and the pressure in doubles for
/// each step of a period, at most the path's steps and the period's closing step; 0 otherwise.
double repeat_bytes_per_cell(const Scenario& sc, const LoadPath& path);

/// CPU seconds and FFT convolutions of a half-space since construction: the one measurement the
/// calibrations (a stepped run's here, a wear run's in wear/cost_estimate.hpp) extrapolate.
class ConvolutionMeter {
 public:
  explicit ConvolutionMeter(const HalfSpace& half_space);
  double seconds() const;       ///< CPU seconds (process_cpu_seconds) since construction
  double convolutions() const;  ///< FFT convolutions since construction

 private:
  const HalfSpace& half_space_;
  double cpu0_;
  std::int64_t convolutions0_;
};

struct RunCostEstimate {
  double convolutions = 0.0;         ///< predicted FFT convolutions of the whole run
  double seconds = 0.0;              ///< predicted CPU time of the solves (s), outputs excluded
  int calibration_steps = 0;         ///< steps solved to calibrate (step 0 included)
  double calibration_seconds = 0.0;  ///< CPU time of the calibration, operators built (s)
  /// Under load.tolerance where the path's normal load changes: the convolutions at the ends
  /// of the measured range of the step control's rate (kCurvatureRateRange); 0 otherwise.
  double convolutions_low = 0.0, convolutions_high = 0.0;
};

/// Calibration budget: step 0 (the normal loading), then tangential steps until
/// kCalibrationSteps of them ran or the calibration took kCalibrationSeconds of CPU (at least
/// one).
inline constexpr int kCalibrationSteps = 4;
inline constexpr double kCalibrationSeconds = 1.0;

/// Cost of a tangential step after the path's second turning point (the first reversal
/// completed) relative to the first steps: the later half-cycles start from the stick set of
/// the previous one in the same direction. Measured steady/first-step convolution ratios:
/// 0.45 (Mindlin n = 64), 0.53 (n = 128), 0.59 (rough cycle n = 128), docs/reliability.md.
inline constexpr double kSettledStepShare = 0.5;
/// Cost of a step the cycle predictor starts (Model::cycle_predictor, a load transition seen
/// before) relative to the first steps: such a step usually meets the tolerance from its start
/// and costs one product. bench_cycle n = 256: 72 convolutions in cycle 2 and 64-76 from cycle 3
/// on against ~20 per first step (64 steps): 0.05-0.06; the shipped cyclic scenarios at n = 32
/// and the n = 64 Mindlin loop's ETA (test_cost_estimate) put the mean near 0.04.
inline constexpr double kPredictedStepShare = 0.04;

/// Cost of a step whose normal load changes (the Coulomb bound moves within it) relative to the
/// first such steps, at every stage of the path, a row's sub-steps each: neither settled nor
/// predicted steps start at their answer when the bound has moved since. Measured on
/// tools/bench/step_control_cost.py's cases (32 rows a period, 1 and 4 sub-steps a row): the
/// third period's rows cost 0.88-1.06x the lead-in's first rows (sphere, rough, displacement),
/// 1.06-1.58x under solver.coupling = cerruti; the first period's 1.1-1.4x.
inline constexpr double kMovingBoundStepShare = 1.0;

/// Under load.tolerance: the rate (1/period^2, PeriodRate) the step control settles at on a
/// path, over the time mean of |F''| / |F| along the rows whose normal load changes (F the
/// normal load, F'' its second divided difference at each row's end: the change of the rows'
/// slopes, the kinks the embedded estimate sees). The rate is not known from the calibrated
/// rows: after the calibration's four rows of tools/bench/step_control_cost.py's tables
/// (F_z = P (1 + 0.3 sin 2 pi t), 32 rows a period from t = -1/4) it measured 0.17-7.9 where the
/// runs' rate from the second period on averaged 1.19-2.05 (its five cases at 1e-3, 5e-4 and
/// 1e-4). Those averages over the path's curvature mean (8.12) are 0.15-0.25, and 0.13-0.29
/// with the bench's sphere at n = 48 under normal-load amplitudes 0.1, 0.3 and 0.5 and a
/// tangential amplitude of 0.25 mu P (1e-3): the middle, rounded. Measured on sinusoidal
/// normal loads only.
inline constexpr double kCurvatureRateFactor = 0.2;
/// The range of that ratio `fretbem check` prints beside its estimate: the 19 runs above within
/// 0.13-0.29, and the Cerruti case at n = 32 and 1e-3 at about 0.11 (its third period's
/// step_error 9.2e-4: its rows stayed whole where 0.2 forecasts 2 sub-steps), rounded
/// outwards. A row's sub-steps jump by one where Δt √(rate/ε) crosses an integer, so near such
/// a crossing no single rate holds a factor 1.5.
inline constexpr double kCurvatureRateRange[2] = {0.1, 0.3};

/// Each step's cost relative to a first tangential step (step 0 counts 1 too): 1 up to the
/// path's second turning point, kSettledStepShare after it, kPredictedStepShare where the
/// cycle predictor starts the step; a step the Masing image starts counts kSettledStepShare
/// before the second turning point and kPredictedStepShare after it; a row solved in m
/// sub-steps (row_substeps, history/step_control.hpp) whose normal load changes counts
/// m x kMovingBoundStepShare, whether the cycle predictor starts it or not (it saves a fifth of
/// them, not the predicted rows' 0.96); a row that repeats the row before it counts
/// kPredictedStepShare. Under solver.coupling = coupled (cross-coupled bodies) every other step
/// counts 1 (m for a row in m sub-steps): its alternations cost as much in every cycle. What
/// the estimate extrapolates with and what a run's progress ETA counts on.
std::vector<double> step_cost_shares(const Model& model);

/// Builds the model (operators included), solves the first steps and extrapolates: the
/// convolutions of step 0 plus the mean of the calibrated tangential steps (a row's sub-steps
/// each, a row solved again counted twice; rows that repeat the row before are solved but not
/// calibrated on) times the steps left, each at its step_cost_shares share; seconds =
/// convolutions x the calibration's CPU seconds per convolution. Under load.tolerance a row
/// whose normal load changes counts the sub-steps substeps_for gives it at the rate
/// kCurvatureRateFactor predicts, and until the end of the path's first whole period at the
/// calibration's rate where that is larger (the rate is never lowered before a period is
/// solved). Writes no file. Not for wear runs (estimate_wear_cost).
RunCostEstimate estimate_run_cost(const Scenario& sc);

/// The report line(s) of `fretbem check`, each ending in '\n'.
std::string describe(const RunCostEstimate& e, std::size_t steps);

}  // namespace fretbem
