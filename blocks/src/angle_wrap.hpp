#pragma once
// Angles wrapped onto one turn, for the frequency responses' phase bookkeeping
// (frequency.cpp, phase_model.cpp, zpk.cpp). Private to blocks/.
#include <cmath>

namespace dmbd::blocks {

inline double wrap_pi(double a) {  // into (-pi, pi]
  a = std::remainder(a, 2.0 * M_PI);
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

inline double wrap_2pi(double a) {  // into [0, 2 pi)
  a = std::fmod(a, 2.0 * M_PI);
  return a < 0.0 ? a + 2.0 * M_PI : a;
}

}  // namespace dmbd::blocks
