#include "fretbem/io/replaced_results.hpp"

#include <string_view>

#include "fretbem/core/errors.hpp"
#include "fretbem/io/run_files.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMoving = ".fretbem-replacing";
constexpr const char* kAside = ".fretbem-replaced";
constexpr const char* kRestoring = ".fretbem-restoring";
constexpr const char* kFailed = ".fretbem-failed";
constexpr const char* kCheckpoint = "checkpoint.h5";

bool present(const fs::path& p) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(p, ec));
}

// rename(2) with the file named on failure (InputError: the folder is not usable as is).
void move(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  if (ec)
    throw InputError(from.string() + ": cannot move it to " + to.string() + ": " + ec.message());
}

void remove_tree(const fs::path& p) {
  std::error_code ec;
  fs::remove_all(p, ec);
  if (ec) throw InputError(p.string() + ": cannot remove: " + ec.message());
}

void make_folder(const fs::path& p) {
  std::error_code ec;
  fs::create_directory(p, ec);
  if (ec) throw InputError(p.string() + ": cannot create: " + ec.message());
}

// Every run file of `from` into `to` (which exists), the checkpoint first: without it `from`
// no longer holds a run to resume.
void move_run_files(const fs::path& from, const fs::path& to) {
  if (present(from / kCheckpoint)) move(from / kCheckpoint, to / kCheckpoint);
  for (const char* f : kRunOutputFiles)
    if (present(from / f)) move(from / f, to / f);
}

// The checkpoint first, as above.
void remove_run_files(const fs::path& dir) {
  if (present(dir / kCheckpoint)) remove_tree(dir / kCheckpoint);
  for (const char* f : kRunOutputFiles)
    if (present(dir / f)) remove_tree(dir / f);
}

// Renames every file of the restoring folder over DIR's, the checkpoint last (until then DIR
// holds no run to resume), then removes the folder: a kill midway is finished by the next run.
void finish_restore(const fs::path& dir) {
  const fs::path from = dir / kRestoring;
  for (const char* f : kRunOutputFiles)
    if (f != std::string_view(kCheckpoint) && present(from / f)) move(from / f, dir / f);
  if (present(from / kCheckpoint)) move(from / kCheckpoint, dir / kCheckpoint);
  remove_tree(from);
}

// The set-aside files back into DIR, in place of the new run's: its checkpoint and the files
// of its that none replaces are removed before the set-aside folder becomes the restoring one,
// so from then on a run file in DIR that is not in it is one already put back.
void restore(const fs::path& dir) {
  const fs::path aside = dir / kAside;
  if (present(dir / kCheckpoint)) remove_tree(dir / kCheckpoint);
  for (const char* f : kRunOutputFiles)
    if (present(dir / f) && !present(aside / f)) remove_tree(dir / f);
  move(aside, dir / kRestoring);
  finish_restore(dir);
}

}  // namespace

void set_aside_results(const fs::path& dir) {
  if (present(dir / kAside)) return remove_run_files(dir);  // the finished results stay aside
  const fs::path moving = dir / kMoving;
  remove_tree(moving);  // settle_replaced_results emptied it; anything left is not ours
  make_folder(moving);
  move_run_files(dir, moving);
  move(moving, dir / kAside);
}

void drop_replaced_results(const fs::path& dir) {
  if (present(dir / kAside)) remove_tree(dir / kAside);
}

PutBack put_back_replaced_results(const fs::path& dir) {
  if (!present(dir / kAside)) return {};
  PutBack done{.put_back = true, .failed = dir / kFailed, .why_not_kept = {}};
  try {
    remove_tree(done.failed);
    make_folder(done.failed);
    move_run_files(dir, done.failed);
  } catch (const InputError& e) {  // the finished results come first: restore removes the rest
    done.failed.clear(), done.why_not_kept = e.what();
  }
  restore(dir);
  return done;
}

bool holds_replaced_results(const fs::path& dir) {
  for (const char* f : {kMoving, kAside, kRestoring, kFailed})
    if (present(dir / f)) return true;
  return false;
}

std::string settle_replaced_results(const fs::path& dir) {
  std::string note;
  if (present(dir / kRestoring)) {  // killed while putting them back
    finish_restore(dir);
    note = "put back";
  }
  if (present(dir / kMoving)) {  // killed while setting aside: DIR holds the rest of them
    move_run_files(dir / kMoving, dir);
    remove_tree(dir / kMoving);
    note = "put back";
  }
  if (present(dir / kAside)) {
    if (present(dir / kCheckpoint)) return note;  // a new run to resume: both are kept
    restore(dir);
    note = "put back";
  }
  if (note.empty()) return "";
  return "note: " + dir.string() +
         ": a run with --overwrite ended before it finished or had a checkpoint; the results it "
         "was to replace are put back";
}

}  // namespace fretbem
