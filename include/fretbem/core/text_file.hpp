// Small outputs (summaries, status files, XDMF descriptions, checkpoints) written so that a failure
// never leaves a torn file in place of a good one.
#pragma once

#include <filesystem>
#include <string_view>

namespace fretbem {

/// Writes `text` to PATH atomically: PATH.tmp is written, flushed and fsynced with every call
/// checked, then renamed over PATH and the folder fsynced (checkpoints use it too). On any failure
/// (a full disk, a read-only or missing folder) the temporary file is removed, PATH keeps its
/// previous contents, and std::runtime_error says "PATH: cannot write: <system message>". Before,
/// an unchecked stream renamed a truncated sweep.csv over a good one on a full disk, with exit 0
/// (issue 14, session 6).
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

/// Creates DIR (and its parents) for results; InputError "DIR: cannot create the output
/// folder: <reason>" when it cannot (a file of that name, no permission): the same line for
/// run, sweep and ensemble.
void create_output_folder(const std::filesystem::path& dir);

}  // namespace fretbem
