// The step observers of a run on a grid distributed over MPI ranks: the files are written on
// rank 0 from the whole grid's state gathered to it (docs/mpi-grid.md).
#pragma once

#include <vector>

#include "fretbem/history/observer.hpp"

namespace fretbem {

/// A distributed grid's writers (on rank 0; none elsewhere), called on rank 0 with the whole
/// grid's state gathered to it; an error there (a full disk, a non-finite column) is raised on
/// every rank. Every rank holds one and calls it alike.
class GatheredWriters final : public Observer {
 public:
  explicit GatheredWriters(std::vector<Observer*> writers) : writers_(std::move(writers)) {}
  void on_step(const StepRecord& rec, const InterfaceState& state, const Model& model) override;
  void on_finish(const InterfaceState& state, const Model& model) override;

 private:
  std::vector<Observer*> writers_;
};

}  // namespace fretbem
