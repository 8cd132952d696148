#include "fretbem/history/masing_image.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "fretbem/history/cycle_predictor.hpp"
#include "fretbem/history/model.hpp"

namespace fretbem {

namespace {

// The path qualifies when every step has step 0's normal load and one tangential control, and
// the targets are collinear (one traction component carries the image).
bool qualifies(const LoadPath& path) {
  const std::vector<LoadStep>& s = path.steps;
  if (s.size() < 3 || !path.collinear_direction()) return false;
  for (std::size_t k = 1; k < s.size(); ++k)
    if (!(s[k].normal == s[0].normal) || s[k].control != s[1].control ||
        s[k].relative != s[1].relative)
      return false;
  return true;
}

// The secant value at weight w past v1 (w = 0 at v1, -1 at v0) of a virgin traction with bound
// g >= 0 and sign `sign`. By Ciavarella–Jäger tau_v = mu p - mu p*, p* the corrective pressure
// of a normal contact at F_z - l / mu; for a Hertzian p* the square p*^2 = k^2 (c^2 - r^2) is
// smooth in the load l at every node where p* > 0 on the secant's levels, so the secant runs
// through (g - |tau_v|)^2 = (mu p*)^2, and a node whose square passes zero starts to slip
// (|tau_v| = g); under displacement control c^2 is linear in the shift and the secant exact
// (MasingImage.VirginSecantReproducesCattaneo). On the Mindlin–Deresiewicz cycle at n = 256
// the virgin quarter costs 255 convolutions with it, 310 with the secant through tau_v itself
// and 370 from the previous step.
double secant_value(double v0, double v1, double w, double g, double sign) {
  const double a0 = std::max(g - sign * v0, 0.0), a1 = std::max(g - sign * v1, 0.0);
  const double q = a1 * a1 + w * (a1 * a1 - a0 * a0);
  return sign * (g - std::sqrt(std::max(q, 0.0)));
}

}  // namespace

MasingImage::Plan MasingImage::plan(const LoadPath& path, bool predictor) {
  Plan p;
  if (!qualifies(path)) return p;
  const std::vector<LoadStep>& s = path.steps;
  const std::size_t n = s.size();
  const Vec2 e = *path.collinear_direction();
  p.level.resize(n);
  for (std::size_t k = 0; k < n; ++k) p.level[k] = e.dot(s[k].target);
  // The virgin segment 1 .. kv: every change of the load has the sign of the first one.
  std::size_t kv = 0;
  double sign = 0.0;
  for (std::size_t k = 1; k < n; ++k) {
    const double d = p.level[k] - p.level[k - 1];
    if (sign == 0.0 && d != 0.0) sign = d > 0.0 ? 1.0 : -1.0;
    if (d * sign < 0.0) break;
    kv = k;
  }
  if (sign == 0.0) return {};
  p.image.assign(n, 0), p.virgin.assign(n, 0), p.turning.assign(n, 0);
  for (std::size_t k = 1; k <= kv; ++k) p.virgin[k] = 1;
  p.branches = kv + 1 < n;
  if (!p.branches) return p;  // a monotone path: only the virgin secant
  // Turning: the load's last change into k and its next change out of k have opposite signs.
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double in = p.level[k] - p.level[k - 1];
    std::size_t j = k + 1;
    while (j + 1 < n && p.level[j] == p.level[k]) ++j;
    p.turning[k] = in * (p.level[j] - p.level[k]) < 0.0 ? 1 : 0;
  }
  const std::vector<long> src = predictor ? CyclePredictor::sources(s) : std::vector<long>(n, -1);
  for (std::size_t k = kv + 1; k < n; ++k) p.image[k] = src[k] <= long(kv) ? 1 : 0;
  return p;
}

MasingImage::Plan MasingImage::plan(const Model& m) {
  const bool exact = m.scenario.solver.predictor != PredictorMode::none && !m.friction->evolves() &&
                     !m.wear && m.tangential_operator->components() == 1 &&
                     m.scenario.solver.coupling == Coupling::analogy;
  return exact ? plan(m.path, m.cycle_predictor) : Plan{};
}

// One more level would pass kBytesPerCell per grid cell of `cells`: recording stops for good.
bool MasingImage::stops_at_memory_bound(Eigen::Index cells) {
  const double nodes = comm_->sum(double(nodes_.size())), all_cells = comm_->sum(double(cells));
  if (8.0 * nodes * double(levels_.size() + 2) > kBytesPerCell * all_cells) full_ = true;
  return full_;
}

