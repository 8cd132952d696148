// The reduction layer on MPI ranks against what each reduction means, computed on every rank
// from the ranks' known inputs (rank r contributes r + 1); the serial communicator is the
// identity. Integers up to 3 are exact in double, so the comparisons are exact.
#include <gtest/gtest.h>

#include <vector>

#include "fretbem/parallel/communicator.hpp"
#include "mpi_test_util.hpp"

using namespace fretbem;

TEST(CommunicatorMpi, SerialIsTheIdentity) {
  const Communicator& c = serial_communicator();
  EXPECT_EQ(c.size(), 1);
  EXPECT_EQ(c.sum(2.5), 2.5);
  EXPECT_EQ(c.max(-1.0), -1.0);
  EXPECT_FALSE(c.any(false));
  std::vector<double> v{1, 2};
  c.sum(v);
  EXPECT_EQ(v, (std::vector<double>{1, 2}));
  EXPECT_EQ(c.gather(v, 0), v);
}

TEST(CommunicatorMpi, ReductionsOverTwoRanks) {
  if (!mpi_test::on_ranks()) return mpi_test::run_on_ranks(2);
  const Communicator& c = world_communicator();
  ASSERT_EQ(c.size(), 2);
  const double mine = c.rank() + 1.0;
  EXPECT_EQ(c.sum(mine), 3.0);
  EXPECT_EQ(c.max(mine), 2.0);
  EXPECT_EQ(c.min(mine), 1.0);
  EXPECT_TRUE(c.any(c.rank() == 1));
  EXPECT_FALSE(c.any(false));
  std::vector<double> v{mine, 2 * mine};
  c.sum(v);
  EXPECT_EQ(v, (std::vector<double>{3, 6}));
  std::vector<double> b{mine, mine};
  c.broadcast(b, 1);
  EXPECT_EQ(b, (std::vector<double>{2, 2}));
  // Rank r sends r + 1 values: rank 0 receives them in rank order.
  const std::vector<double> part(c.rank() + 1, mine);
  const std::vector<double> all = c.gather(part, 0);
  if (c.rank() == 0)
    EXPECT_EQ(all, (std::vector<double>{1, 2, 2}));
  else
    EXPECT_TRUE(all.empty());
}
