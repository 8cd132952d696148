// Stepper's repeat slots: a coupled step of a sequence the caller repeats (the steps of a
// carried wear cycle) starts its normal-tangential alternation from the pressure and traction
// the same step ended with one repetition earlier (set_repeat_slot).
//
// Why: from the step's start (the last step's end; solver.predictor = none) the first
// alternation moves the pressure by 0.1-0.3 of itself (the load changed) and the alternation
// contracts by 0.15-0.2 each time, so a step takes 7-9 alternations, ~1450 convolutions at
// n = 24 (combination sweep seed 48 case 18). One cycle earlier the same step ended on a surface
// that differs by one cycle's wear, with a friction history one cycle's slip behind: a start
// ~1e-3 from the answer there, 4.3 alternations and ~340 convolutions a step. The alternation
// still runs to solver.coupling_tolerance from it, so the step converges to the same fixed
// point within the tolerances; only where it starts changes.
#include <string>

#include "fretbem/history/stepper.hpp"

namespace fretbem {

namespace {

const std::string kRepeatPrefix = "repeat_end";

std::string repeat_name(std::size_t slot, std::size_t c) {
  return kRepeatPrefix + std::to_string(slot) + "_" + std::to_string(c);
}

}  // namespace

// Puts the slot's last end into the state as the alternation's first iterate (traction,
// its displacement C tau, pressure); false when the slot holds none. Nodes the end left on its
// bound and the new bound puts slightly outside or inside are put on the new bound by the
// first alternation (onto_new_bound there; CyclePredictor::onto_moved_bound here for the
// bound of the remembered end, which is not kept).
bool Stepper::start_from_repeat() {
  if (repeat_slot_ < 0 || std::size_t(repeat_slot_) >= repeat_ends_.size()) return false;
  const VecField& end = repeat_ends_[std::size_t(repeat_slot_)];
  const std::size_t nc = state_.traction.size();
  if (end.size() != nc + 1 || end.back().size() != state_.pressure.size()) return false;
  for (std::size_t c = 0; c < nc; ++c) state_.traction[c] = end[c];
  state_.pressure = end.back();
  model_.tangential_operator->apply(state_.traction, state_.displacement);
  return true;
}

// After a coupled step: its end in its slot, for the same step one repetition later.
void Stepper::remember_repeat() {
  if (repeat_slot_ < 0) return;
  const std::size_t slot = std::size_t(repeat_slot_);
  if (repeat_ends_.size() <= slot) repeat_ends_.resize(slot + 1);
  VecField& end = repeat_ends_[slot];
  end = state_.traction;
  end.push_back(state_.pressure);
}

void Stepper::save_repeats(StepperMemory& m) const {
  for (std::size_t s = 0; s < repeat_ends_.size(); ++s)
    for (std::size_t c = 0; c < repeat_ends_[s].size(); ++c)
      m.fields[repeat_name(s, c)] = repeat_ends_[s][c];
}

// The slots a checkpoint holds, each with the traction components and the pressure (a slot
// whose step never ran a coupled alternation holds none); none at all after a fresh start or
// an ODE evaluation's restart, which start from their own state.
void Stepper::restore_repeats(const StepperMemory& m) {
  repeat_ends_.clear();
  const std::size_t nc = state_.traction.size();
  for (auto f = m.fields.lower_bound(kRepeatPrefix);
       f != m.fields.end() && f->first.compare(0, kRepeatPrefix.size(), kRepeatPrefix) == 0; ++f) {
    const std::string slot = f->first.substr(kRepeatPrefix.size());
    const std::size_t s = std::stoul(slot.substr(0, slot.find('_')));
    if (repeat_ends_.size() <= s) repeat_ends_.resize(s + 1);
  }
  for (std::size_t s = 0; s < repeat_ends_.size(); ++s)
    for (std::size_t c = 0; c <= nc; ++c) {
      const auto f = m.fields.find(repeat_name(s, c));
      if (f == m.fields.end()) {
        repeat_ends_[s].clear();
        break;
      }
      repeat_ends_[s].push_back(f->second);
    }
}

}  // namespace fretbem
