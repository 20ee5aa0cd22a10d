// DiagramSource (issue 13, build 5): the file and its subsystems' files are read and
// parsed once; evaluating at other parameter values, tuning and sweeping then run from
// memory. Proven by deleting the files after loading.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "dmbd/diagrams/diagram_source.hpp"
#include "dmbd/diagrams/linearize.hpp"
#include "dmbd/diagrams/tune.hpp"

namespace {

using namespace dmbd::diagrams;  // NOLINT
namespace fs = std::filesystem;

const std::string kExamples = DMBD_EXAMPLES "/diagrams/";

class Source : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_test_source_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A copy of an example diagram and its subsystem in the scratch folder.
  std::string copy_example(const std::string& name) {
    for (const std::string& f : {name, std::string("rfsea_plant.yaml")}) fs::copy_file(kExamples + f, dir_ / f);
    return (dir_ / name).string();
  }
  fs::path dir_;
};

TEST_F(Source, EvaluatesAtOtherValuesWithoutItsFiles) {
  const auto source = DiagramSource::load(copy_example("position_encoder.yaml"));
  fs::remove_all(dir_);  // the diagram and its subsystem's file are gone
  const auto shipped = source->evaluate();
  const auto doubled = source->evaluate({{"P_q", 2 * 42512.69}});
  EXPECT_EQ(shipped->parameters().at("P_q"), 42512.69);
  EXPECT_EQ(doubled->parameters().at("P_q"), 2 * 42512.69);
  // The subsystem is evaluated too, and the loops differ.
  EXPECT_NE(linearize(*shipped, "q_d", "q").poles(), linearize(*doubled, "q_d", "q").poles());
  EXPECT_EQ(shipped->blocks().size(), doubled->blocks().size());
  // Overrides are still checked against the parameters.
  EXPECT_THROW(source->evaluate({{"P_qq", 1.0}}), DiagramError);
}

TEST_F(Source, TuningRunsFromMemory) {
  const auto source = DiagramSource::load(copy_example("position_encoder.yaml"));
  fs::remove_all(dir_);
  // The shipped gains of controller 1 (test_paper.cpp), from the deleted copy.
  const PdTuningResult r = tune_pd({source, "q_d", "q", "P_q", "D_q", {}, 6.020599913279624, 0.1});
  EXPECT_GT(r.evaluations, 30);
  EXPECT_NEAR(r.d_critical, 7114.90, 1e-5 * 7114.90);
  EXPECT_NEAR(r.p, 42512.69, 1e-3 * 42512.69);
}

TEST_F(Source, ProblemsInASubsystemFileAreReportedAtEvaluationAtTheBlock) {
  std::ofstream(dir_ / "top.yaml") << "name: top\ninputs: {u: {}}\noutputs: {y: {}}\nblocks:\n"
                                      "  p: {type: subsystem, file: gone.yaml}\nconnections: [u -> p, p -> y]\n";
  const auto source = DiagramSource::load((dir_ / "top.yaml").string());
  try {
    (void)source->evaluate();
    ADD_FAILURE() << "no error";
  } catch (const DiagramError& e) {
    ASSERT_EQ(e.diagnostics().size(), 1u) << e.what();
    EXPECT_EQ(e.diagnostics()[0].where.line, 5);
    EXPECT_NE(e.diagnostics()[0].message.find("cannot read diagram file"), std::string::npos);
    EXPECT_NE(e.diagnostics()[0].message.find("No such file or directory"), std::string::npos) << e.what();
  }
}

}  // namespace
