// Ensemble runs: one scenario over Hurst exponents x seeds, members as independent
// `fretbem run` processes (single-threaded FFTs each), then an aggregate of the paper's
// normalised curves (Figs. 2–4) per H and bin of F_x/(mu F_z): mean and Student-t 95 % interval.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "fretbem/study/member_launcher.hpp"

namespace fretbem {

struct EnsembleOptions {
  std::filesystem::path scenario;
  std::vector<std::string> sets;  ///< --set overrides, applied before the member's H and seed
  std::vector<double> hurst;
  int seeds = 20;  ///< surface.seed = 1..seeds
  int jobs = 0;    ///< concurrent members; 0: all cores
  int bins = 20;   ///< bins of F_x/(mu F_z) over [0, 1]
  std::filesystem::path out;
  std::filesystem::path binary;  ///< the fretbem executable members run (default: this one)
  MemberEntry in_process;        ///< members in worker processes (PoolOptions::in_process)
  bool quiet = false;
  /// Run every member afresh; without it a re-run into `out` continues the ensemble there:
  /// complete members are kept, stopped ones continue from their checkpoint, failed and
  /// missing ones run again (as `fretbem sweep`).
  bool overwrite = false;
};

/// Largest --bins: an aggregate row per bin and H; 10^4 bins already resolve F_x/(mu F_z)
/// far below any member's load step (10^8 bins would write a 17 GB file).
constexpr int kMaxBins = 10000;
/// Largest --seeds (surface.seed = 1..seeds): --seeds 2147483647 would loop forever (the
/// seed counter overflows) while the member list grows.
constexpr int kMaxSeeds = 100000;

/// "0.1,0.3" -> {0.1, 0.3}; InputError naming --hurst on a bad list or a repeated value.
std::vector<double> parse_hurst_list(const std::string& list);
/// Member directory below the ensemble output: H0.3/seed_007.
std::filesystem::path member_dir(double hurst, int seed);

/// One member's monotone curves in the paper's normalisation, strictly increasing in f.
struct MemberCurve {
  std::vector<double> f;       ///< F_x / (mu F_z)
  std::vector<double> stick;   ///< A_stick / A0 (A0: contact area of row 0)
  std::vector<double> kx;      ///< k_x / k_x0 (k_x0: row 0)
  std::vector<double> fstick;  ///< F_x,stick / (mu F_z)
};
/// Reads DIR/timeseries.csv; keeps only rows where f rises (later rows repeat full sliding).
MemberCurve read_member_curve(const std::filesystem::path& csv, double mu);
/// Linear interpolation of (x, y), x strictly increasing, at xq; NaN outside [x0, x_last].
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xq);

struct MeanCi {
  double mean = 0, half_width = 0;  ///< 95 % two-sided Student-t interval half width
  int n = 0;
};
/// Mean and t_{0.975, n-1} s / sqrt(n) of the finite values (NaN half width when n < 2).
MeanCi mean_ci95(const std::vector<double>& v);

/// run_ensemble's result when SIGTERM or SIGINT stopped it.
constexpr int kEnsembleStopped = -1;

/// Runs the members that are not complete (study/member_pool.hpp), writes DIR/members.csv and
/// DIR/aggregate.csv; returns the number of members not ok (failed, each reported on stderr,
/// or left to a run of an earlier, killed ensemble that still writes into it), or
/// kEnsembleStopped when a signal ended the running members (members.csv and aggregate.csv are
/// still written, of the finished members; members never started have exit code -1). Throws
/// InputError on bad options.
int run_ensemble(const EnsembleOptions& opt);

}  // namespace fretbem
