#pragma once
// The loader's repairs of physically invalid values (docs/model.md, "Repairs"): each
// appends a Repair and a one-line warning to the description.
#include "dmbd/model/robot_description.hpp"

#include <functional>
#include <string>

namespace dmbd::model::detail {

// balanceinertia on `link` (inertia_kgm2 already in the link frame): every principal
// moment becomes their mean. `where` is "FILE:LINE: " of its <inertia>.
void balance_link_inertia(Link& link, const std::string& where, RobotDescription& robot);

// Moving joints (any type but fixed) whose child and every link below it have no mass.
// strict: throws ModelError naming the first, at where(joint name); otherwise each is
// listed (the mass stays 0; the plant welds such a joint).
void check_massless_moving(RobotDescription& robot, const std::function<std::string(const std::string&)>& where,
                           bool strict);

}  // namespace dmbd::model::detail
