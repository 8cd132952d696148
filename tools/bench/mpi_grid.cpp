// Strong scaling of the distributed grid (docs/mpi-grid.md): for each n, the wall time of one
// convolution (HalfSpace::normal, free grid, padded 2n x 2n) on the ranks of this mpirun and,
// as the unit, of the serial convolution of the same grid measured in the same run on every
// rank at once; the distributed convolution's split into moving rows (MPI_Alltoallv), the
// FFTW-MPI transforms and, inside those, the two global transposes (timed alone); and one
// cold Hertz normal solve (contact radius L/4, force control, 1e-10) distributed and serial,
// then one Cattaneo increment on its pressure (projected CG from zero traction to
// F_x = 0.5 mu F_z, force control, 1e-10, plain CG).
// Medians over --repeats; wall times are the slowest rank's.
//
// Usage: mpirun -n K bench_mpi_grid [--min-n N] [--max-n N] [--repeats R] [--solve-max-n N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "bench_util.hpp"
#include "fretbem/contact/normal_solver.hpp"
#include "fretbem/contact/tangential_solver.hpp"
#include "fretbem/elastic/half_space.hpp"

using namespace fretbem;

namespace {

struct Options {
  int min_n = 512, max_n = 2048, repeats = 5, solve_max_n = 1024;
};

void usage(int status) {
  bench::exit_with_usage(status,
                         "usage: mpirun -n K bench_mpi_grid [--min-n N] [--max-n N] [--repeats R] "
                         "[--solve-max-n N]\n");
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Median over repeats of the slowest rank's wall time of f().
template <class F>
double timed(const Communicator& c, int repeats, F&& f) {
  std::vector<double> s;
  for (int r = 0; r < repeats; ++r) {
    c.sum(0.0);  // a barrier
    const double t0 = now();
    f();
    s.push_back(c.max(now() - t0));
  }
  return median(s);
}

Field slab(const HalfSpace& hs, const Field& f) {
  return f.middleCols(hs.first_row(), hs.local_rows());
}

// One force-controlled increment from zero traction to F_x on the bounds g (serial) and gd
// (this rank's slab): iterations and the slowest rank's wall seconds, serial then distributed.
void cattaneo_increment(const Communicator& c, HalfSpace& serial, HalfSpace& dist, const Field& g,
                        const Field& gd, double Fx) {
  int its = 0, itd = 0;
  auto solve = [&](HalfSpace& hs, const Field& bound, int& iterations) {
    TangentialOperator op(hs, Vec2(1, 0));
    ProjectedCgSolver solver(op, {1e-10, 5000, Precondition::off});
    const VecField tau0 = op.zeros(), u0 = op.zeros();
    VecField tau = tau0, u = u0;
    const TangentialIncrement inc{&bound, &tau0, &u0, TangentialControl::force,
                                  Eigen::VectorXd::Constant(1, Fx)};
    iterations = solver.solve(inc, tau, u).iterations;
  };
  const double ts = timed(c, 1, [&] { solve(serial, g, its); });
  const double td = timed(c, 1, [&] { solve(dist, gd, itd); });
  if (c.rank() == 0) std::printf("  %4d %9.3f %4d %9.3f %6.3f", its, ts, itd, td, td / ts);
}

void row(const Communicator& c, int n, const Options& o) {
  const Material m{Body{210e9, 0.3}, std::nullopt, 0.3};
  const Grid g = Grid::square(n, 1e-3);
  HalfSpace serial(g, m, Coupling::analogy);
  HalfSpace dist(g, m, Coupling::analogy, {}, c);
  const Field p = Field::Random(n, n).abs() * 1e6, pd = slab(dist, p);
  Field u;
  serial.normal(p, u), dist.normal(pd, u);  // warm-up
  const double unit = timed(c, o.repeats, [&] { serial.normal(p, u); });
  const HalfSpace::MpiTimes t0 = dist.mpi_times();
  const double conv = timed(c, o.repeats, [&] { dist.normal(pd, u); });
  const HalfSpace::MpiTimes t1 = dist.mpi_times();
  const double moving = c.max(t1.moving - t0.moving) / o.repeats;
  const double transforming = c.max(t1.transforming - t0.transforming) / o.repeats;
  const double transpose = dist.mpi_transpose_seconds(o.repeats);
  if (c.rank() == 0)
    std::printf("%5d %2d  %9.4f %9.4f %6.3f  %9.4f %9.4f %9.4f", n, c.size(), unit, conv,
                conv / unit, moving, transforming, 2 * transpose);
  if (n <= o.solve_max_n) {
    Field z(n, n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) z(i, j) = -(g.x(i) * g.x(i) + g.y(j) * g.y(j)) / (2 * 10e-3);
    // Hertz: a = L/4 = 0.25 mm at F = 4 E* a^3 / (3 R).
    const double force = 4 * m.E_star() * std::pow(0.25e-3, 3) / (3 * 10e-3);
    const NormalOptions opt{1e-10, 4000, Precondition::off};
    NormalSolver ss(serial, opt), sd(dist, opt);
    const Field zd = slab(dist, z);
    NormalResult rs, rd;
    Field ps, pd;
    const double ts = timed(c, 1, [&] { rs = ss.solve_force(z, force, ps); });
    const double td = timed(c, 1, [&] { rd = sd.solve_force(zd, force, pd); });
    if (c.rank() == 0)
      std::printf("  %4d %9.3f %4d %9.3f %6.3f", rs.iterations, ts, rd.iterations, td, td / ts);
    cattaneo_increment(c, serial, dist, Field(m.mu * ps), Field(m.mu * pd), 0.5 * m.mu * force);
  }
  if (c.rank() == 0) std::printf("\n"), std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  bench::parse_grid_range(argc, argv, o.min_n, o.max_n, o.repeats,
                          {{"--solve-max-n", &o.solve_max_n, 0, 1 << 14}}, usage);
  const Communicator& c = world_communicator();
  if (c.rank() == 0)
    std::printf(
        "    n  K  serial_s  conv_s  ratio  moving_s  fftw_s  transposes_s  it_serial "
        "solve_serial_s it_K solve_K_s ratio  tan_it_serial tan_serial_s tan_it_K tan_K_s "
        "ratio\n");
  for (int n = o.min_n; n <= o.max_n; n *= 2) row(c, n, o);
}
