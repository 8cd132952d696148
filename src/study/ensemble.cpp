#include "fretbem/study/ensemble.hpp"

#include <algorithm>
#include <boost/math/distributions/students_t.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "fretbem/core/csv_reader.hpp"
#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/output_lock.hpp"
#include "fretbem/core/resources.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/core/text_file.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/study/member_pool.hpp"
#include "fretbem/study/member_status.hpp"
#include "fretbem/study/mpi_queue.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One member: its surface, its folder below the ensemble's, and, once the pool is done, what
// its status file says.
struct Member {
  double hurst = 0;
  int seed = 0;
  fs::path dir;
  MemberStatus status;
  bool ok = false;  ///< finished with exit 0 and its time series read
};

}  // namespace

std::vector<double> parse_hurst_list(const std::string& list) {
  std::vector<double> out;
  for (const std::string& tok : csv::split_line(list)) {
    double v = 0;
    const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (tok.empty() || r.ec != std::errc() || r.ptr != tok.data() + tok.size() ||
        !(v > 0 && v <= 1))
      throw InputError("--hurst: '" + tok + "' is not a Hurst exponent in (0, 1]");
    // One member directory per (H, seed): a repeated H would run into the same directory
    // and count its members twice.
    if (std::find(out.begin(), out.end(), v) != out.end())
      throw InputError("--hurst: " + format_number(v) + " is listed twice");
    out.push_back(v);
  }
  if (out.empty()) throw InputError("--hurst: empty list");
  return out;
}

fs::path member_dir(double hurst, int seed) {
  char s[32];
  std::snprintf(s, sizeof s, "seed_%03d", seed);
  std::string h = "H";  // appended, not "H" + ...: GCC 12 -Wrestrict false positive
  h += format_number(hurst);
  return fs::path(h) / s;
}

namespace {

// What the aggregate needs of every member (without each of these an ensemble runs to exit 0
// and aggregates nothing): seeds and H change a rough surface only (a sphere gives identical
// members and a zero-width interval), k_x at every step (`none`/`turning` leave every k_x
// column nan), and a tangential path (without one every bin is empty).
void refuse_unaggregatable(const Scenario& sc, const fs::path& file) {
  const std::string where = file.string() + ": ensemble: ";
  if (sc.surface.type != SurfaceType::rough)
    throw InputError(where +
                     "surface.type must be rough (--hurst and --seeds vary a rough surface; "
                     "every member of another surface would be the same run)");
  if (sc.solver.stiffness != StiffnessMode::every)
    throw InputError(where +
                     "solver.stiffness must be every (the aggregate's k_x/k_x0 needs k_x "
                     "at every step)");
  if (sc.load.path == PathType::none)
    throw InputError(where +
                     "load.path = none has no tangential load to aggregate over "
                     "F_x/(mu F_z); use ramp (as rough_monotone.ini)");
}

// Settings every member starts from. One FFT thread: members run side by side. fft_plan = auto:
// measured plans (2-8 % less CPU per member, docs/performance.md), which
// measure_plans_once has put in the wisdom file, so every member (and a user rerunning one
// with the same file) plans from the same wisdom and gets the same bits. monotone = shortcut:
// the aggregate reads the virgin ramp, where the Ciavarella–Jäger superposition is exact
// and costs about 15 % fewer convolutions than the incremental solve (docs/performance.md); a
// scene it does not hold for is solved incrementally.
const std::vector<std::string>& member_defaults() {
  static const std::vector<std::string> d{"solver.threads=1", "solver.fft_plan=auto",
                                          "solver.monotone=shortcut"};
  return d;
}

// Measures the members' FFT plans once, here, before they start: members then find them in the
// wisdom file instead of waiting on its lock one after another (about 0.8 s at n = 256).
void measure_plans_once(const Scenario& sc) {
  const FftOptions fft = fft_options(sc);  // the members' own, as build_model resolves them
  if (fft.measure) {
    const HalfSpace plans(sc.grid, sc.material, sc.solver.coupling, fft);
  }
}

// The members as the study pool runs them: single-threaded FFTs with measured plans first
// (member_defaults), so that a user's --set still wins, then the user's overrides, then the
// member's surface. The command line is what a user types to rerun a member alone (see
// docs/paper-reproduction.md).
StudyMembers study_members(const EnsembleOptions& o, const std::vector<Member>& members) {
  StudyMembers m;
  m.scenario = o.scenario, m.out = o.out, m.defaults = member_defaults();
  m.count = members.size();
  m.dir = [&members](std::size_t k) { return members[k].dir; };
  m.sets = [&o, &members](std::size_t k) {
    std::vector<std::string> sets = o.sets;
    sets.push_back("surface.hurst=" + format_number(members[k].hurst));
    sets.push_back("surface.seed=" + std::to_string(members[k].seed));
    return sets;
  };
  return m;
}

// Runs the members that are not complete yet (every member with --overwrite), at most `jobs`
// at a time, and reads back each one's status. False when SIGTERM or SIGINT stopped them.
bool run_members(const EnsembleOptions& o, std::vector<Member>& members) {
  const StudyMembers study = study_members(o, members);
  PoolOptions pool;
  pool.jobs = o.jobs, pool.quiet = o.quiet, pool.binary = o.binary;
  pool.label = "fretbem ensemble", pool.restart = o.overwrite;
  pool.in_process = o.in_process;
  std::vector<std::size_t> todo;
  for (std::size_t k = 0; k < members.size(); ++k) todo.push_back(k);
  if (!o.overwrite) todo = pending_members(study);
  const bool finished = run_study_members(study, *make_local_queue(todo), pool);
  for (std::size_t k = 0; k < members.size(); ++k) {
    members[k].status = read_member_status(study.path(k));
    members[k].ok = member_complete(study, k);
  }
  return finished;
}

}  // namespace

