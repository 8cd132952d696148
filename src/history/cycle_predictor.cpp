#include "fretbem/history/cycle_predictor.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

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

namespace {

// Step k's transition's latest earlier occurrence, or -1.
std::vector<long> transition_sources(const std::vector<LoadStep>& steps) {
  double tscale = 1e-300, nscale = 1e-300;
  for (const LoadStep& s : steps) {
    tscale = std::max(tscale, s.target.cwiseAbs().maxCoeff());
    nscale = std::max(nscale, std::abs(s.normal.value));
  }
  using Key = std::array<long long, 8>;
  auto q = [](double v, double scale) { return std::llround(v / (1e-7 * scale)); };
  auto key = [&](const LoadStep& p, const LoadStep& c) {
    const long long kind = (p.normal.force_control ? 1 : 0) + 2 * int(p.control) +
                           8 * (p.relative ? 1 : 0) + 16 * (c.normal.force_control ? 1 : 0) +
                           32 * int(c.control) + 128 * (c.relative ? 1 : 0);
    return Key{kind,
               q(p.target.x(), tscale),
               q(p.target.y(), tscale),
               q(p.normal.value, nscale),
               q(c.target.x(), tscale),
               q(c.target.y(), tscale),
               q(c.normal.value, nscale),
               0};
  };
  std::vector<long> out(steps.size(), -1);
  std::map<Key, long> last;
  for (std::size_t k = 1; k < steps.size(); ++k) {
    const auto [it, fresh] = last.try_emplace(key(steps[k - 1], steps[k]), long(k));
    if (!fresh) out[k] = it->second, it->second = long(k);
  }
  return out;
}

}  // namespace

std::vector<long> CyclePredictor::sources(const std::vector<LoadStep>& steps) {
  return transition_sources(steps);
}

std::vector<char> CyclePredictor::repeated_later(const std::vector<LoadStep>& steps) {
  std::vector<char> out(steps.size(), 0);
  for (const long s : transition_sources(steps))
    if (s >= 0) out[std::size_t(s)] = 1;
  return out;
}

std::vector<char> CyclePredictor::repeated_earlier(const std::vector<LoadStep>& steps) {
  std::vector<char> out(steps.size(), 0);
  const std::vector<long> src = transition_sources(steps);
  for (std::size_t k = 0; k < src.size(); ++k) out[k] = src[k] >= 0 ? 1 : 0;
  return out;
}

const VecField* CyclePredictor::find(const LoadStep& prev, const LoadStep& cur, Eigen::Index nx,
                                     Eigen::Index ny) {
  for (const Entry& e : entries_) {
    if (!same_transition(e.prev, e.cur, prev, cur)) continue;
    const bool same_nodes = guess_nodes_ == e.nodes && !guess_.empty() &&
                            guess_.size() == e.values.size() && guess_[0].rows() == nx &&
                            guess_[0].cols() == ny;
    if (!same_nodes) guess_.assign(e.values.size(), Field::Zero(nx, ny));
    guess_nodes_ = e.nodes;
    for (std::size_t c = 0; c < e.values.size(); ++c)
      for (std::size_t j = 0; j < e.nodes->size(); ++j) guess_[c]((*e.nodes)[j]) = e.values[c][j];
    return &guess_;
  }
  return nullptr;
}

void CyclePredictor::onto_moved_bound(const Field& bound, double largest, VecField& traction) {
  const double band = kOnBoundBand * largest;
  for (Eigen::Index k = 0; k < bound.size(); ++k) {
    double t2 = 0.0;
    for (const Field& c : traction) t2 += c(k) * c(k);
    const double t = std::sqrt(t2);
    if (t > 0.0 && t < bound(k) && bound(k) - t <= band)
      for (Field& c : traction) c(k) *= bound(k) / t;
  }
}

// Entries that share a node list are neighbours (a list is shared only with the newest entry
// when it is remembered), so each list counts once: where it differs from the previous entry's.
void CyclePredictor::recount() {
  stored_ = 0;
  const std::vector<Eigen::Index>* last = nullptr;
  for (const Entry& e : entries_) {
    if (e.nodes.get() != last) stored_ += e.nodes->size();
    last = e.nodes.get();
    for (const auto& v : e.values) stored_ += v.size();
  }
}

