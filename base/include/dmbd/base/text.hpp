#pragma once
// Whether a file read for a parser is text: a binary file (or one in another encoding)
// is reported at the first offending byte without echoing the bytes themselves, so no
// message ever prints control bytes to a terminal.
#include <optional>
#include <string>

#include "dmbd/base/location.hpp"

namespace dmbd {

// Nothing when `text` is UTF-8 without control characters other than tab, line feed
// and carriage return; else "the file is not text: byte N is 0xHH ..." at its line
// and column (the column counts characters).
std::optional<Diagnostic> not_text(const std::string& text, const std::string& file);

}  // namespace dmbd
