#pragma once
// What a run's frames draw over the robot besides the robot itself, declared by whoever
// knows what it means (a bus controller, an experiment) and drawn by report/ from the
// run's log: a point's path, its world position read from three logged signals.
#include <array>
#include <string>

namespace dmbd::sim {

// A point's path over the last window_s seconds of the run up to the frame's sample;
// samples that are not finite (none logged yet) break the line.
struct Overlay {
  std::string label;                        // in the frame's legend
  std::array<std::string, 3> signals;       // the point's world x, y, z (m), logged signals
  std::array<unsigned char, 3> rgb{255, 255, 255};  // its colour
  bool dashed = false;                      // a dashed line (a target), else solid
  double window_s = 2.0;                    // how much of the past it shows, s
};

}  // namespace dmbd::sim
