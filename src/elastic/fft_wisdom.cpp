#include "fretbem/elastic/fft_wisdom.hpp"

#include <fftw3.h>
#include <unistd.h>

#include <cstdlib>
#include <mutex>
#include <string>
#include <system_error>

namespace fretbem::fft_wisdom {

namespace fs = std::filesystem;

namespace {

bool single(FftPrecision p) {
  return p == FftPrecision::float32;
}

// Reads wisdom into FFTW's global store; FFTW merges it with what the process already has.
void import_file(FftPrecision p, const fs::path& f) {
  std::error_code ec;
  if (!fs::is_regular_file(f, ec)) return;
  if (single(p))
    fftwf_import_wisdom_from_filename(f.c_str());
  else
    fftw_import_wisdom_from_filename(f.c_str());
}

}  // namespace

fs::path file(FftPrecision p) {
  const std::string name = single(p) ? "fftw-wisdom-float" : "fftw-wisdom-double";
  if (const char* env = std::getenv("FRETBEM_FFTW_WISDOM")) {
    if (!*env) return {};
    return single(p) ? fs::path(std::string(env) + ".float") : fs::path(env);
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return fs::path(xdg) / "fretbem" / name;
  if (const char* home = std::getenv("HOME"); home && *home)
    return fs::path(home) / ".cache" / "fretbem" / name;
  return {};
}

namespace {

// The file's folder, made if missing; false when it cannot be had or written.
bool writable_folder(const fs::path& f) {
  std::error_code ec;
  const fs::path dir = f.has_parent_path() ? f.parent_path() : fs::path(".");
  fs::create_directories(dir, ec);
  return fs::is_directory(dir, ec) && ::access(dir.c_str(), W_OK) == 0;
}

}  // namespace

bool persistent(FftPrecision p) {
  const fs::path f = file(p);
  return !f.empty() && writable_folder(f);
}

std::optional<FileLock> lock(FftPrecision p) {
  const fs::path f = file(p);
  if (f.empty() || !writable_folder(f)) return std::nullopt;
  return FileLock::wait_lock(f.string() + ".lock");
}

// Forgets first, so that the file's entries are all the process knows: FFTW's planner also
// records the lookups it made (the failed WISDOM_ONLY attempt included), and the process must
// not plan from anything but what the lock holder saved. Plans already made stay valid.
void reload(FftPrecision p) {
  const fs::path f = file(p);
  if (f.empty()) return;
  if (single(p))
    fftwf_forget_wisdom();
  else
    fftw_forget_wisdom();
  import_file(p, f);
}

void load(FftPrecision p) {
  static std::once_flag loaded[2];
  std::call_once(loaded[single(p)], [p] {
    const fs::path f = file(p);
    if (!f.empty()) import_file(p, f);
  });
}

void save(FftPrecision p) {
  const fs::path f = file(p);
  if (f.empty() || !writable_folder(f)) return;
  import_file(p, f);  // keep what other runs added since this one loaded
  const fs::path tmp = f.string() + ".tmp" + std::to_string(::getpid());
  const int ok = single(p) ? fftwf_export_wisdom_to_filename(tmp.c_str())
                           : fftw_export_wisdom_to_filename(tmp.c_str());
  std::error_code ec;
  if (ok) fs::rename(tmp, f, ec);
  if (!ok || ec) fs::remove(tmp, ec);
}

}  // namespace fretbem::fft_wisdom
