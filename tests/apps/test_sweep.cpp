// dmbd simulate --jobs and dmbd sweep plan/collect (docs/sweeps.md): a 16-run sweep
// (tests/apps/data/sweep16.yaml, a 4 x 4 matrix of 0.3 s runs) run in one process, in
// two worker processes, and planned, run through GNU parallel and collected, must give
// the same files: log.csv byte for byte, metrics.json equal but for the wall-time fields,
// the plots byte for byte. And the errors: a failing worker, a job that did not finish,
// an unknown variant, a plan into a folder in use.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.hpp"
#include "sweep_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::quote;
using dmbd::cli_testing::run_dmbd;
using dmbd::cli_testing::slurp;
using dmbd::sweep_testing::expect_same_run;
using dmbd::sweep_testing::kScenario;
using dmbd::sweep_testing::lines_of;
using dmbd::sweep_testing::Scratch;
using dmbd::sweep_testing::shell;

bool have_parallel() { return std::system("parallel --version >/dev/null 2>&1") == 0; }

TEST(SimulateJobs, TwoWorkerProcessesWriteWhatOneProcessWrites) {
  Scratch t("jobs");
  const auto one = run_dmbd({"simulate", kScenario, "--out", (t.dir() / "one").string(), "--no-frames"}, t.dir());
  ASSERT_EQ(one.code, 0) << one.err;
  const auto two = run_dmbd({"simulate", kScenario, "--out", (t.dir() / "two").string(), "--no-frames", "--jobs", "2"}, t.dir());
  ASSERT_EQ(two.code, 0) << two.err;
  expect_same_run(t.dir() / "one", t.dir() / "two");
  EXPECT_EQ(slurp(t.dir() / "two" / "metrics.json").find(kScenario) != std::string::npos, true);
  EXPECT_EQ(lines_of(one.out).size(), lines_of(two.out).size());  // a line per run and per file, as one process prints
  EXPECT_EQ(lines_of(two.out).front().rfind("with_dob/locked: 0.3 s simulated in ", 0), 0u) << two.out;
}

TEST(SimulateJobs, AFailingWorkerGivesTheErrorOfOneProcessAndWritesNothing) {
  Scratch t("jobs_fail");
  // The last controller value binds a signal that does not exist: runs 13 to 16 fail.
  std::string text = slurp(kScenario);
  const auto last = text.rfind("F_m: l_knee.force}");
  ASSERT_NE(last, std::string::npos);
  text.replace(last, 18, "F_m: l_knee.forc}");
  for (std::string::size_type p; (p = text.find("../../../examples")) != std::string::npos;)
    text.replace(p, 17, std::string(DMBD_SOURCE_DIR) + "/examples");
  const fs::path bad = t.dir() / "bad.yaml";
  std::ofstream(bad) << text;
  const auto one = run_dmbd({"simulate", bad.string(), "--out", (t.dir() / "one").string(), "--no-frames"}, t.dir());
  const auto two = run_dmbd({"simulate", bad.string(), "--out", (t.dir() / "two").string(), "--no-frames", "--jobs", "2"}, t.dir());
  EXPECT_EQ(one.code, 2);
  EXPECT_EQ(two.code, 2);
  EXPECT_NE(one.err.find("variant 'without_dob_noisy/locked'"), std::string::npos) << one.err;
  EXPECT_NE(one.err.find("'l_knee.forc', which no sensor"), std::string::npos) << one.err;
  EXPECT_EQ(two.err, one.err);
  EXPECT_EQ(lines_of(two.err).size(), 1u) << two.err;
  EXPECT_FALSE(fs::exists(t.dir() / "two"));
  EXPECT_FALSE(fs::exists(t.dir() / "one"));
}

