#include "dmbd/base/number_parser.hpp"

#include <cerrno>
#include <cctype>
#include <cstdlib>

namespace dmbd {

double plain_number(const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  const bool whole = !text.empty() && end == begin + text.size() && !std::isspace(static_cast<unsigned char>(text[0]));
  if (!whole) {
    const std::string shown = text.size() > 60 ? text.substr(0, 57) + "..." : text;
    throw NumberError(0, "expected a number, got '" + shown + "'");
  }
  return v;
}

}  // namespace dmbd
