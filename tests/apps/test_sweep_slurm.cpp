// A sweep plan run by a real Slurm (docs/sweeps.md, "On a real Slurm"): a one-node
// cluster on loopback started in a scratch folder (slurm_cluster.hpp), the 16 jobs of
// tests/apps/data/sweep16.yaml submitted as the plan's job array with
// `sbatch --wait slurm.sbatch` from the plan's folder, collected, and compared with the
// single process as the GNU parallel test does (test_sweep.cpp). Without Slurm and MUNGE
// installed, or not as root, the test fails saying so: CI installs them (scripts/setup)
// and runs as root, and a skip there would hide that the route stopped being tried.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>

#include "cli_support.hpp"
#include "slurm_cluster.hpp"
#include "sweep_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::quote;
using dmbd::cli_testing::run_dmbd;
using dmbd::cli_testing::slurp;
using dmbd::slurm_testing::SlurmCluster;
using dmbd::sweep_testing::expect_same_run;
using dmbd::sweep_testing::kScenario;
using dmbd::sweep_testing::Scratch;

struct Output {
  int code = -1;
  std::string text;  // stdout and stderr
};

// A shell command run in `cwd`, its output captured.
Output run_in(const std::string& command, const fs::path& cwd) {
  Output o;
  FILE* p = ::popen(("cd " + quote(cwd.string()) + " && " + command + " 2>&1").c_str(), "r");
  if (!p) return o;
  for (char buf[512]; std::fgets(buf, sizeof buf, p);) o.text += buf;
  const int status = ::pclose(p);
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

TEST(SweepSlurm, PlannedJobArrayRunBySlurmAndCollectedEqualsOneProcess) {
  ASSERT_EQ(::geteuid(), 0u) << "this test starts slurmd and munged, and must run as root (CI does)";
  const std::string missing = dmbd::slurm_testing::missing_programs();
  ASSERT_EQ(missing, "") << "Slurm and MUNGE are needed: Debian's slurm-wlm and munge (scripts/setup installs them); not found: " << missing;
  Scratch t("slurm_cluster");
  const SlurmCluster cluster(t.dir() / "cluster");  // stopped before the folder is removed
  ASSERT_EQ(cluster.error(), "") << "the one-node Slurm cluster did not come up, with this slurm.conf:\n" << cluster.conf_text();
  const fs::path plan = t.dir() / "the plan";  // a blank in every path the jobs see
  const auto p = run_dmbd({"sweep", "plan", kScenario, "--out", plan.string()}, t.dir());
  ASSERT_EQ(p.code, 0) << p.err;

  const Output sbatch = run_in(cluster.env() + "timeout 120 sbatch --wait slurm.sbatch", plan);
  ASSERT_EQ(sbatch.code, 0) << sbatch.text << "\n" << cluster.logs();
  std::smatch id;
  ASSERT_TRUE(std::regex_search(sbatch.text, id, std::regex("Submitted batch job ([0-9]+)"))) << sbatch.text;
  // Each array task ran one line of jobs.txt, and said so in its own output file.
  for (int k = 1; k <= 16; ++k) {
    const fs::path out = plan / ("slurm-" + id[1].str() + "_" + std::to_string(k) + ".out");
    EXPECT_NE(slurp(out).find("wrote parts/" + std::to_string(k) + "/part.json\n"), std::string::npos) << out << ": " << slurp(out);
  }

  const auto c = run_dmbd({"sweep", "collect", plan.string(), "--no-frames"}, t.dir());
  ASSERT_EQ(c.code, 0) << c.err;
  const auto one = run_dmbd({"simulate", kScenario, "--out", (t.dir() / "one").string(), "--no-frames"}, t.dir());
  ASSERT_EQ(one.code, 0) << one.err;
  expect_same_run(t.dir() / "one", plan / "run");
  const auto m = nlohmann::json::parse(slurp(plan / "run" / "metrics.json"));
  EXPECT_EQ(m["scenario_file"], (plan / "scenario" / "tests" / "apps" / "data" / "sweep16.yaml").string());
}

}  // namespace
