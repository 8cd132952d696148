#include "fretbem/core/output_lock.hpp"

#include <string>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/text_file.hpp"

namespace fretbem {

namespace fs = std::filesystem;

OutputLock::OutputLock(const fs::path& dir, const char* holder) {
  create_output_folder(dir);
  lock_ = FileLock::try_lock(dir / file_name);
  if (!lock_)
    throw InputError(dir.string() + ": another fretbem " + holder +
                     " is writing into this folder right now; wait for it to end, or choose "
                     "another --out");
}

}  // namespace fretbem
