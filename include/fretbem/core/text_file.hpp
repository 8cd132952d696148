// Text-file chores: small outputs (summaries, status files, XDMF descriptions, checkpoints)
// written so that a failure never leaves a torn file in place of a good one, and the UTF-8
// byte-order mark some Windows editors put before the first line of an input.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace fretbem {

/// `text` without a leading UTF-8 byte-order mark: it is not part of the first key, cell or
/// height of an input file (scenarios, tables, studies, text height maps).
inline std::string_view without_utf8_bom(std::string_view text) {
  constexpr std::string_view bom = "\xEF\xBB\xBF";
  return text.starts_with(bom) ? text.substr(bom.size()) : text;
}
/// The same in place, for a first line read with std::getline.
inline void drop_utf8_bom(std::string& line) {
  line.erase(0, line.size() - without_utf8_bom(line).size());
}

/// Writes `text` to PATH atomically: PATH.tmp is written, flushed and fsynced with every call
/// checked, then renamed over PATH and the folder fsynced (checkpoints use it too). On any failure
/// (a full disk, a read-only or missing folder) the temporary file is removed, PATH keeps its
/// previous contents, and std::runtime_error says "PATH: cannot write: <system message>". An
/// unchecked stream would rename a truncated file (a sweep.csv) over a good one on a full disk
/// and exit 0.
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

/// Creates DIR (and its parents) for results; InputError "DIR: cannot create the output
/// folder: <reason>" when it cannot (a file of that name, no permission): the same line for
/// run, sweep and ensemble. Refuses (InputError naming DIR) the root folder and the home
/// folder ($HOME), which are never one run's folder.
void create_output_folder(const std::filesystem::path& dir);

/// Refuses (InputError) the root folder and $HOME itself as output folders: a run there would
/// spread its files among everything else. create_output_folder and `check` call it.
void refuse_shared_folder(const std::filesystem::path& dir);

}  // namespace fretbem
