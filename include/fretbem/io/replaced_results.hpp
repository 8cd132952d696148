// `run --overwrite` into a folder holding another run's results: they are set aside in
// DIR/.fretbem-replaced/ and removed only once the new run has finished (every row done). A
// new run that fails puts them back (its own files moved to DIR/.fretbem-failed/ for
// inspection); one that is stopped keeps both, its checkpoint in DIR and the results aside,
// so that `run --resume` continues it under the same rule. After a kill the next `run` or
// `run --resume` in DIR settles the folder first (both under the OutputLock).
//
// Kill safety: the old files move into DIR/.fretbem-replacing/, which is then renamed to
// .fretbem-replaced (one atomic step) before the new run writes anything. So a
// .fretbem-replacing folder holds old files only (DIR the rest, nothing new); a
// .fretbem-replaced folder holds all of them (DIR only the new run's files); and the new
// run's checkpoint.h5 in DIR marks a new run that can be resumed. Moving the failed run's
// files away and discarding them take checkpoint.h5 first, so a kill midway leaves a state
// settled the same way. Putting back removes the new run's checkpoint and the files of its that
// no set-aside one replaces, then renames .fretbem-replaced to .fretbem-restoring (one atomic
// step) and renames its files over DIR's, checkpoint.h5 last: a .fretbem-restoring folder
// holds the old files still to put back, DIR no new file they do not replace.
#pragma once

#include <filesystem>
#include <string>

namespace fretbem {

/// Moves the run files of DIR (run_files.hpp) aside, as above; nothing when there are none.
/// When finished results are already aside (a stopped or killed replacement), DIR holds the
/// unfinished new run's files: those are discarded and the finished ones stay aside.
void set_aside_results(const std::filesystem::path& dir);

/// The run in DIR has finished: the results it replaces are removed.
void drop_replaced_results(const std::filesystem::path& dir);

/// What put_back_replaced_results did.
struct PutBack {
  bool put_back = false;         ///< results were set aside, and are back in DIR
  std::filesystem::path failed;  ///< where the failed run's files went; empty: removed
  std::string why_not_kept;      ///< why they could not be kept (one line), when removed
};

/// The run in DIR has failed: its run files move to DIR/.fretbem-failed/ (an older one is
/// removed first; when that fails they are removed) and the set-aside results back into DIR.
/// Nothing is moved when no results were set aside.
PutBack put_back_replaced_results(const std::filesystem::path& dir);

/// DIR holds results a replacement keeps: set aside (a replacement stopped or killed) or put
/// back by a failed one (its files in DIR/.fretbem-failed/ beside them). Whatever replaces them
/// must do it as `run --overwrite` does; emptying DIR would lose finished results.
bool holds_replaced_results(const std::filesystem::path& dir);

/// Brings DIR back to a state above after an interrupted replacement: with the new run's
/// checkpoint in DIR both are kept (the new run resumes); without it the new run's files are
/// removed and the set-aside ones put back. Returns a one-line note when it put any back,
/// else "".
std::string settle_replaced_results(const std::filesystem::path& dir);

}  // namespace fretbem