TEST(Sweep, PlannedRunThroughGnuParallelAndCollectedEqualsOneProcess) {
  if (!have_parallel()) GTEST_SKIP() << "GNU parallel is not installed (scripts/setup installs the Debian package 'parallel')";
  Scratch t("parallel");
  const fs::path plan = t.dir() / "plan";
  const auto p = run_dmbd({"sweep", "plan", kScenario, "--out", plan.string()}, t.dir());
  ASSERT_EQ(p.code, 0) << p.err;
  // Self-contained: the scenario and its two diagrams copied with their relative places.
  const fs::path copy = plan / "scenario" / "tests" / "apps" / "data" / "sweep16.yaml";
  EXPECT_TRUE(fs::exists(copy));
  EXPECT_TRUE(fs::exists(plan / "scenario" / "examples" / "diagrams" / "dob_controller.yaml"));
  EXPECT_TRUE(fs::exists(plan / "scenario" / "examples" / "diagrams" / "force_pd_controller.yaml"));
  const auto jobs = lines_of(slurp(plan / "jobs.txt"));
  ASSERT_EQ(jobs.size(), 16u);
  EXPECT_NE(jobs[15].find("--variant 'without_dob_noisy/2953kg' --out parts/16"), std::string::npos) << jobs[15];
  EXPECT_NE(slurp(plan / "slurm.sbatch").find("#SBATCH --array=1-16\n"), std::string::npos);
  ASSERT_EQ(shell("parallel --jobs 2 --halt now,fail=1 :::: jobs.txt", plan), 0);
  const auto c = run_dmbd({"sweep", "collect", plan.string(), "--no-frames"}, t.dir());
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_NE(c.out.find("wrote " + (plan / "run").string() + "/metrics.json"), std::string::npos) << c.out;
  const auto one = run_dmbd({"simulate", kScenario, "--out", (t.dir() / "one").string(), "--no-frames"}, t.dir());
  ASSERT_EQ(one.code, 0) << one.err;
  expect_same_run(t.dir() / "one", plan / "run");
  const auto m = nlohmann::json::parse(slurp(plan / "run" / "metrics.json"));
  EXPECT_EQ(m["scenario_file"], fs::absolute(copy).lexically_normal().string());
}

TEST(Sweep, TheSlurmScriptRunsTheLineOfItsArrayTask) {
  Scratch t("slurm");
  const fs::path plan = t.dir() / "plan";
  ASSERT_EQ(run_dmbd({"sweep", "plan", kScenario, "--out", plan.string()}, t.dir()).code, 0);
  // What Slurm does for task 6 of the array, by hand (a real Slurm: test_sweep_slurm.cpp):
  // the task starts in the submission folder (or sbatch --chdir's) with its index set.
  ASSERT_EQ(shell("SLURM_ARRAY_TASK_ID=6 bash slurm.sbatch", plan), 0);
  const auto part = nlohmann::json::parse(slurp(plan / "parts" / "6" / "part.json"));
  EXPECT_EQ(part["variant"], "without_dob/30000kg");
  EXPECT_FALSE(fs::exists(plan / "parts" / "5"));
  // Started elsewhere, it says where it expected to be, and runs nothing.
  const int code = std::system(("cd " + quote(t.dir().string()) + " && SLURM_ARRAY_TASK_ID=5 bash plan/slurm.sbatch 2>" +
                                quote((t.dir() / "err").string()))
                                   .c_str());
  EXPECT_EQ(WEXITSTATUS(code), 2);
  EXPECT_EQ(slurp(t.dir() / "err"), "slurm.sbatch: no jobs.txt in " + t.dir().string() +
                                        " (submit from the plan's folder, or with --chdir=PLAN)\n");
  EXPECT_FALSE(fs::exists(plan / "parts" / "5"));
}

// sbatch refuses an #SBATCH line with a blank in its value ("Invalid directive found in
// batch script", Slurm 22.05), and a line break in the name would end the comment line:
// the job name keeps letters, digits, '.', '_' and '-' of the scenario's name.
TEST(Sweep, TheSlurmJobNameIsOneWordWhateverTheScenarioIsCalled) {
  Scratch t("slurm_name");
  std::string text = slurp(kScenario);
  text.replace(text.find("name: sweep16"), 13, "name: \"knee force (2 loads)\\nrm -rf x\"");
  for (std::string::size_type p; (p = text.find("../../../examples")) != std::string::npos;)
    text.replace(p, 17, std::string(DMBD_SOURCE_DIR) + "/examples");
  std::ofstream(t.dir() / "named.yaml") << text;
  const auto p = run_dmbd({"sweep", "plan", (t.dir() / "named.yaml").string(), "--out", (t.dir() / "plan").string()}, t.dir());
  ASSERT_EQ(p.code, 0) << p.err;
  const auto lines = lines_of(slurp(t.dir() / "plan" / "slurm.sbatch"));
  EXPECT_EQ(lines[1], "# A Slurm job array: task K runs line K of jobs.txt (one variant of knee_force__2_loads__rm_-rf_x).");
  EXPECT_EQ(lines[4], "#SBATCH --job-name=dmbd-knee_force__2_loads__rm_-rf_x");
  EXPECT_EQ(lines.size(), 16u);
}

