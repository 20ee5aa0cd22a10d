#include "simulate_jobs.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/scenario/run_parts.hpp"

namespace dmbd::apps {

namespace {

namespace fs = std::filesystem;

// A fresh folder under the system's temporary folder, removed with everything in it.
class ScratchFolder {
 public:
  ScratchFolder() {
    std::string t = (fs::temp_directory_path() / "dmbd-jobs-XXXXXX").string();
    if (!mkdtemp(t.data())) throw OutputError("cannot create a temporary folder for the workers (" + t + "): " + std::strerror(errno));
    path_ = t;
  }
  ~ScratchFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  std::string part(std::size_t k) const { return (fs::path(path_) / fmt::format("part{}", k)).string(); }
  std::string error(std::size_t k) const { return (fs::path(path_) / fmt::format("error{}.txt", k)).string(); }

 private:
  std::string path_;
};

// In the worker: run variant k, write its part, and leave without unwinding the parent's
// state (no destructors, no atexit handlers: the parent owns the loaded objects' folders).
[[noreturn]] void work(const scenario::Scenario& s, std::size_t k, const scenario::ScenarioRunOptions& o, const ScratchFolder& scratch) {
  int status = 0;
  std::string message;
  try {
    scenario::ScenarioRunOptions quiet;
    quiet.duration_s = o.duration_s;
    scenario::write_part(s, scenario::run_scenario_variant(s, s.variants[k], quiet), scratch.part(k));
  } catch (const InputError& e) {
    status = 2, message = e.what();
  } catch (const std::exception& e) {
    status = 1, message = e.what();
  } catch (...) {
    status = 1, message = "unknown exception in the worker process";
  }
  if (status != 0) {
    try {
      write_file_atomic(scratch.error(k), message);
    } catch (...) {
      status = 3;  // the parent says the worker could not report
    }
  }
  std::_Exit(status);
}

struct Outcome {
  int status = 0;    // the worker's exit status; -1: killed by a signal
  int signal = 0;
};

// The first failed worker's error in the scenario's order, thrown.
[[noreturn]] void rethrow(const scenario::Scenario& s, const std::map<std::size_t, Outcome>& failed, const ScratchFolder& scratch) {
  const auto& [k, out] = *failed.begin();
  const std::string variant = s.variants[k].name;
  if (out.status == -1)
    throw std::runtime_error(fmt::format("the worker process of variant '{}' was killed by signal {} ({})", variant, out.signal, strsignal(out.signal)));
  std::string message;
  if (out.status == 3 || try_read_file(scratch.error(k), message))
    throw std::runtime_error(fmt::format("the worker process of variant '{}' failed (exit status {}) without a message", variant, out.status));
  if (out.status == 2) throw InputError(message);
  throw std::runtime_error(message);
}

}  // namespace

std::vector<sim::VariantResult> run_variants_in_processes(const scenario::Scenario& s, const scenario::ScenarioRunOptions& o, int jobs) {
  scenario::build_controllers(s);  // compiled once, here: the workers inherit the loaded objects
  ScratchFolder scratch;
  double total = 0, done = 0;
  for (const auto& v : s.variants) total += o.duration_s.value_or(v.duration_s);
  std::map<pid_t, std::size_t> running;
  std::map<std::size_t, Outcome> failed;
  std::size_t next = 0;
  while ((failed.empty() && next < s.variants.size()) || !running.empty()) {
    while (failed.empty() && next < s.variants.size() && running.size() < static_cast<std::size_t>(jobs)) {
      std::cout.flush(), std::cerr.flush(), std::fflush(nullptr);  // a worker must not print the parent's buffers again
      const pid_t pid = fork();
      if (pid == 0) work(s, next, o, scratch);
      if (pid < 0) {
        if (running.empty()) throw std::runtime_error(std::string("cannot start a worker process: ") + std::strerror(errno));
        break;  // fewer at a time
      }
      running[pid] = next++;
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("waiting for the worker processes: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;  // not a worker
    const std::size_t k = it->second;
    running.erase(it);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      done += o.duration_s.value_or(s.variants[k].duration_s);
      if (o.on_progress) o.on_progress(done / total, s.variants[k].name);
    } else {
      failed[k] = WIFSIGNALED(status) ? Outcome{-1, WTERMSIG(status)} : Outcome{WEXITSTATUS(status), 0};
    }
  }
  if (!failed.empty()) rethrow(s, failed, scratch);
  std::vector<sim::VariantResult> runs;
  for (std::size_t k = 0; k < s.variants.size(); ++k) runs.push_back(scenario::read_part(s, s.variants[k], scratch.part(k)));
  return runs;
}

}  // namespace dmbd::apps
