// The half-space operator slab-decomposed over MPI ranks (FFTW-MPI) against the serial one on
// random fields: free (zero-padded) and periodic grids, analogy and Cerruti, the Fourier
// preconditioner and the operator's constants. Both are double FFT convolutions of the same
// kernels, different only in the order of the transforms' sums: their round-off is a few
// eps log2(N) (~1e-14 at N = 46 x 40), so 1e-12 relative leaves a factor ~100.
#include <gtest/gtest.h>

#include <random>

#include "fretbem/core/errors.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "mpi_test_util.hpp"

using namespace fretbem;

namespace {

constexpr double kTolerance = 1e-12;

Field random_field(int nx, int ny, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  Field f(nx, ny);
  for (Eigen::Index k = 0; k < f.size(); ++k) f(k) = u(rng);
  return f;
}

// Largest difference between this rank's slab and its rows of the serial field, over the
// largest serial value, both over all ranks.
double slab_error(const HalfSpace& hd, const Field& serial, const Field& slab) {
  const Communicator& c = hd.communicator();
  const Field mine = serial.middleCols(hd.first_row(), hd.local_rows());
  EXPECT_EQ(slab.rows(), mine.rows());
  EXPECT_EQ(slab.cols(), mine.cols());
  const double diff = slab.size() ? (slab - mine).abs().maxCoeff() : 0.0;
  return c.max(diff) / c.max(serial.abs().maxCoeff());
}

Material steel_on_rigid() {
  return Material{Body{210e9, 0.3}, std::nullopt, 0.3};
}
Material steel_on_steel() {
  return Material{Body{210e9, 0.3}, Body{210e9, 0.3}, 0.3};
}

// Every operator of a HalfSpace on `grid` with `coupling`, distributed against serial.
void expect_distributed_equals_serial(const Grid& grid, Coupling coupling, const Material& m) {
  const Communicator& world = world_communicator();
  HalfSpace hs(grid, m, coupling);
  HalfSpace hd(grid, m, coupling, {}, world);
  EXPECT_EQ(world.sum(hd.local_rows()), grid.ny);
  EXPECT_NEAR(hd.normal_self(), hs.normal_self(), kTolerance * hs.normal_self());
  EXPECT_NEAR(hd.normal_max_eigenvalue(), hs.normal_max_eigenvalue(),
              kTolerance * hs.normal_max_eigenvalue());
  const Field p = random_field(grid.nx, grid.ny, 11), q = random_field(grid.nx, grid.ny, 12);
  auto slab = [&](const Field& f) { return Field(f.middleCols(hd.first_row(), hd.local_rows())); };
  Field us, ud, vs, vd;
  hs.normal(p, us), hd.normal(slab(p), ud);
  EXPECT_LT(slab_error(hd, us, ud), kTolerance) << "normal";
  hs.normal_inverse(p, us), hd.normal_inverse(slab(p), ud);
  EXPECT_LT(slab_error(hd, us, ud), kTolerance) << "normal_inverse";
  hs.tangential_analogy(p, us), hd.tangential_analogy(slab(p), ud);
  EXPECT_LT(slab_error(hd, us, ud), kTolerance) << "tangential_analogy";
  hs.tangential(p, q, us, vs), hd.tangential(slab(p), slab(q), ud, vd);
  EXPECT_LT(slab_error(hd, us, ud), kTolerance) << "tangential x";
  EXPECT_LT(slab_error(hd, vs, vd), kTolerance) << "tangential y";
  EXPECT_EQ(hd.sparse_limit(), 0u);
}

// Started by ctest: this test again under mpirun -n `ranks`; on the ranks: every operator of
// steel on a rigid body, distributed against serial.
void expect_on_ranks_equals_serial(int ranks, const Grid& grid, Coupling coupling) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(ranks);
  expect_distributed_equals_serial(grid, coupling, steel_on_rigid());
}

}  // namespace

// Odd ny: the ranks' slabs differ in size, and with zero padding the second rank transforms
// only padding rows (every field row moves to the first rank and back).
TEST(HalfSpaceMpi, FreeAnalogyEqualsSerial) {
  expect_on_ranks_equals_serial(2, Grid{20, 23, 1e-6, false}, Coupling::analogy);
}

TEST(HalfSpaceMpi, FreeCerrutiEqualsSerial) {
  expect_on_ranks_equals_serial(2, Grid{20, 23, 1e-6, false}, Coupling::cerruti);
}

TEST(HalfSpaceMpi, PeriodicAnalogyEqualsSerial) {
  expect_on_ranks_equals_serial(2, Grid{18, 22, 1e-6, true}, Coupling::analogy);
}

TEST(HalfSpaceMpi, PeriodicCerrutiEqualsSerial) {
  expect_on_ranks_equals_serial(2, Grid{18, 22, 1e-6, true}, Coupling::cerruti);
}

// Three ranks on an even grid: blocks of 8, 8 and 6 rows.
TEST(HalfSpaceMpi, ThreeRanksFreeCerrutiEqualsSerial) {
  expect_on_ranks_equals_serial(3, Grid{16, 22, 1e-6, false}, Coupling::cerruti);
}

// Identical bodies: coupled is Cerruti exactly (beta = 0) and is distributed; dissimilar
// bodies' cross terms and float transforms are refused with the key that asks for them.
TEST(HalfSpaceMpi, RefusesWhatIsNotDistributed) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  const Grid g{16, 16, 1e-6, false};
  const Communicator& world = world_communicator();
  expect_distributed_equals_serial(g, Coupling::coupled, steel_on_steel());
  try {
    HalfSpace hd(g, steel_on_rigid(), Coupling::coupled, {}, world);
    ADD_FAILURE() << "cross terms accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("solver.coupling = coupled"), std::string::npos);
  }
  try {
    HalfSpace hd(g, steel_on_rigid(), Coupling::analogy, {1, false, FftPrecision::float32}, world);
    ADD_FAILURE() << "float accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("solver.fft_precision"), std::string::npos);
  }
}
