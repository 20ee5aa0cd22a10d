#include "slurm_cluster.hpp"

#include <fcntl.h>
#include <netinet/in.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>
#include <utility>

#include "cli_support.hpp"

namespace dmbd::slurm_testing {

namespace {

namespace fs = std::filesystem;
using cli_testing::quote;
using cli_testing::slurp;

// Whether a TCP port can be bound on every address (slurmctld and slurmd listen there).
bool port_free(int port) {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_ANY);
  a.sin_port = htons(static_cast<uint16_t>(port));
  const bool ok = s >= 0 && ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  if (s >= 0) ::close(s);
  return ok;
}

// Two free ports from 20000 to 29999: below Linux's ephemeral range (32768 up), so no
// client connection takes them before the daemons bind them, and apart for two test
// processes (from the process id). Not Slurm's 6817/6818, so an installed Slurm is left alone.
std::pair<int, int> two_free_ports() {
  std::vector<int> found;
  for (int k = 0; k < 10000 && found.size() < 2; ++k) {
    const int port = 20000 + (static_cast<int>(::getpid()) * 2 + k) % 10000;
    if (port_free(port)) found.push_back(port);
  }
  return found.size() == 2 ? std::pair{found[0], found[1]} : std::pair{0, 0};
}

// The CPUs this process may run on, as `nproc` counts them.
int cpus() {
  cpu_set_t set;
  return ::sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 1;
}

std::string slurm_conf(const fs::path& d, std::pair<int, int> ports) {
  std::ostringstream c;
  c << "# A one-node Slurm cluster on loopback for dmbd's tests (tests/apps/slurm_cluster.cpp)\n"
    << "ClusterName=dmbdtest\nSlurmctldHost=localhost(127.0.0.1)\n"
    << "SlurmctldPort=" << ports.first << "\nSlurmdPort=" << ports.second << "\n"
    << "SlurmUser=root\nSlurmdUser=root\n"
    << "AuthType=auth/munge\nAuthInfo=socket=" << (d / "munge" / "munge.socket").string() << "\nCredType=cred/munge\n"
    << "StateSaveLocation=" << (d / "state").string() << "\nSlurmdSpoolDir=" << (d / "spool").string() << "\n"
    << "SlurmctldPidFile=" << (d / "slurmctld.pid").string() << "\nSlurmdPidFile=" << (d / "slurmd.pid").string() << "\n"
    << "SlurmctldLogFile=" << (d / "log" / "slurmctld.log").string() << "\nSlurmdLogFile=" << (d / "log" / "slurmd.log").string() << "\n"
    // No cgroups: a job's processes are its process group (linuxproc's walk of /proc missed
    // a child forked while a cancelled job was being killed, which then outlived it).
    << "ProctrackType=proctrack/pgid\nTaskPlugin=task/none\n"
    << "JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\n"
    << "SelectType=select/cons_tres\nSelectTypeParameters=CR_CPU\nSchedulerType=sched/builtin\n"
    // Schedule as soon as a task ends (the default waits 3 s between passes), and keep
    // sbatch --wait polling every 2 s (it multiplies its sleep by 4 while that stays under
    // half MinJobAge, up to 32 s).
    << "SchedulerParameters=batch_sched_delay=0\nMinJobAge=4\n"
    << "MailProg=/bin/true\nReturnToService=2\nSlurmdParameters=config_overrides\n"
    << "NodeName=localhost NodeAddr=127.0.0.1 CPUs=" << cpus() << " State=UNKNOWN\n"
    << "PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n";
  return c.str();
}

void sleep_ms(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }

// The last `n` characters of a file.
std::string tail(const fs::path& f, std::size_t n) {
  const std::string text = slurp(f);
  return text.size() <= n ? text : "..." + text.substr(text.size() - n);
}

// Stops a child: SIGTERM, then SIGKILL if it has not exited within 10 s.
void stop(pid_t pid) {
  ::kill(pid, SIGTERM);
  for (int k = 0; k < 200; ++k, sleep_ms(50))
    if (::waitpid(pid, nullptr, WNOHANG) == pid) return;
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
}

}  // namespace

std::string missing_programs() {
  std::string missing;
  for (const char* p : {"munged", "mungekey", "slurmctld", "slurmd", "sinfo", "sbatch", "squeue", "scancel"})
    if (std::system(("command -v " + std::string(p) + " >/dev/null 2>&1").c_str()) != 0) missing += (missing.empty() ? "" : " ") + std::string(p);
  return missing;
}

SlurmCluster::SlurmCluster(fs::path dir) : dir_(std::move(dir)) {
  for (const char* sub : {"munge", "state", "spool", "log"}) fs::create_directories(dir_ / sub);
  const auto ports = two_free_ports();
  if (ports.first == 0) {
    error_ = "no two free TCP ports from 20000 to 29999";
    return;
  }
  conf_ = slurm_conf(dir_, ports);
  std::ofstream(dir_ / "slurm.conf") << conf_;
  if (start_munge() && start_slurm() && wait_until_idle()) return;
  error_ += "\n" + logs();
}

