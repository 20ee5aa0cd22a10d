#pragma once
#include <stdexcept>
#include <string>

namespace dmbd::model {

// A user mistake in a model file (URDF, actuator table): the message is one line
// naming the file, the line where known, and what was expected.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace dmbd::model