void CyclePredictor::remember(const LoadStep& prev, const LoadStep& cur, const VecField& traction,
                              const Field& bound) {
  auto same = [&](const Entry& e) { return same_transition(e.prev, e.cur, prev, cur); };
  if (auto it = std::find_if(entries_.begin(), entries_.end(), same); it != entries_.end())
    entries_.erase(it);
  auto nodes = std::make_shared<std::vector<Eigen::Index>>();
  for (Eigen::Index k = 0; k < bound.size(); ++k)
    if (bound(k) > 0.0) nodes->push_back(k);
  Entry e{prev, cur, nodes, std::vector<std::vector<double>>(traction.size())};
  const bool same_nodes = !entries_.empty() && *entries_.front().nodes == *nodes;
  if (comm_->min(same_nodes ? 1.0 : 0.0) > 0.0) e.nodes = entries_.front().nodes;
  for (std::size_t c = 0; c < traction.size(); ++c) {
    e.values[c].reserve(e.nodes->size());
    for (const Eigen::Index k : *e.nodes) e.values[c].push_back(traction[c](k));
  }
  entries_.push_front(std::move(e));
  ++remembered_;
  recount();
  // 8 bytes per stored double or index; the oldest entries go first.
  const double limit = bytes_per_cell_ * comm_->sum(double(bound.size())) / 8.0;
  while (entries_.size() > 1 && comm_->sum(double(stored_)) > limit) {
    entries_.pop_back();
    recount();
  }
}

void CyclePredictor::forget_newest(std::size_t count) {
  for (; count > 0 && !entries_.empty(); --count) entries_.pop_front();
  recount();
}

// ---- checkpoint form ---------------------------------------------------------------------
// [layout 1, components, entries, then per entry: prev and cur (9 numbers each: time, cycle,
// normal force control, normal value, control, target x, target y, relative, turning), shared
// (1: the previous entry's node list), node count, the nodes unless shared, the values
// component by component].

namespace {

constexpr double kLayout = 1.0;

void put_step(std::vector<double>& v, const LoadStep& s) {
  v.insert(v.end(), {s.time, double(s.cycle), s.normal.force_control ? 1.0 : 0.0, s.normal.value,
                     double(int(s.control)), s.target.x(), s.target.y(), s.relative ? 1.0 : 0.0,
                     s.turning ? 1.0 : 0.0});
}

class FlatReader {
 public:
  explicit FlatReader(const std::vector<double>& v) : v_(v) {}
  [[noreturn]] static void fail(const std::string& what) {
    throw std::runtime_error("predictor: " + what);
  }
  double number() {
    if (at_ >= v_.size()) fail("ends early");
    const double x = v_[at_++];
    if (!std::isfinite(x)) fail("holds a non-finite value");
    return x;
  }
  std::size_t count(double hi) {
    const double x = number();
    if (x < 0 || x > hi || x != std::floor(x)) fail("bad count " + std::to_string(x));
    return std::size_t(x);
  }
  bool flag() { return count(1) == 1; }
  LoadStep step() {
    LoadStep s;
    s.time = number();
    const double cycle = number();
    if (std::abs(cycle) > 2e9 || cycle != std::floor(cycle)) fail("bad cycle");
    s.cycle = int(cycle);
    s.normal.force_control = flag();
    s.normal.value = number();
    s.control = static_cast<Control>(count(1));
    s.target.x() = number();
    s.target.y() = number();
    s.relative = flag();
    s.turning = flag();
    return s;
  }
  std::size_t left() const { return v_.size() - at_; }

 private:
  const std::vector<double>& v_;
  std::size_t at_ = 0;
};

}  // namespace

std::vector<double> CyclePredictor::flatten() const {
  std::vector<double> v;
  if (entries_.empty()) return v;
  v.reserve(3 + stored_ + 24 * entries_.size());
  v.insert(v.end(), {kLayout, double(entries_.front().values.size()), double(entries_.size())});
  const std::vector<Eigen::Index>* last = nullptr;
  for (const Entry& e : entries_) {
    put_step(v, e.prev);
    put_step(v, e.cur);
    const bool shared = e.nodes.get() == last;
    v.push_back(shared ? 1.0 : 0.0);
    v.push_back(double(e.nodes->size()));
    if (!shared)
      for (const Eigen::Index k : *e.nodes) v.push_back(double(k));
    for (const auto& c : e.values) v.insert(v.end(), c.begin(), c.end());
    last = e.nodes.get();
  }
  return v;
}

