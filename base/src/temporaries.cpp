// Temporary files removed on SIGINT, SIGTERM and SIGHUP, and swept when stale
// (temporaries.hpp).
#include "dmbd/base/temporaries.hpp"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>
#include <filesystem>

namespace dmbd {

namespace {

constexpr int kSlots = 128;
constexpr std::size_t kPathBytes = 4096;

enum SlotState : int { kFree = 0, kFilling = 1, kRegistered = 2 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[kPathBytes];
};

Slot slots[kSlots];

static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the slots' states");

extern "C" void unlink_temporaries(int sig) {
  for (Slot& s : slots)
    if (s.state.load(std::memory_order_acquire) == kRegistered) ::unlink(s.path);
  std::signal(sig, SIG_DFL);  // the signal, blocked while this runs, then ends the process
  std::raise(sig);
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

TemporaryPath::TemporaryPath(const std::string& path) {
  if (path.size() >= kPathBytes) return;
  for (int k = 0; k < kSlots; ++k) {
    int expected = kFree;
    if (!slots[k].state.compare_exchange_strong(expected, kFilling, std::memory_order_acq_rel)) continue;
    std::memcpy(slots[k].path, path.c_str(), path.size() + 1);
    slots[k].state.store(kRegistered, std::memory_order_release);
    slot_ = k;
    return;
  }
}

TemporaryPath::~TemporaryPath() {
  if (slot_ >= 0) slots[slot_].state.store(kFree, std::memory_order_release);
}

void remove_temporaries_on_signals() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction a {};
    a.sa_handler = unlink_temporaries;
    sigemptyset(&a.sa_mask);
    a.sa_flags = 0;
    ::sigaction(sig, &a, nullptr);
  }
}

void remove_stale_temporaries(const std::string& dir) {
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if ((ends_with(name, ".tmp") || ends_with(name, ".tmp.mp4")) && it->is_regular_file(ec)) std::filesystem::remove(it->path(), ec);
  }
}

}  // namespace dmbd
