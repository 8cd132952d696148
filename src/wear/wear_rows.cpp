// How a simulated cycle is kept in a wear report and how a worn depth is fingerprinted.
#include "wear_rows.hpp"

#include <span>
#include <utility>
#include <vector>

#include "fretbem/core/fingerprint.hpp"

namespace fretbem::wear_detail {

void keep(WearReport& rep, WearCycle c) {
  c.rate = Field();
  rep.history.push_back(std::move(c));
}

void keep(WearReport& rep, WearCycle c, Observer& log) {
  log.cycle(c);
  keep(rep, std::move(c));
}

// A collision needs two different worn-depth fields with the same 64-bit value. Distributed,
// the ranks' slab fingerprints are summed into their own slots as two 32-bit halves (whole
// numbers below 2^32: exact in doubles, and exact in a sum with zeros), then fingerprinted
// in rank order on every rank.
std::uint64_t fingerprint(const Eigen::Ref<const Field>& W, const Communicator& comm) {
  Fingerprint f;
  f.add_bytes(W.data(), std::size_t(W.size()) * sizeof(double));
  if (!comm.distributed()) return f.value();
  std::vector<double> halves(2 * std::size_t(comm.size()), 0.0);
  const std::size_t r = 2 * std::size_t(comm.rank());
  halves[r] = double(f.value() >> 32);
  halves[r + 1] = double(f.value() & 0xffffffffull);
  comm.sum(std::span<double>(halves));
  Fingerprint all;
  for (std::size_t k = 0; k < halves.size(); k += 2)
    all.add_word((std::uint64_t(halves[k]) << 32) | std::uint64_t(halves[k + 1]));
  return all.value();
}

}  // namespace fretbem::wear_detail