void MasingImage::record_virgin(double level, const Field& tau, const Field& bound, bool keep_all) {
  if (full_) return;
  if (!keep_all && levels_.size() == 2)  // the secant reads the last two only
    levels_.erase(levels_.begin()), tau_.erase(tau_.begin());
  if (comm_->sum(double(nodes_.size())) == 0.0) {
    for (Eigen::Index k = 0; k < bound.size(); ++k)
      if (bound(k) > 0.0) nodes_.push_back(k);
    sign_ = level < 0.0 ? -1.0 : 1.0;
  }
  if (stops_at_memory_bound(bound.size())) return;
  const double l = std::abs(level);
  if (!levels_.empty() && !(l > levels_.back())) return;
  levels_.push_back(l);
  tau_.emplace_back();
  tau_.back().reserve(nodes_.size());
  for (const Eigen::Index k : nodes_) tau_.back().push_back(tau(k));
}

// Inverting the image: a solved step on a branch gives the virgin traction at its half change,
// tau_v = (tau - tau_T) / (2 sign(L - L_T)), a new level between the recorded ones (a sine's
// reloading branch needs the half changes of the unloading branch before it).
void MasingImage::record_branch(double level, const Field& tau, const Field& bound) {
  if (turning_.size() == 0 || levels_.empty() || full_) return;
  const double half = 0.5 * std::abs(level - turning_level_);
  const auto at = std::lower_bound(levels_.begin(), levels_.end(), half);
  const double gap = 1e-9 * levels_.back();
  if (!(half > gap) || (at != levels_.end() && *at - half <= gap) ||
      (at != levels_.begin() && half - *(at - 1) <= gap))
    return;
  if (stops_at_memory_bound(bound.size())) return;
  const double factor = 2.0 * (level < turning_level_ ? -1.0 : 1.0) * sign_;
  std::vector<double> v;
  v.reserve(nodes_.size());
  for (const Eigen::Index k : nodes_) v.push_back((tau(k) - turning_(k)) / factor);
  const auto i = at - levels_.begin();
  levels_.insert(at, half);
  tau_.insert(tau_.begin() + i, std::move(v));
  recent_.push_back(half);
  if (recent_.size() > 2) recent_.erase(recent_.begin());
}

void MasingImage::record_turning(double level, const Field& tau) {
  turning_ = tau;
  turning_level_ = level;
  recent_.clear();
}

// tau_T + sign(L - L_T) 2 tau_v(|L - L_T| / 2), tau_v interpolated linearly between the two
// recorded levels around the half change (level 0: tau_v = 0). (Interpolating the square of
// the corrective pressure mu p - |tau_v| instead, exact in c^2 for Hertz, cost more
// convolutions on the Mindlin–Deresiewicz cycle at n = 256: 1198 against 1114 in the first
// cycle.)
const VecField* MasingImage::image(double level) {
  if (turning_.size() == 0 || levels_.empty()) return nullptr;
  const double half = 0.5 * std::abs(level - turning_level_);
  if (half > levels_.back()) return nullptr;
  const auto hi =
      std::size_t(std::lower_bound(levels_.begin(), levels_.end(), half) - levels_.begin());
  const double l0 = hi == 0 ? 0.0 : levels_[hi - 1], l1 = levels_[hi];
  const double w1 = l1 > l0 ? (half - l0) / (l1 - l0) : 1.0, w0 = 1.0 - w1;
  const double factor = 2.0 * (level < turning_level_ ? -1.0 : 1.0) * sign_;
  image_.assign(1, turning_);
  Field& t = image_[0];
  for (std::size_t j = 0; j < nodes_.size(); ++j) {
    const double v0 = hi == 0 ? 0.0 : tau_[hi - 1][j];
    t(nodes_[j]) += factor * (w0 * v0 + w1 * tau_[hi][j]);
  }
  return &image_;
}

void MasingImage::continue_secant(std::ptrdiff_t i0, std::size_t i1, double half, const Field& g,
                                  double factor, Field& t) const {
  const double l0 = i0 < 0 ? 0.0 : levels_[std::size_t(i0)], l1 = levels_[i1];
  const double w = (half - l1) / (l1 - l0);
  for (std::size_t j = 0; j < nodes_.size(); ++j) {
    const double v0 = i0 < 0 ? 0.0 : tau_[std::size_t(i0)][j];
    t(nodes_[j]) += factor * secant_value(v0, tau_[i1][j], w, g(nodes_[j]), sign_);
  }
}

