#pragma once
// Internal to report/: a variant's log sampled into a 3-D replay track (viz::ReplayTrack):
// at each sampled row, every link's pose by the frames' forward kinematics
// (log_poses.hpp), the table's (a fixed base without contact, one body after the links),
// the centre of mass, the contact forces where the frames draw them and the overlays'
// signals.
#include <cstddef>
#include <optional>
#include <vector>

#include "dmbd/viz/replay.hpp"
#include "log_poses.hpp"
#include "table.hpp"

namespace dmbd::report::detail {

// Rows 0, m, 2m, ... and the last row, m = max(1, round(1 / (rate_hz dt))) for the log's
// mean step dt: about rate_hz samples a simulated second (all rows of a slower log).
std::vector<std::size_t> replay_rows(const sim::Log& log, double rate_hz);

// Floats a sample of the track holds (poses, forces, centre of mass, overlays, time):
// what the replay's size budget counts.
std::size_t floats_per_sample(const model::RobotDescription& robot, const PoseColumns& c, bool table);

viz::ReplayTrack replay_track(const model::RobotDescription& robot, const sim::VariantResult& r, const PoseColumns& c,
                              const std::optional<Table>& table, const std::vector<std::size_t>& rows);

}  // namespace dmbd::report::detail
