#pragma once
// A scenario variant's bus controller options of one type, for the tests: read
// (bus_options) and edited in place (edit_bus_options: the variant gets its own copy).
#include <memory>
#include <stdexcept>

#include "dmbd/scenario/scenario.hpp"

namespace dmbd::test {

// The first bus controller of v whose options are a T, or null.
template <class T>
const T* bus_options(const scenario::VariantSetup& v) {
  for (const auto& o : v.bus_controllers)
    if (const auto* t = dynamic_cast<const T*>(o.get())) return t;
  return nullptr;
}

// The same, as a copy of v's own that the test may change (throws when v has none).
template <class T>
T& edit_bus_options(scenario::VariantSetup& v) {
  for (auto& o : v.bus_controllers)
    if (const auto* t = dynamic_cast<const T*>(o.get())) {
      auto copy = std::make_shared<T>(*t);
      o = copy;
      return *copy;
    }
  throw std::runtime_error("the variant has no such bus controller");
}

}  // namespace dmbd::test
