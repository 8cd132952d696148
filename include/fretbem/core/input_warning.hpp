// Cautions about inputs that are accepted but doubtful (a key the scenario's choices leave
// unread, a height map with no spacing to check, a shift near the small-slip bound). The
// library says them here; the program decides where they go (`fretbem` prints each distinct
// one once on stderr, for `check` and `run` alike). They are held until the inputs are
// accepted (release_input_warnings: the first step is solved, or check reports), so that an
// input refused before then shows its refusal alone, on one line. Without a handler they are
// dropped.
#pragma once

#include <functional>
#include <string>

namespace fretbem {

using InputWarningHandler = std::function<void(const std::string& text)>;

/// Installs the handler (an empty one drops warnings); returns the previous one.
InputWarningHandler set_input_warning_handler(InputWarningHandler handler);

/// Holds one caution (a sentence naming the key, file or value) for the handler.
void input_warning(const std::string& text);

/// Hands the held cautions to the handler, in the order they came.
void release_input_warnings();

}  // namespace fretbem