MemberCurve read_member_curve(const fs::path& csv_file, double mu) {
  const auto table = csv::read_table(csv_file, {.allow_nan = true});
  auto col = [&](const std::string& name) {
    const long i = table.find(name);
    if (i < 0) throw InputError(csv_file.string() + ": no column '" + name + "'");
    return static_cast<std::size_t>(i);
  };
  const std::size_t cFz = col("Fz"), cFx = col("Fx"), cA = col("contact_area"),
                    cS = col("stick_area"), cFs = col("Fx_stick"), cK = col("kx");
  MemberCurve c;
  double A0 = 0, k0 = 0;
  for (std::size_t row = 0; row < table.rows.size(); ++row) {
    const auto& v = table.rows[row];
    const double muFz = mu * v[cFz], f = v[cFx] / muFz;
    if (row == 0) A0 = v[cA], k0 = v[cK];
    if (!c.f.empty() && !(f > c.f.back())) continue;  // only where F_x still rises
    c.f.push_back(f);
    c.stick.push_back(v[cS] / A0);
    c.kx.push_back(v[cK] / k0);
    c.fstick.push_back(v[cFs] / muFz);
  }
  if (c.f.empty()) throw InputError(csv_file.string() + ": no rows");
  return c;
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xq) {
  if (x.empty() || !(xq >= x.front() && xq <= x.back())) return kNaN;
  std::size_t i = 1;
  while (i + 1 < x.size() && x[i] < xq) ++i;
  if (x.size() == 1) return y[0];
  const double t = (xq - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + t * (y[i] - y[i - 1]);
}

MeanCi mean_ci95(const std::vector<double>& v) {
  MeanCi r;
  double s = 0, s2 = 0;
  for (double x : v)
    if (std::isfinite(x)) ++r.n, s += x;
  if (r.n == 0) return {kNaN, kNaN, 0};
  r.mean = s / r.n;
  for (double x : v)
    if (std::isfinite(x)) s2 += (x - r.mean) * (x - r.mean);
  if (r.n < 2) return r.half_width = kNaN, r;
  const boost::math::students_t t(r.n - 1);
  r.half_width = boost::math::quantile(t, 0.975) * std::sqrt(s2 / (r.n - 1) / r.n);
  return r;
}

namespace {

// DIR/members.csv: one row per member with exit code, wall time of its last attempt and status
// (the words of sweep.csv); a member never started has exit code -1.
void write_members(const fs::path& file, const std::vector<Member>& members) {
  std::ostringstream out;
  out << "hurst,seed,dir,exit_code,wall_seconds,status\n";
  for (const auto& m : members)
    out << format_number(m.hurst) << ',' << m.seed << ',' << m.dir.generic_string() << ','
        << m.status.exit_code << ',' << format_number(m.status.seconds) << ','
        << member_status_word(m.status, m.ok) << '\n';
  write_file_atomically(file, out.str());
}

// An aggregate cell without a value (a mean over no member, an interval of fewer than two)
// stays empty: a reader's CSV parser then sees a missing value, never a NaN to average over.
std::string cell(double v) {
  return std::isfinite(v) ? format_number(v) : "";
}

// DIR/aggregate.csv: per H and bin, each member's curve interpolated at the bin centre (not
// raw points binned), then mean and 95 % Student-t interval over the members covering it.
using Curves = std::map<const Member*, MemberCurve>;

// Reads every successful member's curve; a member whose time series cannot be read counts as
// failed (exit code -1) and is reported.
Curves load_curves(const EnsembleOptions& o, std::vector<Member>& members, double mu) {
  Curves curves;
  for (auto& m : members) {
    if (!m.ok) continue;
    try {
      curves[&m] = read_member_curve(o.out / m.dir / "timeseries.csv", mu);
    } catch (const std::exception& e) {
      m.ok = false, m.status.exit_code = -1;
      std::fprintf(stderr, "fretbem ensemble: member %s: %s\n", m.dir.string().c_str(), e.what());
    }
  }
  return curves;
}

void write_aggregate(const EnsembleOptions& o, const std::vector<Member>& members,
                     const Curves& all) {
  std::ostringstream out;
  out << "hurst,bin,f_lo,f_hi,f_centre,members,failed,stick_area_mean,stick_area_ci95,"
         "kx_mean,kx_ci95,Fx_stick_mean,Fx_stick_ci95\n";
  for (double H : o.hurst) {
    std::vector<MemberCurve> curves;
    int failed = 0;
    for (const auto& m : members) {
      if (m.hurst != H) continue;
      if (!m.ok)
        ++failed;
      else
        curves.push_back(all.at(&m));
    }
    for (int b = 0; b < o.bins; ++b) {
      const double lo = double(b) / o.bins, hi = double(b + 1) / o.bins, fc = 0.5 * (lo + hi);
      std::vector<double> A, K, Fs;
      for (const auto& c : curves) {
        A.push_back(interpolate(c.f, c.stick, fc));
        K.push_back(interpolate(c.f, c.kx, fc));
        Fs.push_back(interpolate(c.f, c.fstick, fc));
      }
      const MeanCi a = mean_ci95(A), k = mean_ci95(K), s = mean_ci95(Fs);
      out << format_number(H) << ',' << b << ',' << cell(lo) << ',' << cell(hi) << ',' << cell(fc)
          << ',' << a.n << ',' << failed << ',' << cell(a.mean) << ',' << cell(a.half_width) << ','
          << cell(k.mean) << ',' << cell(k.half_width) << ',' << cell(s.mean) << ','
          << cell(s.half_width) << '\n';
    }
  }
  // Whole or not at all: an unchecked stream on a full disk leaves a truncated file and exit 0.
  write_file_atomically(o.out / "aggregate.csv", out.str());
}

}  // namespace

int run_ensemble(const EnsembleOptions& opt) {
  EnsembleOptions o = opt;
  if (o.hurst.empty()) throw InputError("ensemble: --hurst is required");
  if (o.seeds < 1 || o.seeds > kMaxSeeds)
    throw InputError("--seeds: must be in [1, " + std::to_string(kMaxSeeds) + "], got " +
                     std::to_string(o.seeds));
  if (o.jobs < 0) throw InputError("--jobs: must be >= 1, got " + std::to_string(o.jobs));
  if (o.bins < 1 || o.bins > kMaxBins)
    throw InputError("--bins: must be in [1, " + std::to_string(kMaxBins) + "], got " +
                     std::to_string(o.bins));
  if (o.jobs == 0) o.jobs = usable_cpus();  // affinity mask and SLURM_CPUS_PER_TASK
  if (o.binary.empty()) o.binary = fs::read_symlink("/proc/self/exe");
  // Validate every member's scenario up front (one line naming the key on bad input).
  double mu = 0;
  std::optional<Scenario> member;
  for (double H : o.hurst) {
    auto sets = member_defaults();
    sets.insert(sets.end(), o.sets.begin(), o.sets.end());
    sets.push_back("surface.hurst=" + format_number(H));
    member = load_scenario(o.scenario, sets);
    refuse_unaggregatable(*member, o.scenario);
    mu = member->material.mu;
  }
  if (o.out.empty()) o.out = fs::path("out") / ("ensemble_" + o.scenario.stem().string());
  // One ensemble per folder at a time: two would start the same members and each overwrite
  // the other's aggregate. A re-run into the folder continues the ensemble there.
  const OutputLock lock(o.out, "ensemble");
  std::vector<Member> members;
  for (double H : o.hurst)
    for (int s = 1; s <= o.seeds; ++s) {
      Member m;
      m.hurst = H, m.seed = s, m.dir = member_dir(H, s);
      members.push_back(m);
    }
  install_stop_signal_handlers();
  measure_plans_once(*member);  // grid, material and solver are those of every member
  const bool complete = run_members(o, members);
  const Curves curves = load_curves(o, members, mu);
  write_members(o.out / "members.csv", members);
  write_aggregate(o, members, curves);
  int not_ok = 0;
  for (const auto& m : members) not_ok += !m.ok;
  if (!complete)
    std::fprintf(stderr, "fretbem ensemble: stopped by a signal; %d of %zu member(s) finished\n",
                 int(members.size()) - not_ok, members.size());
  return complete ? not_ok : kEnsembleStopped;
}

}  // namespace fretbem
