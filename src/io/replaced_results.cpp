#include "fretbem/io/replaced_results.hpp"

#include "fretbem/core/errors.hpp"
#include "fretbem/io/run_files.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMoving = ".fretbem-replacing";
constexpr const char* kAside = ".fretbem-replaced";

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

// Every run file of `from` into `to` (which exists).
void move_run_files(const fs::path& from, const fs::path& to) {
  for (const char* f : kRunOutputFiles)
    if (present(from / f)) move(from / f, to / f);
}

// The set-aside files back into DIR, in place of the new run's.
void restore(const fs::path& dir, const fs::path& aside) {
  for (const char* f : kRunOutputFiles)
    if (present(dir / f)) remove_tree(dir / f);
  move_run_files(aside, dir);
  remove_tree(aside);
}

}  // namespace

void set_aside_results(const fs::path& dir) {
  const fs::path moving = dir / kMoving;
  remove_tree(moving);  // settle_replaced_results emptied it; anything left is not ours
  std::error_code ec;
  fs::create_directory(moving, ec);
  if (ec) throw InputError(moving.string() + ": cannot create: " + ec.message());
  move_run_files(dir, moving);
  move(moving, dir / kAside);
}

bool replacing_results(const fs::path& dir) {
  return present(dir / kAside);
}

void drop_replaced_results(const fs::path& dir) {
  if (present(dir / kAside)) remove_tree(dir / kAside);
}

std::string settle_replaced_results(const fs::path& dir) {
  std::string note;
  if (present(dir / kMoving)) {  // killed while setting aside: DIR holds the rest of them
    move_run_files(dir / kMoving, dir);
    remove_tree(dir / kMoving);
    note = "put back";
  }
  if (present(dir / kAside)) {
    if (present(dir / "checkpoint.h5")) return drop_replaced_results(dir), note;
    restore(dir, dir / kAside);
    note = "put back";
  }
  if (note.empty()) return "";
  return "note: " + dir.string() +
         ": a run with --overwrite ended before its first checkpoint; the results it was to "
         "replace are put back";
}

}  // namespace fretbem
