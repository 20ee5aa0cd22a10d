#pragma once
// A number as error and warning messages write it: six significant digits, the shortest
// of fixed and scientific notation (std::ostream's default float format).
#include <string>

namespace dmbd {

// "0.0014184", "1e+06", "130": v with 6 significant digits.
std::string number_text(double v);

}  // namespace dmbd