// Jobs still running (a test that failed half way) are cancelled first: their slurmstepd
// would otherwise outlive slurmd, retrying to report to it.
SlurmCluster::~SlurmCluster() {
  if (pids_.size() == 3 && std::system((env() + "scancel --user=root >/dev/null 2>&1").c_str()) == 0)
    for (int k = 0; k < 50 && !queue_empty(); ++k) sleep_ms(200);
  for (auto p = pids_.rbegin(); p != pids_.rend(); ++p) stop(*p);
}

bool SlurmCluster::queue_empty() const {
  return std::system((env() + "squeue -h 2>/dev/null | grep -q .").c_str()) != 0;
}

std::string SlurmCluster::env() const { return "SLURM_CONF=" + quote((dir_ / "slurm.conf").string()) + " "; }

std::string SlurmCluster::logs() const {
  std::string text;
  for (const char* f : {"munged.out", "slurmctld.out", "slurmctld.log", "slurmd.out", "slurmd.log"})
    if (fs::exists(dir_ / "log" / f) && fs::file_size(dir_ / "log" / f) > 0) text += std::string("--- ") + f + ":\n" + tail(dir_ / "log" / f, 1500) + "\n";
  return text;
}

// A daemon as a child of this process, its output into log/LOG, SLURM_CONF set; it gets
// SIGTERM when this process ends, however it ends.
pid_t SlurmCluster::spawn(const std::vector<std::string>& argv, const std::string& log) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string out = (dir_ / "log" / log).string(), conf = (dir_ / "slurm.conf").string();
  const pid_t parent = ::getpid(), pid = ::fork();
  if (pid != 0) {
    if (pid > 0) pids_.push_back(pid);
    return pid;
  }
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) ::_exit(1);
  const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644), in = ::open("/dev/null", O_RDONLY);
  ::dup2(in, 0);
  ::dup2(fd, 1);
  ::dup2(fd, 2);
  ::setenv("SLURM_CONF", conf.c_str(), 1);
  ::execvp(args[0], args.data());
  ::_exit(127);
}

bool SlurmCluster::all_alive() {
  for (pid_t p : pids_) {
    int status = 0;
    if (::waitpid(p, &status, WNOHANG) == p) {
      error_ = "a daemon (pid " + std::to_string(p) + ") exited with status " + std::to_string(status);
      pids_.erase(std::find(pids_.begin(), pids_.end(), p));
      return false;
    }
  }
  return true;
}

// A key of its own, and munged on a socket in the folder (--force: munged refuses to start
// where a folder above its files is writable by others, as a TMPDIR may be; in the
// foreground it logs to stderr, log/munged.out).
bool SlurmCluster::start_munge() {
  const fs::path m = dir_ / "munge";
  const std::string key = (m / "munge.key").string();
  if (std::system(("mungekey -c -b 1024 -k " + quote(key) + " >>" + quote((dir_ / "log" / "munged.out").string()) + " 2>&1").c_str()) != 0) {
    error_ = "mungekey could not create " + key;
    return false;
  }
  spawn({"munged", "--foreground", "--force", "--key-file=" + key, "--socket=" + (m / "munge.socket").string(),
         "--pid-file=" + (m / "munged.pid").string(), "--log-file=" + (dir_ / "log" / "munged.log").string(),
         "--seed-file=" + (m / "munged.seed").string()},
        "munged.out");
  for (int k = 0; k < 200 && all_alive(); ++k, sleep_ms(50))
    if (fs::exists(m / "munge.socket")) return true;
  if (error_.empty()) error_ = "munged did not create its socket within 10 s";
  return false;
}

bool SlurmCluster::start_slurm() {
  const std::string conf = (dir_ / "slurm.conf").string();
  spawn({"slurmctld", "-D", "-f", conf}, "slurmctld.out");
  spawn({"slurmd", "-D", "-f", conf, "-N", "localhost"}, "slurmd.out");
  return all_alive();
}

// Until sinfo shows the node idle: slurmd has registered with slurmctld.
bool SlurmCluster::wait_until_idle() {
  const std::string cmd = env() + "sinfo -h -N -o %T 2>&1";
  std::string last;
  for (int k = 0; k < 150 && all_alive(); ++k, sleep_ms(200)) {
    FILE* p = ::popen(cmd.c_str(), "r");
    last.clear();
    for (char buf[256]; p && std::fgets(buf, sizeof buf, p);) last += buf;
    if (p) ::pclose(p);
    if (last == "idle\n") return true;
  }
  if (error_.empty()) error_ = "the node was not idle within 30 s; sinfo said: " + last;
  return false;
}

}  // namespace dmbd::slurm_testing
