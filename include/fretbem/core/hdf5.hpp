// HDF5 (C API) handles shared by every reader and writer of .h5 files: result files,
// checkpoints, height maps. One owner per identifier, closed with its matching H5?close, and
// the library's own error printing switched off so failures reach the user as one line.
#pragma once

#include <hdf5.h>

#include <string>
#include <vector>

namespace fretbem::hdf5 {

/// Owns one HDF5 identifier and closes it with the matching H5?close. `close()` reports the
/// status of the close (a file's close flushes it: on a full disk that is where a write fails);
/// the destructor closes silently what was not closed explicitly.
template <herr_t (*Close)(hid_t)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  ~Handle() { close(); }
  Handle(Handle&& o) noexcept : id_(o.id_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) close(), id_ = o.id_, o.id_ = -1;
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  /// Closes now; returns H5?close's status (0 when there was nothing to close).
  herr_t close() {
    const herr_t status = id_ >= 0 ? Close(id_) : 0;
    id_ = -1;
    return status;
  }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_ = -1;
};

using File = Handle<H5Fclose>;
using Group = Handle<H5Gclose>;
using Dataset = Handle<H5Dclose>;
using Space = Handle<H5Sclose>;
using Type = Handle<H5Tclose>;
using Plist = Handle<H5Pclose>;
using Attribute = Handle<H5Aclose>;

/// While alive, HDF5 prints nothing on its own (errors come back as return codes); the
/// previous setting is restored afterwards.
class Quiet {
 public:
  Quiet();
  ~Quiet();
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

/// Switches HDF5's own error printing off for the rest of the process (writers that keep a
/// file open across many calls; readers use Quiet).
void silence();

/// Keeps HDF5 from closing its library (and every file still known to it) at exit. Call
/// first thing in main. A file whose flush failed on a full disk stays registered and its
/// close at exit crashed (SIGSEGV in H5F__close_cb from H5_term_library, HDF5 1.10.8) after
/// the run had reported the error; fretbem's handles close every file themselves.
void no_library_close_at_exit();

/// The names of the links in a group (or file root), by name; throws std::runtime_error if
/// the group cannot be listed.
std::vector<std::string> link_names(hid_t group);

/// The most specific message on the HDF5 error stack, which is then cleared.
std::string last_error();

/// Whether `path` (absolute, or relative to `loc`) names an object. H5Lexists fails (rather
/// than answering no) when an intermediate group is missing, so the path is walked one
/// component at a time; a failing lookup answers no.
bool exists(hid_t loc, const std::string& path);

/// `id` when it is valid (identifiers and status codes alike are negative on failure), else
/// throws std::runtime_error "WHAT: cannot ACTION: <last_error()>".
hid_t checked(hid_t id, const std::string& what, const std::string& action);

}  // namespace fretbem::hdf5
