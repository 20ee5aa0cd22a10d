#pragma once
// Temporary files that an interrupted run must not leave behind. While one is being
// written (write_file_atomic's "<path>.tmp", the video writer's "<stem>.tmp.mp4") its
// path is registered; the command line's handlers of SIGINT, SIGTERM and SIGHUP unlink
// every registered path (async-signal-safe: a fixed table, unlink only) and then let the
// signal end the process as it would have. What a kill -9 leaves is swept by the next
// writer of the folder (remove_stale_temporaries).
#include <string>

namespace dmbd {

// Registers `path` for removal on a signal for the life of the object (it does not
// create or remove the file itself). A path longer than 4095 bytes, or more than 128 at
// once, is not registered (it is still swept as stale later).
class TemporaryPath {
 public:
  explicit TemporaryPath(const std::string& path);
  ~TemporaryPath();
  TemporaryPath(const TemporaryPath&) = delete;
  TemporaryPath& operator=(const TemporaryPath&) = delete;

 private:
  int slot_ = -1;
};

// Installs the handlers of SIGINT, SIGTERM and SIGHUP (once; dmbd's main). A library
// user (the Python module) keeps its own handlers: registered paths are then only
// removed by their writers.
void remove_temporaries_on_signals();

// Removes the files in `dir` (not below it) that a killed writer leaves: names ending in
// ".tmp" (write_file_atomic) or ".tmp.mp4" (the video writer). Quietly: a file that
// cannot be removed stays.
void remove_stale_temporaries(const std::string& dir);

}  // namespace dmbd
