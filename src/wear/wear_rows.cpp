// How a simulated cycle is kept in a wear report and how a worn depth is fingerprinted.
#include "wear_rows.hpp"

#include <utility>

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

// A collision needs two different worn-depth fields with the same 64-bit value.
std::uint64_t fingerprint(const Eigen::Ref<const Field>& W) {
  Fingerprint f;
  f.add_bytes(W.data(), std::size_t(W.size()) * sizeof(double));
  return f.value();
}

}  // namespace fretbem::wear_detail
