// `run --overwrite` into a folder holding another run's results: they are set aside in
// DIR/.fretbem-replaced/ and dropped only once the new run has written its first checkpoint
// (after step 0; a wear run: after its first wear step). A run that fails or is killed before
// then leaves them as they were: at once on an error, and after a kill at the next `run` or
// `run --resume` in DIR, which settles the folder first (both under the OutputLock).
//
// Kill safety: the old files move into DIR/.fretbem-replacing/, which is then renamed to
// .fretbem-replaced (one atomic step) before the new run writes anything. So a
// .fretbem-replacing folder holds old files only (DIR the rest, nothing new); a
// .fretbem-replaced folder holds all of them (DIR only the new run's files); and the new
// run's checkpoint.h5 marks the moment from which the new run is the one to keep.
#pragma once

#include <filesystem>
#include <string>

namespace fretbem {

/// Moves the run files of DIR (run_files.hpp) aside, as above; nothing when there are none.
void set_aside_results(const std::filesystem::path& dir);

/// Whether DIR holds set-aside results: the run must checkpoint after step 0 to drop them.
bool replacing_results(const std::filesystem::path& dir);

/// The run in DIR has its checkpoint: the results it replaces are removed.
void drop_replaced_results(const std::filesystem::path& dir);

/// Brings DIR back to one run's files after an interrupted replacement: with the new run's
/// checkpoint the set-aside results are removed; without it the new run's files are removed
/// and the set-aside ones put back. Returns a one-line note when it put any back, else "".
std::string settle_replaced_results(const std::filesystem::path& dir);

}  // namespace fretbem
