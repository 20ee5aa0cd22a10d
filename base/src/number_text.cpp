// Numbers in messages (number_text.hpp).
#include "dmbd/base/number_text.hpp"

#include <sstream>

namespace dmbd {

std::string number_text(double v) {
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

}  // namespace dmbd
