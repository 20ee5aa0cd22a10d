#pragma once
// Internal to report/: the 3-D replay written into DIR/replay/ (replay.cpp) for the page.
#include <string>
#include <vector>

#include "dmbd/report/report.hpp"
#include "dmbd/viz/report.hpp"

namespace dmbd::report::detail {

// At most this many variants are replayed (the frames' variant and the first others in
// the scenario's order): a matrix of hundreds offers the first ones.
constexpr std::size_t kReplayMaxVariants = 12;
// Poses are sampled at about this rate (every m-th logged row, all rows of a slower log) ...
constexpr double kReplayRateHz = 50;
// ... unless the replayed variants would hold more floats than this (8 MB of float32,
// 10.7 MB as base64 text): then all at the one lower rate that fits, as long as it is at
// least kReplayMinRateHz; below it, variants are left out (the last first, never the
// frames' variant) until it is, or until the frames' variant alone is left.
constexpr double kReplayMaxFloats = 2e6;
constexpr double kReplayMinRateHz = 10;

struct Replay {
  viz::ReportReplay page;             // no variants: no replay
  std::vector<std::string> files;     // written, relative to the directory
  std::vector<std::string> warnings;  // variants without a replay, three.js missing
  std::size_t variants_in_run = 0;    // of which page.variants are replayed
  double rate_hz = 0;                 // the poses' sampling rate asked for (the log's own where it is slower)
};

// Writes DIR/replay/ (an earlier one removed first): three.js, one scene script per
// distinct robot scene, one track script per replayed variant. A variant whose robot or
// log cannot be drawn (pose_columns' InputError: a log_only that keeps no joint angles),
// or three.js not installed, gives a warning instead of a replay (one line for many
// variants); an OutputError (a file that cannot be written) is thrown.
Replay write_replay(const scenario::ScenarioRun& run, const std::string& dir, const ReportOptions& options);

}  // namespace dmbd::report::detail