CyclePredictor CyclePredictor::unflatten(const std::vector<double>& v, std::size_t cells,
                                         int components) {
  CyclePredictor p;
  if (v.empty()) return p;
  FlatReader r(v);
  if (r.number() != kLayout) FlatReader::fail("unknown layout");
  if (r.count(2) != std::size_t(components))
    FlatReader::fail("traction components differ from the run's " + std::to_string(components));
  const std::size_t entries = r.count(double(v.size()));
  for (std::size_t i = 0; i < entries; ++i) {
    Entry e;
    e.prev = r.step();
    e.cur = r.step();
    const bool shared = r.flag();
    const std::size_t n = r.count(double(cells));
    if (shared) {
      if (p.entries_.empty() || p.entries_.back().nodes->size() != n)
        FlatReader::fail("entry " + std::to_string(i) + " shares no matching node list");
      e.nodes = p.entries_.back().nodes;
    } else {
      auto nodes = std::make_shared<std::vector<Eigen::Index>>();
      nodes->reserve(n);
      for (std::size_t j = 0; j < n; ++j) {
        const auto k = Eigen::Index(r.count(double(cells) - 1));
        if (!nodes->empty() && k <= nodes->back()) FlatReader::fail("node list not increasing");
        nodes->push_back(k);
      }
      e.nodes = std::move(nodes);
    }
    if (r.left() < n * std::size_t(components)) FlatReader::fail("ends early");
    e.values.assign(std::size_t(components), {});
    for (auto& c : e.values) {
      c.reserve(n);
      for (std::size_t j = 0; j < n; ++j) c.push_back(r.number());
    }
    p.entries_.push_back(std::move(e));
  }
  if (r.left() != 0) FlatReader::fail("holds " + std::to_string(r.left()) + " numbers too many");
  p.recount();
  return p;
}

// Entry by entry: the node list (unless shared) and each component's values, gathered in rank
// order (the order of the cells: slabs are consecutive column blocks of the grid).
std::vector<double> CyclePredictor::gathered(const std::vector<double>& v, const Communicator& comm,
                                             Eigen::Index offset) {
  if (!comm.distributed() || v.empty()) return v;  // the entries are the same on every rank
  const auto components = std::size_t(v[1]), entries = std::size_t(v[2]);
  std::vector<double> out(v.begin(), v.begin() + 3);
  std::size_t at = 3, shared_count = 0;
  for (std::size_t i = 0; i < entries; ++i) {
    out.insert(out.end(), v.begin() + long(at), v.begin() + long(at + 19));  // steps, shared
    const bool shared = v[at + 18] != 0.0;
    const auto n = std::size_t(v[at + 19]);
    at += 20;
    const std::size_t count_at = out.size();
    out.push_back(0.0);
    if (!shared) {
      std::vector<double> nodes(v.begin() + long(at), v.begin() + long(at + n));
      for (double& k : nodes) k += double(offset);
      const std::vector<double> all = comm.gather(nodes, 0);
      shared_count = all.size();
      out.insert(out.end(), all.begin(), all.end());
      at += n;
    }
    out[count_at] = double(shared_count);
    for (std::size_t c = 0; c < components; ++c, at += n) {
      const std::vector<double> all =
          comm.gather(std::vector<double>(v.begin() + long(at), v.begin() + long(at + n)), 0);
      out.insert(out.end(), all.begin(), all.end());
    }
  }
  if (comm.rank() != 0) return {};
  return out;
}

std::vector<double> CyclePredictor::sliced(const std::vector<double>& v, Eigen::Index offset,
                                           Eigen::Index cells) {
  if (v.size() < 3) return v;
  const auto components = std::size_t(v[1]), entries = std::size_t(v[2]);
  std::vector<double> out(v.begin(), v.begin() + 3);
  std::vector<std::size_t> keep;
  std::size_t at = 3;
  for (std::size_t i = 0; i < entries; ++i) {
    if (at + 20 > v.size()) return v;  // unflatten says what is wrong
    out.insert(out.end(), v.begin() + long(at), v.begin() + long(at + 19));
    const bool shared = v[at + 18] != 0.0;
    const auto n = std::size_t(v[at + 19]);
    at += 20;
    if (at + (shared ? 0 : n) + components * n > v.size()) return v;
    std::vector<double> nodes;
    if (!shared) {
      keep.clear();
      for (std::size_t j = 0; j < n; ++j) {
        const double k = v[at + j] - double(offset);
        if (k >= 0.0 && k < double(cells)) keep.push_back(j), nodes.push_back(k);
      }
      at += n;
    }
    out.push_back(double(keep.size()));
    out.insert(out.end(), nodes.begin(), nodes.end());
    for (std::size_t c = 0; c < components; ++c, at += n)
      for (const std::size_t j : keep) out.push_back(v[at + j]);
  }
  return out;
}

}  // namespace fretbem
