#pragma once
// A measured error as text with three significant digits, for RecordProperty in the
// balancing pieces' tests (the worst errors show up in the test's XML report).
#include <cstdio>
#include <string>

namespace dmbd::wholebody::testing {

inline std::string text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

}  // namespace dmbd::wholebody::testing
