#pragma once
// A one-node Slurm cluster on loopback, all of it in one folder, for the test that runs a
// sweep plan's job array on a real Slurm (tests/apps/test_sweep_slurm.cpp, docs/sweeps.md
// "On a real Slurm"): its own MUNGE key and munged (socket, pid, log and seed files in the
// folder), a generated slurm.conf (two free ports, one node `localhost` on 127.0.0.1 with
// this process's CPUs, state, spool and logs in the folder, SlurmUser root), slurmctld and
// slurmd in the foreground as children of the test. The daemons listen on every address,
// Slurm's default (CommunicationParameters=NoInAddrAny would bind to what the host name
// resolves to, which need not be loopback), and accept only credentials of the folder's
// key. Needs root and Debian's slurm-wlm and munge. The destructor stops the daemons; if
// the test process is killed they get SIGTERM (PR_SET_PDEATHSIG) and the running jobs'
// slurmstepd end with their job (the scratch folder then stays).
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace dmbd::slurm_testing {

// The programs the cluster needs that are not on the PATH, space separated ("" when all
// are there): munged, mungekey, slurmctld, slurmd, sinfo, sbatch, squeue, scancel.
std::string missing_programs();

class SlurmCluster {
 public:
  // Creates `dir` and starts the cluster in it; waits (at most 30 s) until sinfo shows
  // its node idle. error() says why when it did not come up.
  explicit SlurmCluster(std::filesystem::path dir);
  ~SlurmCluster();  // cancels jobs left running, stops slurmd, slurmctld and munged, waiting for each
  SlurmCluster(const SlurmCluster&) = delete;
  SlurmCluster& operator=(const SlurmCluster&) = delete;

  // "" when the node is idle; else what failed, with the tails of the daemons' logs.
  const std::string& error() const { return error_; }
  // The prefix of a shell command that talks to this cluster: "SLURM_CONF='DIR/slurm.conf' ".
  std::string env() const;
  // The tails of the daemons' logs (for a failure message).
  std::string logs() const;
  const std::string& conf_text() const { return conf_; }

 private:
  bool start_munge();
  bool start_slurm();
  bool wait_until_idle();
  bool all_alive();
  bool queue_empty() const;
  pid_t spawn(const std::vector<std::string>& argv, const std::string& log);

  std::filesystem::path dir_;
  std::string conf_, error_;
  std::vector<pid_t> pids_;  // in the order started
};

}  // namespace dmbd::slurm_testing
