// Repairs of a loaded URDF: balanceinertia and moving joints without mass.
#include "urdf_repairs.hpp"

#include "dmbd/base/number_text.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/inertia_repair.hpp"

#include <cmath>
#include <vector>

namespace dmbd::model::detail {

void balance_link_inertia(Link& link, const std::string& where, RobotDescription& robot) {
  const Eigen::Vector3d before = principal_moments(link.inertia_kgm2);
  link.inertia_kgm2 = balance_inertia(link.inertia_kgm2);
  const Eigen::Vector3d after = principal_moments(link.inertia_kgm2);
  const double pct = 100.0 * triangle_excess(before);
  Repair rp;
  rp.link = link.name;
  rp.kind = "balanceinertia";
  rp.before = {before[0], before[1], before[2]};
  rp.after = {after[0], after[1], after[2]};
  rp.what = "inertia violates the triangle inequality (principal moments " + number_text(before[0]) + " + " + number_text(before[1]) +
            " < " + number_text(before[2]) + " kg m^2, by " + number_text(std::round(pct * 10) / 10) + " %)";
  robot.warnings.push_back(where + "link '" + link.name + "': " + rp.what +
                           ": repaired by balanceinertia (principal moments set to their mean, " + number_text(after[2]) +
                           " kg m^2; MuJoCo's rule; --strict refuses)");
  robot.repairs.push_back(std::move(rp));
}

void check_massless_moving(RobotDescription& robot, const std::function<std::string(const std::string&)>& where,
                           bool strict) {
  const std::vector<double> sub = subtree_masses(robot);
  for (const Joint& j : robot.joints) {
    const int c = robot.link_index(j.child);
    if (j.type == JointType::Fixed || c < 0 || sub[static_cast<std::size_t>(c)] > 0) continue;
    const std::string what = std::string("moved by ") + joint_type_name(j.type) + " joint '" + j.name +
                             "' but it and the links below it have no mass";
    if (strict)
      throw ModelError(where(j.name) + "link '" + j.child + "': " + what +
                       " (strict: expected a mass > 0 on a moving link)");
    Repair rp;
    rp.link = j.child;
    rp.kind = "massless_moving_link";
    rp.before = {robot.links[static_cast<std::size_t>(c)].mass_kg};
    rp.after = rp.before;
    rp.what = what;
    robot.warnings.push_back(where(j.name) + "link '" + j.child + "': " + what +
                             ": mass kept at 0 kg (total unchanged); the plant welds joint '" + j.name +
                             "' (--strict refuses)");
    robot.repairs.push_back(std::move(rp));
  }
}

}  // namespace dmbd::model::detail
