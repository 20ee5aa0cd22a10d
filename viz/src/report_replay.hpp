#pragma once
// Internal to viz/: the report page's 3-D replay section (report_replay.cpp) and its
// player script (replay_player.cpp).
#include <string>
#include <string_view>

#include "dmbd/viz/report.hpp"

namespace dmbd::viz::detail {

// The path percent-encoded for an attribute, or std::invalid_argument naming `field`
// unless it is relative and inside the report's directory (report.cpp).
std::string report_url(const std::string& path, std::string_view field);

// The replay's CSS (added to the page's style when there is a replay).
extern const char* const kReplayCss;
// The player (inlined after the replay's library scripts).
extern const char* const kReplayPlayerJs;

// The section (controls, view, setup) appended to `out`; nothing for no variants.
// Throws std::invalid_argument for a path outside the directory, an initial variant out
// of range, a replay without its two library scripts, or a camera validate() refuses.
void replay_section(const ReportReplay& replay, std::string& out);
// The library scripts and the player, for the end of the body; nothing for no variants.
void replay_scripts(const ReportReplay& replay, std::string& out);

}  // namespace dmbd::viz::detail
