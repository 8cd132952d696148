#include "fretbem/history/cycle_predictor.hpp"

#include <algorithm>
#include <cmath>

namespace fretbem {

namespace {

// The same transition of the load (the steps' own time, cycle and turning flag do not matter).
// Loads are compared to 1e-9 of the transition's largest value: a sine path's targets one
// period apart differ in the last bits (sin(2 pi (t + 1)) != sin(2 pi t) in floating point).
bool near(double a, double b, double scale) {
  return std::abs(a - b) <= 1e-9 * scale;
}

bool same_transition(const LoadStep& p0, const LoadStep& c0, const LoadStep& p1,
                     const LoadStep& c1) {
  auto kind = [](const LoadStep& a, const LoadStep& b) {
    return a.normal.force_control == b.normal.force_control && a.control == b.control &&
           a.relative == b.relative;
  };
  if (!kind(p0, p1) || !kind(c0, c1)) return false;
  const double tscale =
      std::max({p0.target.norm(), c0.target.norm(), p1.target.norm(), c1.target.norm(), 1e-300});
  const double nscale = std::max({std::abs(p0.normal.value), std::abs(c0.normal.value), 1e-300});
  return (p0.target - p1.target).norm() <= 1e-9 * tscale &&
         (c0.target - c1.target).norm() <= 1e-9 * tscale &&
         near(p0.normal.value, p1.normal.value, nscale) &&
         near(c0.normal.value, c1.normal.value, nscale);
}

}  // namespace

const VecField* CyclePredictor::find(const LoadStep& prev, const LoadStep& cur, Eigen::Index nx,
                                     Eigen::Index ny) {
  for (const Entry& e : entries_) {
    if (!same_transition(e.prev, e.cur, prev, cur)) continue;
    guess_.assign(e.values.size(), Field::Zero(nx, ny));
    for (std::size_t c = 0; c < e.values.size(); ++c)
      for (std::size_t j = 0; j < e.nodes->size(); ++j) guess_[c]((*e.nodes)[j]) = e.values[c][j];
    return &guess_;
  }
  return nullptr;
}

void CyclePredictor::remember(const LoadStep& prev, const LoadStep& cur, const VecField& traction,
                              const Field& bound) {
  // Bytes held by an entry: its values, and its node list unless another entry shares it.
  auto size = [](const Entry& e) {
    return e.nodes->size() * (e.values.size() + (e.nodes.use_count() == 1 ? 1 : 0));
  };
  auto drop = [&](std::deque<Entry>::iterator it) {
    stored_ -= size(*it);
    const auto nodes = it->nodes;
    entries_.erase(it);
    // The node list now held by one entry alone counts for that entry again.
    if (nodes.use_count() == 2) stored_ += nodes->size();
  };
  auto same = [&](const Entry& e) { return same_transition(e.prev, e.cur, prev, cur); };
  if (auto it = std::find_if(entries_.begin(), entries_.end(), same); it != entries_.end())
    drop(it);
  auto nodes = std::make_shared<std::vector<Eigen::Index>>();
  for (Eigen::Index k = 0; k < bound.size(); ++k)
    if (bound(k) > 0.0) nodes->push_back(k);
  Entry e{prev, cur, nodes, std::vector<std::vector<double>>(traction.size())};
  if (!entries_.empty() && *entries_.front().nodes == *nodes) {
    if (entries_.front().nodes.use_count() == 1) stored_ -= nodes->size();  // now shared
    e.nodes = entries_.front().nodes;
  }
  for (std::size_t c = 0; c < traction.size(); ++c) {
    e.values[c].reserve(e.nodes->size());
    for (const Eigen::Index k : *e.nodes) e.values[c].push_back(traction[c](k));
  }
  nodes.reset();  // only the entries hold node lists now
  entries_.push_front(std::move(e));
  stored_ += entries_.front().nodes->size() * traction.size() +
             (entries_.front().nodes.use_count() == 1 ? entries_.front().nodes->size() : 0);
  // 8 bytes per stored double or index; the oldest entries go first.
  const double limit = kBytesPerCell * double(bound.size()) / 8.0;
  while (entries_.size() > 1 && double(stored_) > limit) drop(std::prev(entries_.end()));
}

}  // namespace fretbem
