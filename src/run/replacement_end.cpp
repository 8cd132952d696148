#include "fretbem/run/replacement_end.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/rank_zero.hpp"
#include "fretbem/history/failed_solve.hpp"
#include "fretbem/io/replaced_results.hpp"

namespace fretbem {

namespace {

// Puts the replaced results back and says so; "" when the run replaced none. A folder that
// cannot be put back now is settled by the next run in it (the error says which file).
std::string put_back(const std::filesystem::path& dir, std::filesystem::path& failed) {
  try {
    const PutBack done = put_back_replaced_results(dir);
    failed = done.failed;
    if (!done.put_back) return "";
    const std::string put = "; the results it was to replace are put back, its own files ";
    if (failed.empty()) return put + "removed (" + done.why_not_kept + ")";
    return put + "are in " + failed.string();
  } catch (const std::exception& e) {
    return "; the results it was to replace are not put back yet (" + std::string(e.what()) +
           "): the next run or resume in " + dir.string() + " settles the folder";
  }
}

// The current exception again, its message ending in `note` (one error line, as main prints
// it); a failed solve's inputs go where its files went. Errors without a message of their own
// (out of memory, a file system call) keep it, the note printed before.
[[noreturn]] void rethrow_with(const std::string& note, const std::filesystem::path& failed) {
  try {
    throw;
  } catch (const IncrementFailure& e) {
    throw IncrementFailure(e.what() + note, e.inputs, failed.empty() ? e.dir : failed);
  } catch (const InputError& e) {
    throw InputError(e.what() + note);
  } catch (const SolverError& e) {
    throw SolverError(e.what() + note);
  } catch (const std::system_error&) {
    std::fprintf(stderr, "fretbem: the run failed%s\n", note.c_str());
    throw;
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(e.what() + note);
  } catch (...) {
    std::fprintf(stderr, "fretbem: the run failed%s\n", note.c_str());
    throw;
  }
}

}  // namespace

int settle_replacement_at_end(const std::filesystem::path& dir, const Communicator& comm,
                              const std::function<RunEnd()>& run) {
  RunEnd end;
  try {
    end = run();
  } catch (...) {
    if (comm.rank() != 0) throw;
    std::filesystem::path failed;
    const std::string note = put_back(dir, failed);
    if (note.empty()) throw;
    rethrow_with(note, failed);
  }
  // After the try: a finished run whose old results cannot be removed has not failed.
  if (end.finished) on_rank_zero(comm, [&] { drop_replaced_results(dir); });
  return end.code;
}

}  // namespace fretbem
