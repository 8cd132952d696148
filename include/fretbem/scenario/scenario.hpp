// Scenario: a validated simulation description in SI units, read from an INI file
// (Boost.Program_options syntax) plus `section.key=value` overrides (README "Scenario files").
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fretbem/core/solver_options.hpp"
#include "fretbem/elastic/grid.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "fretbem/elastic/material.hpp"
#include "fretbem/surface/surface.hpp"

namespace fretbem {

enum class SurfaceType { sphere, flat, rough, file };
enum class PathType { none, ramp, sine, table };
enum class Control { force, displacement };
/// How a load table joins its rows: straight lines, or a not-a-knot cubic spline (C2).
enum class LoadInterpolation { linear, cubic };
enum class TangentialAlgorithm { projected, partition };
/// When the exact differential stiffness kx is computed (solver.stiffness): every step, only at
/// the ends of monotone segments (step 0, turning points, the last step), or never. Rows
/// without it carry kx = nan.
enum class StiffnessMode { every, turning, none };
/// solver.predictor: where a tangential increment may start (CyclePredictor). automatic: cycle
/// when the load path repeats a transition and the remembered tractions fit in memory.
enum class PredictorMode { automatic, none, cycle };
/// solver.fft_plan: how FFTW plans are chosen (Scenario::Solver::fft_plan).
enum class FftPlanning { automatic, estimate, measure };
/// solver.monotone: how virgin monotone segments are solved.
enum class MonotoneMethod { incremental, shortcut };
enum class WearLaw { none, archard, energy };
/// arkode: erk or dirk, whichever the run's length against the explicit stability cap favours.
enum class WearIntegrator { arkode, cycle, erk, dirk };
/// Newton iteration of the implicit (dirk) wear integrator: modified Newton with the frozen-slip
/// Newton matrix (WearPreconditioner), or Jacobian-free Newton–Krylov (SPGMR, finite-difference
/// Jacobian-vector products of the wear map, the frozen-slip matrix as preconditioner).
enum class WearNewton { frozen, krylov };

struct SurfaceSpec {
  SurfaceType type = SurfaceType::sphere;
  double radius = 0.0;         ///< sphere radius (m)
  RoughSpec rough;             ///< rough surfaces
  std::filesystem::path file;  ///< file surfaces (resolved against the scenario's folder)
  std::string dataset;         ///< HDF5 dataset or .npz entry of file surfaces ("" = the only one)
  /// Axis order of .npy/.npz/.h5/text height maps (x3p files carry their own).
  HeightLayout layout = HeightLayout::yx;
  /// surface.spacing: the height map's grid spacing (m), checked against grid.length / n and
  /// against the spacing the file carries (x3p, .npz entry or HDF5 attribute `spacing`).
  std::optional<double> spacing;
};

struct LoadSpec {
  std::optional<double> normal_force;  ///< constant normal force (N)
  std::optional<double> indentation;   ///< constant indentation (m)
  PathType path = PathType::none;
  Control control = Control::force;
  double amplitude = 0.0;               ///< tangential amplitude / (mu F_z) (force control)
  double displacement_amplitude = 0.0;  ///< tangential amplitude (m) (displacement control)
  double direction = 0.0;               ///< direction of the path in the x-y plane (degrees)
  int cycles = 1;
  int steps_per_cycle = 64;
  int steps = 20;
  std::filesystem::path table;  ///< CSV path table (resolved against the scenario)
  /// load.allow_large_shift: run displacement amplitudes and table shifts past the small-slip
  /// bound (kMaxShiftOverContactRadius contact radii, history/preflight.hpp).
  bool allow_large_shift = false;
  /// load.tolerance: the relative error per period that the steps of rows whose normal load
  /// changes may carry (history/step_control: an embedded estimate, sub-steps within the
  /// row); 0: one solve a row.
  double tolerance = 0.0;
  /// load.substeps: without load.tolerance, the equal sub-steps in which each row whose normal
  /// load changes is solved (history/step_control.hpp); 1: one solve a row. Wear runs solve
  /// their rows whole (1), and so do coupled runs unless the key is given
  /// (resolve_load_substeps, scenario/sections.cpp).
  int substeps = 4;
  /// load.interpolation: how a table's load runs between its rows: linear, or cubic (a
  /// not-a-knot spline through the rows, history/load_spline.hpp), which sub-steps follow and
  /// under which the work of nodes slipping through consecutive steps takes the three-point
  /// rule (contact/step_work.hpp). The rows themselves are the same either way.
  LoadInterpolation interpolation = LoadInterpolation::linear;
};

struct SolverSpec {
  /// Relative residual of normal and tangential solves. 1e-8: the errors against the closed
  /// forms (bench_accuracy_vs_time, docs/performance.md) are those of 1e-10 to 3-4 digits up
  /// to n = 512, at 0.7-0.8x the time.
  double tolerance = 1e-8;
  int max_iterations = 5000;
  Coupling coupling = Coupling::analogy;
  /// coupled: the normal and tangential solves of a step alternate until the rms change of
  /// the pressure (relative to its rms) and of the traction (relative to the rms bound mu p)
  /// from one alternation to the next are both at most coupling_tolerance, in at most
  /// coupling_iterations alternations (else the step fails, naming it).
  double coupling_tolerance = 1e-6;
  int coupling_iterations = 50;
  int threads = 0;  ///< 0: all cores
  TangentialAlgorithm algorithm = TangentialAlgorithm::projected;
  StiffnessMode stiffness = StiffnessMode::every;  ///< which steps compute kx
  /// solver.fft_plan: estimate (the default): ESTIMATE plans, no measuring, no file, the same
  /// bits with any thread count; measure: FFTW_MEASURE plans, measured once per size and thread
  /// count and kept as wisdom (fft_wisdom.hpp); automatic: measure when the wisdom file can be
  /// kept (fft_wisdom::persistent), else estimate. Measured plans are chosen per thread count,
  /// so they give the same bits only at the same count (the ensemble's members: one thread).
  FftPlanning fft_plan = FftPlanning::estimate;
  /// float32: single-precision convolutions (opt-in; the default tolerance is then
  /// kFloatFftMinTolerance and smaller ones are refused).
  FftPrecision fft_precision = FftPrecision::float64;
  /// shortcut: virgin monotone segments at constant normal load by the Ciavarella–Jäger
  /// superposition (analogy, collinear paths) instead of incremental solves.
  MonotoneMethod monotone = MonotoneMethod::incremental;
  /// solver.predictor: cycle: a tangential increment also tries, as its start, the traction of
  /// the same step one load cycle earlier (the step with the same previous and current load);
  /// none: it does not; automatic (the default): cycle where it is safe (use_cycle_predictor).
  /// The remembered tractions are part of the checkpoint (a resume is byte-identical).
  PredictorMode predictor = PredictorMode::automatic;
  /// Fourier preconditioning of the normal CG and the tangential projected CG; automatic: the
  /// measured rules (normal: from 256 x 256 cells; tangential: contact patch >= 2048 nodes).
  Precondition precondition = Precondition::automatic;
};

struct OutputSpec {
  std::filesystem::path dir = "out";
  std::vector<std::string> fields;  ///< subset of pressure, traction_x, traction_y, state,
                                    ///< slip_x, slip_y, dissipation, wear
  int fields_every = 0;             ///< 0: only at turning points and the last step
  /// Restart checkpoint (DIR/checkpoint.h5) every this many steps; 0: every 10 s of run time,
  /// at turning points and at the end.
  int checkpoint_every = 0;
};

/// wear.rtol's range, and wear.atol's relative to the unworn indentation (measured):
/// past 0.1 the error control no longer holds the worn depth (rtol or atol/delta0 = 1 leaves it
/// 3.5 % off, 1e300 3.8 times, with exit 0); below 1e-14 ARKODE's steps fail (1e-300, 1e-30).
inline constexpr double kMinWearRelTolerance = 1e-14, kMaxWearRelTolerance = 0.1;

struct WearSpec {
  WearLaw law = WearLaw::none;
  double coefficient = 0.0;  ///< Archard k (1/Pa) or energy alpha (m^3/J = 1/Pa)
  double cycles = 0.0;       ///< cycle count N to integrate to
  WearIntegrator integrator = WearIntegrator::arkode;
  /// ARKODE tolerances on the worn depth W: relative, and absolute (m); atol = 0 (not given):
  /// rtol x the indentation of the unworn surface.
  double rtol = 1e-3, atol = 0.0;
  WearNewton newton = WearNewton::frozen;
  /// Share of the worn depth taken by the indenter, the rest by the half-space (split
  /// between the two bodies with a ratio when both wear); 1 = indenter only.
  double indenter_share = 1.0;
};

enum class FrictionLawKind { constant, static_kinetic, evolving };
/// What an evolving mu follows: the node's accumulated dissipated energy density (J/m^2) or
/// its accumulated slip path (m).
enum class FrictionVariable { dissipation, slip_path };

/// The friction keys of a scenario ([friction] section; mu itself is material.mu).
struct FrictionSpec {
  FrictionLawKind law = FrictionLawKind::constant;
  double mu_kinetic = 0.0;  ///< static_kinetic: mu once a node slips (material.mu: while stuck)
  double mu_final = 0.0;    ///< evolving: mu after a long history (material.mu: at the start)
  FrictionVariable evolution = FrictionVariable::dissipation;  ///< friction.evolution
  double scale = 0.0;  ///< evolving: J/m^2 or m over which mu moves 1 - 1/e of the way
};

struct Scenario {
  std::string name;                     ///< file stem
  std::string resolved_text;            ///< every key with its final value, INI syntax
  std::vector<std::string> given_keys;  ///< keys the file and overrides set (sorted)
  Material material;
  Grid grid;
  SurfaceSpec surface;
  LoadSpec load;
  SolverSpec solver;
  OutputSpec output;
  WearSpec wear;
  FrictionSpec friction;
  /// grid.allow_edge_contact: run even when a free-boundary grid carries more than
  /// kEdgeLoadShareLimit of the normal load on its outermost cells.
  bool allow_edge_contact = false;
};

/// Reads, merges overrides ("section.key=value", applied after the file) and validates.
/// Throws InputError with one line naming the file, key and value on any problem; unknown
/// keys are rejected with the nearest valid name.
Scenario load_scenario(const std::filesystem::path& file,
                       const std::vector<std::string>& overrides = {});
/// Same from text (name used in messages; relative paths resolve against base_dir).
Scenario parse_scenario(const std::string& text, const std::string& name,
                        const std::filesystem::path& base_dir,
                        const std::vector<std::string>& overrides = {});

/// Sets output.dir (e.g. from `run --out DIR`) and rewrites resolved_text to match, so the
/// scenario stored in result files names the folder the run actually wrote.
void set_output_dir(Scenario& scenario, const std::filesystem::path& dir);

}  // namespace fretbem
