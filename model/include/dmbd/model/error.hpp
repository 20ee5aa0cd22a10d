#pragma once
#include <string>

#include "dmbd/base/error.hpp"

namespace dmbd::model {

// A user mistake in a model file (URDF, actuator table), or a simulation that diverged:
// the message is one line naming the file, the line where known, and what was expected
// (or the time and the state).
class ModelError : public InputError {
 public:
  using InputError::InputError;
};

}  // namespace dmbd::model
