#include "fretbem/history/slab_measures.hpp"

#include <vector>

#include "fretbem/history/resolution.hpp"

namespace fretbem {

namespace {

bool touching(const StateField& s, Eigen::Index i, Eigen::Index j) {
  return s(i, j) != std::uint8_t(NodeState::open);
}

// The first row of every rank's slab on every rank (as 0/1 contact flags): the neighbours of
// a slab's last row. Every rank holds at least one row (build_model refuses a grid with fewer
// rows than ranks).
std::vector<double> first_rows(const StateField& s, const HalfSpace& hs) {
  const Communicator& comm = hs.communicator();
  std::vector<double> mine(std::size_t(s.rows()));
  for (Eigen::Index i = 0; i < s.rows(); ++i) mine[std::size_t(i)] = touching(s, i, 0);
  std::vector<double> all = comm.gather(mine, 0);
  all.resize(std::size_t(s.rows()) * std::size_t(comm.size()));
  comm.broadcast(all, 0);
  return all;
}

}  // namespace

// 4 per contact node less 2 per pair of neighbouring contact nodes, the pairs across a slab's
// last row counted by the rank that holds it.
long contact_edges(const StateField& s, const HalfSpace& hs) {
  const Communicator& comm = hs.communicator();
  const std::vector<double> next = first_rows(s, hs);
  const Eigen::Index nx = s.rows(), ny = s.cols();
  const bool last_rank = comm.rank() + 1 == comm.size();
  long nodes = 0, pairs = 0;
  for (Eigen::Index j = 0; j < ny; ++j)
    for (Eigen::Index i = 0; i < nx; ++i) {
      if (!touching(s, i, j)) continue;
      ++nodes;
      pairs += i + 1 < nx && touching(s, i + 1, j);
      if (j + 1 < ny)
        pairs += touching(s, i, j + 1);
      else if (!last_rank)
        pairs += next[std::size_t((comm.rank() + 1) * nx + i)] != 0.0;
    }
  return long(comm.sum(double(4 * nodes - 2 * pairs)));
}

double slip_ring_cells(const StateField& s, const HalfSpace& hs) {
  if (!hs.communicator().distributed()) return slip_ring_cells(s);
  const auto slip =
      long(hs.communicator().sum(double((s == std::uint8_t(NodeState::slip)).count())));
  return slip_ring_width(slip, contact_edges(s, hs));
}

long contact_nodes(const StateField& s, const HalfSpace& hs) {
  return long(hs.communicator().sum(double(contact_nodes(s))));
}

// The outermost cells once each: whole columns j = 0 and ny - 1, the cells i = 0 and nx - 1 of
// the others.
double edge_load_share(const Field& p, const HalfSpace& hs) {
  const Communicator& comm = hs.communicator();
  if (!comm.distributed()) return edge_load_share(p);
  const double total = comm.sum(p.sum());
  const Eigen::Index nx = p.rows(), ny = hs.grid().ny;
  double edge = 0.0;
  for (Eigen::Index j = 0; j < p.cols(); ++j) {
    const Eigen::Index jg = hs.first_row() + j;
    if (jg == 0 || jg + 1 == ny)
      edge += p.col(j).sum();
    else
      edge += p(0, j) + (nx > 1 ? p(nx - 1, j) : 0.0);
  }
  edge = comm.sum(edge);
  return total > 0.0 ? edge / total : 0.0;
}

}  // namespace fretbem
