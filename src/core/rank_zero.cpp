#include "fretbem/core/rank_zero.hpp"

#include <stdexcept>
#include <vector>

#include "fretbem/core/errors.hpp"

namespace fretbem {

namespace {

// The outcome's kind: what main turns into the exit code (2 input, 3 solver, 1 otherwise).
enum class Outcome { ok = 0, input = 1, solver = 2, other = 3 };

[[noreturn]] void raise(Outcome kind, const std::string& message) {
  if (kind == Outcome::input) throw InputError(message);
  if (kind == Outcome::solver) throw SolverError(message);
  throw std::runtime_error(message);
}

}  // namespace

long broadcast_count(const Communicator& comm, long value) {
  double v = double(value);
  comm.broadcast(std::span<double>(&v, 1), 0);
  return long(v);
}

std::string broadcast_text(const Communicator& comm, const std::string& text) {
  if (!comm.distributed()) return text;
  const auto n = std::size_t(broadcast_count(comm, long(text.size())));
  std::vector<double> chars(n);
  if (comm.rank() == 0)
    for (std::size_t i = 0; i < n; ++i) chars[i] = double(static_cast<unsigned char>(text[i]));
  comm.broadcast(chars, 0);
  std::string out(n, '\0');
  for (std::size_t i = 0; i < n; ++i) out[i] = char(static_cast<unsigned char>(chars[i]));
  return out;
}

void on_rank_zero(const Communicator& comm, const std::function<void()>& work) {
  if (!comm.distributed()) return work();
  Outcome kind = Outcome::ok;
  std::string message;
  if (comm.rank() == 0) {
    try {
      work();
    } catch (const InputError& e) {
      kind = Outcome::input, message = e.what();
    } catch (const SolverError& e) {
      kind = Outcome::solver, message = e.what();
    } catch (const std::exception& e) {
      kind = Outcome::other, message = e.what();
    }
  }
  kind = Outcome(broadcast_count(comm, long(kind)));
  if (kind == Outcome::ok) return;
  raise(kind, broadcast_text(comm, message));
}

bool decided_on_rank_zero(const Communicator& comm, const std::function<bool()>& question) {
  if (!comm.distributed()) return question();
  bool answer = false;
  on_rank_zero(comm, [&] { answer = question(); });
  return broadcast_count(comm, answer ? 1 : 0) != 0;
}

}  // namespace fretbem