// A branch's own solved steps continue it to second order in the load step; the interpolated
// image is of second order in the spacing of the virgin levels around the half change, which a
// first unloading crosses at twice the virgin step (n = 256 Mindlin–Deresiewicz cycle: 501
// convolutions on the first unloading against 572 from the interpolated image).
const VecField* MasingImage::branch_start(double level, const Field& bound) {
  if (turning_.size() == 0 || levels_.empty()) return nullptr;
  const double half = 0.5 * std::abs(level - turning_level_);
  const double gap = 1e-9 * levels_.back();
  const auto at = std::lower_bound(levels_.begin(), levels_.end(), half - gap);
  const bool recorded = at != levels_.end() && std::abs(*at - half) <= gap;
  const auto index = [&](double h) {
    return std::size_t(std::lower_bound(levels_.begin(), levels_.end(), h) - levels_.begin());
  };
  if (recorded || full_ || recent_.empty() || !(half > recent_.back())) return image(level);
  const std::ptrdiff_t i0 = recent_.size() > 1 ? std::ptrdiff_t(index(recent_[0])) : -1;
  image_.assign(1, turning_);
  const double factor = 2.0 * (level < turning_level_ ? -1.0 : 1.0) * sign_;
  continue_secant(i0, index(recent_.back()), half, bound, factor, image_[0]);
  return &image_;
}

const VecField* MasingImage::virgin_start(double level, const Field& bound) {
  const double l = std::abs(level);
  if (levels_.empty() || full_ || turning_.size() > 0 || !(l > levels_.back())) return nullptr;
  const std::size_t m = levels_.size();
  image_.assign(1, Field::Zero(bound.rows(), bound.cols()));
  continue_secant(std::ptrdiff_t(m) - 2, m - 1, l, bound, 1.0, image_[0]);
  return &image_;
}

// Flat form: [layout 2, sign, full, turning level, nodes m, levels L, has turning, recent R,
// the m nodes, the L levels, the L x m virgin values level by level, the turning traction
// (cells), the R recent half changes]. Layout 1 has no R and no recent half changes.
std::vector<double> MasingImage::flatten() const {
  if (levels_.empty()) return {};
  const bool turning = turning_.size() > 0;
  std::vector<double> v{2.0,
                        sign_,
                        full_ ? 1.0 : 0.0,
                        turning_level_,
                        double(nodes_.size()),
                        double(levels_.size()),
                        turning ? 1.0 : 0.0,
                        double(recent_.size())};
  for (const Eigen::Index k : nodes_) v.push_back(double(k));
  v.insert(v.end(), levels_.begin(), levels_.end());
  for (const auto& t : tau_) v.insert(v.end(), t.begin(), t.end());
  if (turning) v.insert(v.end(), turning_.data(), turning_.data() + turning_.size());
  v.insert(v.end(), recent_.begin(), recent_.end());
  return v;
}

MasingImage MasingImage::unflatten(const std::vector<double>& v, Eigen::Index nx, Eigen::Index ny) {
  MasingImage m;
  if (v.empty()) return m;
  auto fail = [](const std::string& what) { throw std::runtime_error("masing image: " + what); };
  for (const double x : v)
    if (!std::isfinite(x)) fail("holds a non-finite value");
  const double cells = double(nx * ny);
  if (v.size() < 7 || (v[0] != 1.0 && v[0] != 2.0) || (v[0] == 2.0 && v.size() < 8))
    fail("unknown layout");
  const std::size_t head = v[0] == 1.0 ? 7 : 8;
  const double nodes = v[4], levels = v[5], recent = head == 8 ? v[7] : 0.0;
  if (nodes < 0 || nodes > cells || nodes != std::floor(nodes) || levels < 1 ||
      levels != std::floor(levels) || (v[6] != 0.0 && v[6] != 1.0) ||
      (recent != 0.0 && recent != 1.0 && recent != 2.0))
    fail("bad counts");
  const auto m_n = std::size_t(nodes), l_n = std::size_t(levels), r_n = std::size_t(recent);
  if (v.size() != head + m_n + l_n + l_n * m_n + (v[6] != 0.0 ? std::size_t(cells) : 0) + r_n)
    fail("has " + std::to_string(v.size()) + " numbers, not what its counts say");
  m.sign_ = v[1] < 0.0 ? -1.0 : 1.0, m.full_ = v[2] != 0.0, m.turning_level_ = v[3];
  std::size_t at = head;
  for (std::size_t j = 0; j < m_n; ++j, ++at) {
    if (v[at] < 0 || v[at] >= cells || v[at] != std::floor(v[at]) || (j > 0 && v[at] <= v[at - 1]))
      fail("node list not increasing within the grid");
    m.nodes_.push_back(Eigen::Index(v[at]));
  }
  for (std::size_t l = 0; l < l_n; ++l, ++at) {
    if (v[at] < 0 || (l > 0 && v[at] <= v[at - 1])) fail("levels not increasing");
    m.levels_.push_back(v[at]);
  }
  for (std::size_t l = 0; l < l_n; ++l, at += m_n)
    m.tau_.emplace_back(v.begin() + long(at), v.begin() + long(at + m_n));
  if (v[6] != 0.0)
    m.turning_ = Eigen::Map<const Field>(v.data() + at, nx, ny), at += std::size_t(nx * ny);
  for (std::size_t r = 0; r < r_n; ++r, ++at) {
    if (!std::binary_search(m.levels_.begin(), m.levels_.end(), v[at]))
      fail("recent half change not a recorded level");
    m.recent_.push_back(v[at]);
  }
  return m;
}

