#pragma once
// Whether a file read for a parser is text: a binary file (or one in another encoding)
// is reported at the first offending byte without echoing the bytes themselves, so no
// message ever prints control bytes to a terminal.
#include <cstddef>
#include <optional>
#include <string>

#include "dmbd/base/location.hpp"

namespace dmbd {

// Nothing when `text` is UTF-8 without control characters other than tab, line feed
// and carriage return; else "the file is not text: byte N is 0xHH ..." at its line
// and column (the column counts characters).
std::optional<Diagnostic> not_text(const std::string& text, const std::string& file);

// The same rule applied to a file as it arrives, chunk by chunk (file.hpp's bounded
// reader): where the check has got to, and the first byte that is not text.
struct TextScan {
  std::size_t checked = 0;          // bytes before this offset are whole text characters
  std::optional<std::size_t> bad;   // the offset of the first byte that is not text
};
// Checks `text` from scan.checked on; a character cut off by the end of `text` waits for
// more unless `complete`. True when a byte that is not text was found (scan.bad).
bool scan_text(const std::string& text, bool complete, TextScan& scan);

}  // namespace dmbd
