// MasingImage: a warm start for the tangential increments after a load reversal at constant
// normal load (solver.predictor = auto | cycle).
//
// Under the Cattaneo–Mindlin analogy with constant Coulomb friction at constant normal load the
// traction on a branch that starts at a turning point T is Masing's image of the virgin loading
// (Mindlin & Deresiewicz 1953 for the sphere; Jäger 1998 and Ciavarella 1998 for any profile):
//   tau(L) = tau_T + sign(L - L_T) 2 tau_v(|L - L_T| / 2),
// L the tangential load (force in N under force control, rigid shift in m under displacement
// control) and tau_v(l) the virgin traction at load l. The virgin tractions are recorded while
// the path loads monotonically from step 0 and interpolated linearly in the load between the
// recorded levels, or continued on the secant of the branch's last two solved steps; the
// virgin steps start on the secant of the two last virgin levels. A start changes the cost,
// never the answer beyond the solver tolerance (the solver iterates from it to its stopping
// rule).
#pragma once

#include <vector>

#include "fretbem/history/load_path.hpp"
#include "fretbem/parallel/communicator.hpp"

namespace fretbem {

struct Model;

class MasingImage {
 public:
  /// Memory bound of the virgin table: at most this many bytes per grid cell (a 64-step Hertz
  /// cycle at 20 % contact records 16 levels: ~26 bytes per cell); further levels are not
  /// recorded (the image then exists only up to the last recorded load).
  static constexpr double kBytesPerCell = 128.0;

  /// For each step k of a path: whether the increment of step k starts from the image. True on
  /// the branches after the first turning point of a path whose normal load and control never
  /// change, unless the cycle predictor (`predictor` = Model::cycle_predictor) holds that
  /// step's transition from a step after the virgin segment (a steady cycle's own history is
  /// exact and costs no extra product).
  /// `level` is the load along the path's single direction (force in units of mu F_z, or N,
  /// or shift in m, as the path states it: F_z is constant, so one unit for the whole path);
  /// `virgin` marks steps 1 .. k_v that load monotonically from step 0, `turning` the steps
  /// after which the load reverses. All empty when the path does not qualify.
  struct Plan {
    std::vector<char> image, virgin, turning;
    std::vector<double> level;
    /// A branch follows the virgin segment (else the path is monotone: the virgin steps
    /// start on the secant, and only the last two virgin levels are kept).
    bool branches = false;
  };
  static Plan plan(const LoadPath& path, bool predictor);
  /// The plan of a model's run: empty unless the image is exact there (one traction component
  /// under the analogy, a friction bound that does not evolve, no wear) and solver.predictor is
  /// not `none` (which turns every warm start off).
  static Plan plan(const Model& model);

  /// A virgin step solved at load `level` with traction `tau` (one component, Pa); without
  /// `keep_all` the levels below the last two are dropped (Plan::branches false).
  void record_virgin(double level, const Field& tau, const Field& bound, bool keep_all = true);
  /// A step solved on a branch at load `level` with traction `tau`: by Masing's rule the
  /// virgin traction at its half change, recorded as a further level.
  void record_branch(double level, const Field& tau, const Field& bound);
  /// A turning point solved at load `level` with traction `tau`: the origin of the next branch.
  void record_turning(double level, const Field& tau);
  /// The image at load `level` on the branch from the last turning point, or nullptr when the
  /// load change lies beyond the recorded virgin levels. Valid until the next call.
  const VecField* image(double level);
  /// The start of a branch step at load `level` (bound `bound`, Pa, constant on the path):
  /// the image where the half change is a recorded level (exact), else the secant through the
  /// last two steps solved on this branch (the turning point counting as one), else the
  /// interpolated image; nullptr where the image is. Valid until the next call.
  const VecField* branch_start(double level, const Field& bound);
  /// The start of the next virgin step at load `level`: the secant through the two highest
  /// recorded levels (load 0, where tau_v = 0, counting as one), or nullptr before the first
  /// level or once the table is full. Valid until the next call.
  const VecField* virgin_start(double level, const Field& bound);

  /// Restart support: the table and the branch origin as one flat list of numbers (the
  /// checkpoint's dataset `masing`; empty when nothing is recorded), and the image it holds
  /// for an nx x ny grid; throws std::runtime_error saying what is wrong on any inconsistency.
  std::vector<double> flatten() const;
  static MasingImage unflatten(const std::vector<double>& v, Eigen::Index nx, Eigen::Index ny);
  /// On a grid distributed over ranks (slabs of whole rows j): the ranks' flat forms joined
  /// into the whole grid's (on rank 0, empty elsewhere), `offset` the first cell of this
  /// rank's slab; and the slab [offset, offset + cells) of a whole grid's flat form.
  static std::vector<double> gathered(const std::vector<double>& v, const Communicator& comm,
                                      Eigen::Index offset);
  static std::vector<double> sliced(const std::vector<double>& v, Eigen::Index offset,
                                    Eigen::Index cells);
  /// The reduction layer of a distributed grid: the memory bound counts the nodes of every
  /// rank, so that all ranks stop recording at the same level (serial by default).
  void set_communicator(const Communicator& comm) { comm_ = &comm; }

 private:
  std::vector<Eigen::Index> nodes_;       ///< contact nodes of the virgin table
  std::vector<double> levels_;            ///< |virgin load| per recorded level, increasing
  std::vector<std::vector<double>> tau_;  ///< virgin traction on nodes_, per level
  double sign_ = 1.0;                     ///< direction of the virgin loading
  bool stops_at_memory_bound(Eigen::Index cells);
  bool full_ = false;  ///< the memory bound stopped recording
  Field turning_;      ///< traction at the last turning point
  double turning_level_ = 0.0;
  std::vector<double> recent_;  ///< the last two half changes recorded on the current branch
  /// tau_v continued past level i1 on the secant through level i0 (or load 0 when i0 is
  /// none) to the half change `half`, on nodes_, with bound g on the full grid.
  void continue_secant(std::ptrdiff_t i0, std::size_t i1, double half, const Field& g,
                       double factor, Field& t) const;
  VecField image_;
  const Communicator* comm_ = &serial_communicator();
};

}  // namespace fretbem