namespace {

// The flat form's header length and its count of recent half changes (flatten()).
std::size_t header_of(const std::vector<double>& v) {
  return v[0] == 1.0 ? 7 : 8;
}
std::size_t recent_of(const std::vector<double>& v) {
  return header_of(v) == 8 ? std::size_t(v[7]) : 0;
}

}  // namespace

// The flat form's parts per rank: nodes (shifted by the slab's first cell), each level's
// values and the turning traction, each gathered in rank order, which is the order of the
// cells (slabs are consecutive column blocks of the column-major grid); the header, levels and
// recent half changes are the same on every rank.
std::vector<double> MasingImage::gathered(const std::vector<double>& v, const Communicator& comm,
                                          Eigen::Index offset) {
  if (!comm.distributed() || v.empty()) return v;
  const std::size_t head = header_of(v), recent = recent_of(v);
  const auto m = std::size_t(v[4]), levels = std::size_t(v[5]);
  std::vector<double> nodes(v.begin() + long(head), v.begin() + long(head + m));
  for (double& k : nodes) k += double(offset);
  const std::vector<double> all_nodes = comm.gather(nodes, 0);
  std::vector<double> out(v.begin(), v.begin() + long(head));
  out[4] = double(all_nodes.size());
  out.insert(out.end(), all_nodes.begin(), all_nodes.end());
  const auto at_levels = v.begin() + long(head + m);
  out.insert(out.end(), at_levels, at_levels + long(levels));
  for (std::size_t l = 0; l < levels; ++l) {
    const auto at = at_levels + long(levels + l * m);
    const std::vector<double> all = comm.gather(std::vector<double>(at, at + long(m)), 0);
    out.insert(out.end(), all.begin(), all.end());
  }
  const auto at_recent = v.end() - long(recent);
  if (v[6] != 0.0) {
    const auto at = at_levels + long(levels + levels * m);
    const std::vector<double> all = comm.gather(std::vector<double>(at, at_recent), 0);
    out.insert(out.end(), all.begin(), all.end());
  }
  out.insert(out.end(), at_recent, v.end());
  if (comm.rank() != 0) return {};
  return out;
}

std::vector<double> MasingImage::sliced(const std::vector<double>& v, Eigen::Index offset,
                                        Eigen::Index cells) {
  if (v.size() < 7 || (v[0] != 1.0 && v.size() < 8)) return v;  // unflatten says what is wrong
  const std::size_t head = header_of(v), recent = recent_of(v);
  const auto m = std::size_t(v[4]), levels = std::size_t(v[5]);
  if (v.size() < head + m + levels + levels * m + recent) return v;
  std::vector<std::size_t> keep;
  std::vector<double> out(v.begin(), v.begin() + long(head));
  for (std::size_t j = 0; j < m; ++j) {
    const double k = v[head + j] - double(offset);
    if (k >= 0.0 && k < double(cells)) keep.push_back(j), out.push_back(k);
  }
  out[4] = double(keep.size());
  const std::size_t at_levels = head + m;
  out.insert(out.end(), v.begin() + long(at_levels), v.begin() + long(at_levels + levels));
  for (std::size_t l = 0; l < levels; ++l)
    for (const std::size_t j : keep) out.push_back(v[at_levels + levels + l * m + j]);
  const std::size_t at_turning = at_levels + levels + levels * m + std::size_t(offset);
  if (v[6] != 0.0 && at_turning + std::size_t(cells) + recent <= v.size())
    out.insert(out.end(), v.begin() + long(at_turning), v.begin() + long(at_turning + cells));
  out.insert(out.end(), v.end() - long(recent), v.end());
  return out;
}

}  // namespace fretbem
