#pragma once
// Internal to control/: the built-in bus controller types (registry.cpp lists them).
#include <memory>

#include "dmbd/control/registry.hpp"

namespace dmbd::control::detail {

std::shared_ptr<const BusControllerType> osc_type();      // osc_type.cpp
std::shared_ptr<const BusControllerType> balance_type();  // balance_type.cpp

// The keys of a type: the common ones and its own.
std::vector<std::string> allowed_keys(std::initializer_list<const char*> own);
// Checks the map's keys (an unknown one recorded, then yaml::Skip).
void check_keys(const yaml::Fields& f, const YAML::Node& n, const std::string& what, std::initializer_list<const char*> own);

}  // namespace dmbd::control::detail