TEST(Sweep, CollectNamesTheJobsThatDidNotFinishAndWritesNothing) {
  Scratch t("missing");
  const fs::path plan = t.dir() / "plan";
  ASSERT_EQ(run_dmbd({"sweep", "plan", kScenario, "--out", plan.string(), "--duration", "0.05"}, t.dir()).code, 0);
  const auto jobs = lines_of(slurp(plan / "jobs.txt"));
  for (std::size_t k = 0; k < jobs.size(); ++k)
    if (k != 2 && k != 10) {
      ASSERT_EQ(shell(jobs[k], plan), 0) << jobs[k];
    }
  const auto c = run_dmbd({"sweep", "collect", plan.string(), "--out", (t.dir() / "out").string()}, t.dir());
  EXPECT_EQ(c.code, 2);
  EXPECT_EQ(c.err, "dmbd: error: " + plan.string() +
                       ": 2 of 16 jobs did not finish: job 3 'with_dob/10000kg' (parts/3/part.json), job 11 "
                       "'with_dob_noisy/10000kg' (parts/11/part.json); run those lines of jobs.txt again\n");
  EXPECT_FALSE(fs::exists(t.dir() / "out"));
  // Once they ran, the collection succeeds (at --duration 0.05 s, as planned).
  ASSERT_EQ(shell(jobs[2], plan), 0);
  ASSERT_EQ(shell(jobs[10], plan), 0);
  const auto ok = run_dmbd({"sweep", "collect", plan.string(), "--out", (t.dir() / "out").string(), "--no-frames"}, t.dir());
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(ok.out.find("with_dob/10000kg: 0.05 s simulated in"), std::string::npos) << ok.out;
  // A part whose log was cut short is named, and nothing is written.
  fs::resize_file(plan / "parts" / "1" / "log.bin", 1000);
  const auto cut = run_dmbd({"sweep", "collect", plan.string(), "--out", (t.dir() / "out2").string()}, t.dir());
  EXPECT_EQ(cut.code, 2);
  EXPECT_EQ(cut.err.rfind("dmbd: error: " + (plan / "parts" / "1" / "log.bin").string() + ": 1000 bytes, expected ", 0), 0u) << cut.err;
  EXPECT_FALSE(fs::exists(t.dir() / "out2"));
}

TEST(Sweep, BadInputIsOneLineAndExitTwo) {
  Scratch t("bad");
  const auto v = run_dmbd({"simulate", kScenario, "--variant", "with_dob/1kg", "--out", (t.dir() / "p").string()}, t.dir());
  EXPECT_EQ(v.code, 2);
  EXPECT_EQ(v.err.rfind("dmbd: error: " + kScenario + ": no variant 'with_dob/1kg' (expected one of: with_dob/locked, ", 0), 0u) << v.err;
  EXPECT_FALSE(fs::exists(t.dir() / "p"));
  fs::create_directories(t.dir() / "used");
  std::ofstream(t.dir() / "used" / "x") << "x";
  const auto p = run_dmbd({"sweep", "plan", kScenario, "--out", (t.dir() / "used").string()}, t.dir());
  EXPECT_EQ(p.code, 2);
  EXPECT_EQ(p.err, "dmbd: error: --out '" + (t.dir() / "used").string() + "': the folder is not empty (a plan is written into a new folder)\n");
  const auto c = run_dmbd({"sweep", "collect", (t.dir() / "used").string()}, t.dir());
  EXPECT_EQ(c.code, 2);
  EXPECT_EQ(c.err.rfind("dmbd: error: " + (t.dir() / "used" / "plan.json").string() + ": cannot read the plan: No such file", 0), 0u) << c.err;
  const auto j = run_dmbd({"simulate", kScenario, "--out", (t.dir() / "j").string(), "--jobs", "0"}, t.dir());
  EXPECT_EQ(j.code, 2);
  EXPECT_EQ(j.err, "dmbd: error: --jobs 0: expected a number of processes from 1 to 1024\n");
}

}  // namespace
