#include "dmbd/base/text.hpp"

#include <cstdio>

namespace dmbd {

namespace {

// Length of the valid UTF-8 sequence starting at text[i] (0: invalid or a control
// character other than tab, line feed and carriage return).
std::size_t text_char_length(const std::string& text, std::size_t i) {
  const auto c = static_cast<unsigned char>(text[i]);
  if (c < 0x20) return (c == '\t' || c == '\n' || c == '\r') ? 1 : 0;
  if (c < 0x7f) return 1;
  if (c == 0x7f) return 0;
  std::size_t n = 0;
  unsigned lowest = 0;
  if (c >= 0xc2 && c <= 0xdf) n = 2, lowest = 0x80;
  else if (c >= 0xe0 && c <= 0xef) n = 3, lowest = 0x800;
  else if (c >= 0xf0 && c <= 0xf4) n = 4, lowest = 0x10000;
  else return 0;
  if (i + n > text.size()) return 0;
  unsigned code = c & (0x7f >> n);
  for (std::size_t k = 1; k < n; ++k) {
    const auto b = static_cast<unsigned char>(text[i + k]);
    if ((b & 0xc0) != 0x80) return 0;
    code = (code << 6) | (b & 0x3f);
  }
  if (code < lowest || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return 0;
  if (code >= 0x80 && code < 0xa0) return 0;  // C1 control characters
  return n;
}

}  // namespace

std::optional<Diagnostic> not_text(const std::string& text, const std::string& file) {
  int line = 1, column = 1;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = text_char_length(text, i);
    if (n == 0) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned>(static_cast<unsigned char>(text[i])));
      return Diagnostic{{file, line, column},
                        "the file is not text: byte " + std::to_string(i + 1) + " is " + hex +
                            (static_cast<unsigned char>(text[i]) < 0x80 ? ", a control character" : ", not UTF-8") +
                            " (expected a UTF-8 text file)"};
    }
    if (text[i] == '\n') line += 1, column = 0;
    column += 1;
    i += n;
  }
  return std::nullopt;
}

bool scan_text(const std::string& text, bool complete, TextScan& scan) {
  constexpr std::size_t kLongestCharacter = 4;
  std::size_t i = scan.checked;
  while (!scan.bad && i < text.size()) {
    const std::size_t n = text_char_length(text, i);
    if (n == 0 && !complete && text.size() - i < kLongestCharacter) break;  // perhaps cut off: wait
    if (n == 0) scan.bad = i;
    else i += n;
  }
  scan.checked = i;
  return scan.bad.has_value();
}

}  // namespace dmbd
