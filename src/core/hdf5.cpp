#include "fretbem/core/hdf5.hpp"

#include <stdexcept>

namespace fretbem::hdf5 {

namespace {

herr_t collect_link(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

herr_t innermost_error(unsigned n, const H5E_error2_t* err, void* data) {
  if (n == 0 && err && err->desc) *static_cast<std::string*>(data) = err->desc;
  return 0;
}

}  // namespace

Quiet::Quiet() {
  H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

Quiet::~Quiet() {
  H5Eset_auto2(H5E_DEFAULT, func_, data_);
}

void silence() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

void no_library_close_at_exit() {
  H5dont_atexit();
}

std::vector<std::string> link_names(hid_t group) {
  std::vector<std::string> names;
  if (H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_link, &names) < 0)
    throw std::runtime_error("cannot list a group: " + last_error());
  return names;
}

std::string last_error() {
  std::string msg;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost_error, &msg);
  H5Eclear2(H5E_DEFAULT);
  // A failed system call comes as a multi-line report ("file write failed: time = ...,
  // errno = 28, error message = 'No space left on device', ..."): keep the system's message.
  const std::string tag = "error message = '";
  const auto at = msg.find(tag);
  if (at != std::string::npos) {
    const auto from = at + tag.size();
    msg = msg.substr(0, msg.find(':')) + ": " + msg.substr(from, msg.find('\'', from) - from);
  }
  msg = msg.substr(0, msg.find('\n'));
  return msg.empty() ? "unknown HDF5 error" : msg;
}

bool exists(hid_t loc, const std::string& path) {
  std::size_t pos = 0;
  while (pos != std::string::npos) {
    pos = path.find('/', pos + 1);
    const std::string prefix = path.substr(0, pos);
    if (prefix.empty() || prefix == "/") continue;
    if (H5Lexists(loc, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return true;
}

hid_t checked(hid_t id, const std::string& what, const std::string& action) {
  if (id < 0) throw std::runtime_error(what + ": cannot " + action + ": " + last_error());
  return id;
}

}  // namespace fretbem::hdf5
