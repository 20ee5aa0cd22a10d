#pragma once
// The project's own simulator on the whole-robot standing task (standing_task.hpp): the
// plant (dmbd::model::Plant) with its fixed semi-implicit step, ideal joint torques or
// the ten VLCAs driven by currents, placed and controlled exactly as the task says.
#include "standing_task.hpp"

namespace dmbd::bench {

// The fixed step is 1 ms (the task's timestep, as MuJoCo's) or 0.5 ms (the step the
// shipped scenarios use).
StandingResult run_dmbd_standing_1ms(const dmbd::model::RobotDescription& robot,
                                     const std::vector<dmbd::model::ActuatorParams>* actuators, const StandingTask& task);
StandingResult run_dmbd_standing_05ms(const dmbd::model::RobotDescription& robot,
                                      const std::vector<dmbd::model::ActuatorParams>* actuators, const StandingTask& task);

}  // namespace dmbd::bench
