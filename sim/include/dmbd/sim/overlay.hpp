#pragma once
// What a run's frames draw over the robot besides the robot itself, declared by whoever
// knows what it means (a bus controller, an experiment) and drawn by report/ from the
// run's log: a point's path, a point marked where it is, or a line of text.
#include <array>
#include <string>
#include <vector>

namespace dmbd::sim {

// One thing drawn over the robot, from logged signals.
struct Overlay {
  // What is drawn.
  enum class Kind {
    Path,    // the point's path over the last window_s seconds up to the frame's sample;
             // samples that are not finite (none logged yet) break the line
    Marker,  // the point at the frame's sample: a ring and a cross (not drawn when not finite)
    Text,    // "LABEL: VALUE" in the frame's text panel, VALUE the first signal's value
  };
  std::string label;                        // in the frame's legend (Path, Marker) or its text (Text)
  // Path, Marker: the point's world x, y, z (m), logged signals; an empty z is the ground
  // (0). Text: the first is the signal shown.
  std::array<std::string, 3> signals;
  std::array<unsigned char, 3> rgb{255, 255, 255};  // its colour
  bool dashed = false;                      // Path: a dashed line (a target), else solid
  double window_s = 2.0;                    // Path: how much of the past it shows, s
  Kind kind = Kind::Path;                   // a path, a marker or a text line
  // Text: the signal's value k (rounded, 0 <= k < size) shown as value_names[k] (a phase
  // machine's state by its name); empty, or out of range: the number itself.
  std::vector<std::string> value_names = {};
};

}  // namespace dmbd::sim
