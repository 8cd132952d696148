// The latest wear-map value simulated, kept with the worn depth it ran on, so that the
// implicit integrator's repeated iterate is answered without simulating the steady cycle again.
// Internal to src/wear.
#pragma once

#include "fretbem/elastic/half_space.hpp"

namespace fretbem::wear_detail {

/// The wear map dW/dN = w(z0 - W) is autonomous: a function of the worn depth W (m) alone, N
/// only labels its row. TR-BDF2 with the trivial Newton predictor starts an implicit stage
/// from the step's start y_n (ARKODE copies y_n into the predictor: the first iterate is y_n
/// bit for bit), which the step's explicit first stage, or the stage before that converged at
/// its first iterate, has just evaluated. Only the latest evaluation is kept: it is also the
/// point the frozen-slip Newton matrix is linearised at and the normal solves' warm start
/// predicts from, so a repeat answered from here leaves both consistent.
class MapMemo {
 public:
  /// The rate (m per cycle) kept for exactly this worn depth (this rank's slab; the match is
  /// decided over all ranks), or null.
  const Field* find(const Field& worn, const Communicator& comm) const;
  /// Keeps an evaluation in place of the previous one.
  void keep(const Field& worn, const Field& rate);
  /// Bytes per grid cell held: a worn depth and a rate.
  static constexpr double kBytesPerCell = 2.0 * sizeof(double);

 private:
  Field worn_, rate_;
};

}  // namespace fretbem::wear_detail
