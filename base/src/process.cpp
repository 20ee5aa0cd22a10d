// Programs started by argument vector, without a shell (process.hpp).
#include "dmbd/base/process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <cstring>

extern char** environ;

namespace dmbd {

namespace {

// posix_spawn's file actions, released however the spawn ends.
class FileActions {
 public:
  FileActions() { posix_spawn_file_actions_init(&a_); }
  ~FileActions() { posix_spawn_file_actions_destroy(&a_); }
  FileActions(const FileActions&) = delete;
  FileActions& operator=(const FileActions&) = delete;
  posix_spawn_file_actions_t* get() { return &a_; }

 private:
  posix_spawn_file_actions_t a_;
};

constexpr int kOutputFlags = O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC;

void redirect(FileActions& fa, int fd, const std::string& path) {
  if (path.empty()) posix_spawn_file_actions_addopen(fa.get(), fd, "/dev/null", O_WRONLY, 0);
  else posix_spawn_file_actions_addopen(fa.get(), fd, path.c_str(), kOutputFlags & ~O_CLOEXEC, 0644);
}

// Starts argv; its pid, or -1 with the reason in `why`.
pid_t spawn(const std::vector<std::string>& argv, FileActions& fa, std::string& why) {
  if (argv.empty()) {
    why = "cannot start a program: no command";
    return -1;
  }
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int err = posix_spawnp(&pid, args[0], fa.get(), nullptr, args.data(), environ);
  if (err != 0) {
    why = "cannot start '" + argv[0] + "': " + std::strerror(err);
    return -1;
  }
  return pid;
}

ProgramRun wait_for(pid_t pid) {
  ProgramRun r;
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      r.why = std::string("cannot wait for the program: ") + std::strerror(errno);
      return r;
    }
  }
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  else r.why = "killed by signal " + std::to_string(WTERMSIG(status));
  return r;
}

}  // namespace

ProgramRun run_program(const std::vector<std::string>& argv, const std::string& out_path, const std::string& err_path) {
  FileActions fa;
  posix_spawn_file_actions_addopen(fa.get(), 0, "/dev/null", O_RDONLY, 0);
  redirect(fa, 1, out_path);
  if (!err_path.empty() && err_path == out_path) posix_spawn_file_actions_adddup2(fa.get(), 1, 2);
  else redirect(fa, 2, err_path);
  ProgramRun r;
  const pid_t pid = spawn(argv, fa, r.why);
  return pid < 0 ? r : wait_for(pid);
}

std::string program_output(const std::vector<std::string>& argv, std::size_t max_bytes) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return "";
  FileActions fa;
  posix_spawn_file_actions_addopen(fa.get(), 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(fa.get(), fds[1], 1);
  posix_spawn_file_actions_addopen(fa.get(), 2, "/dev/null", O_WRONLY, 0);
  std::string why, out;
  const pid_t pid = spawn(argv, fa, why);
  ::close(fds[1]);
  char buffer[4096];
  for (ssize_t n; pid >= 0 && ((n = ::read(fds[0], buffer, sizeof buffer)) > 0 || (n < 0 && errno == EINTR));)
    if (n > 0 && out.size() < max_bytes) out.append(buffer, std::min(static_cast<std::size_t>(n), max_bytes - out.size()));
  ::close(fds[0]);
  if (pid >= 0) wait_for(pid);
  return out;
}

std::vector<std::string> command_words(const std::string& command) {
  std::vector<std::string> words;
  std::string word;
  for (char c : command) {
    if (c == ' ' || c == '\t') {
      if (!word.empty()) words.push_back(word);
      word.clear();
    } else {
      word += c;
    }
  }
  if (!word.empty()) words.push_back(word);
  return words;
}

std::string shell_line(const std::vector<std::string>& argv) {
  std::string line;
  for (const std::string& a : argv) {
    const bool plain = !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./=+:,@%") ==
                                         std::string::npos;
    std::string q = "'";
    for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += (line.empty() ? "" : " ") + (plain ? a : q + "'");
  }
  return line;
}

}  // namespace dmbd
