// The pid block's fields (issue 28, row 13): states by structure in its linear model,
// output_limits / anti_windup / Kt read and checked, each mistake one located line.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::diagrams {
namespace {

std::string diagram(const std::string& fields) {
  return "name: p\n"
         "parameters: {Ki: 0, Kd: 0}\n"
         "inputs: {e: {}}\n"
         "outputs: {u: {}}\n"
         "blocks:\n"
         "  C: {type: pid, " + fields + "}\n"
         "connections: [e -> C, C -> u]\n";
}

const Block& pid(const std::shared_ptr<const Diagram>& d) { return d->blocks().front(); }

// An absent term or a literal 0 has no state; a parameter (at 0 here) keeps its state.
TEST(PidBlock, StatesByStructure) {
  const std::vector<std::pair<std::string, int>> cases{
      {"P: 1", 0},
      {"P: 1, I: 2", 1},
      {"P: 1, I: 0", 0},
      {"P: 1, I: 0.0, D: 0, tau: 0.01", 0},
      {"P: 1, I: 2, D: 0, tau: 0.01", 1},
      {"P: 1, I: 2, D: 0.5, tau: 0.01", 2},
      {"P: 1, I: Ki", 1},
      {"P: 1, D: Kd, tau: 0.01", 1},
      {"P: 1, I: Ki, D: Kd, tau: 0.01", 2},
  };
  for (const auto& [fields, n] : cases) {
    const auto d = Diagram::parse(diagram(fields), "p.yaml");
    EXPECT_EQ(pid(d).model.num_states(), n) << fields;
    ASSERT_TRUE(pid(d).pid.has_value());
    EXPECT_EQ(pid(d).pid->has_i, fields.find("I:") != std::string::npos && fields.find("I: 0") == std::string::npos) << fields;
  }
  // A pd's literal D: 0 is a static gain, as before; its D given by a parameter keeps the filter.
  const std::string pd_yaml = "name: p\nparameters: {Kd: 0}\ninputs: {e: {}}\noutputs: {u: {}}\nblocks:\n  C: {type: pd, P: 1, D: DD}\n"
                              "connections: [e -> C, C -> u]\n";
  auto with = [&](const std::string& d) { return std::string(pd_yaml).replace(pd_yaml.find("DD"), 2, d); };
  EXPECT_EQ(pid(Diagram::parse(with("0"), "p.yaml")).model.num_states(), 0);
  EXPECT_EQ(pid(Diagram::parse(with("Kd, tau: 0.01"), "p.yaml")).model.num_states(), 1);
}

TEST(PidBlock, LimitsAndAntiWindupAreRead) {
  const auto d = Diagram::parse(diagram("P: 2, I: 30, output_limits: [-1.5, 2*1.5], anti_windup: back_calculation, Kt: 40"), "p.yaml");
  const PidLaw& law = *pid(d).pid;
  EXPECT_EQ(law.p, 2.0);
  EXPECT_EQ(law.i, 30.0);
  ASSERT_TRUE(law.output_limits.has_value());
  EXPECT_EQ(law.output_limits->first, -1.5);
  EXPECT_EQ(law.output_limits->second, 3.0);
  EXPECT_EQ(law.anti_windup, AntiWindup::BackCalculation);
  EXPECT_EQ(law.kt, 40.0);
  EXPECT_STREQ(to_string(law.anti_windup), "back_calculation");
  // The linear model is the unsaturated law: P + I/s, DC gain infinite, one state.
  EXPECT_EQ(pid(d).model.num_states(), 1);
}

// Each mistake: one line at the field that is wrong (line 6 holds the block).
TEST(PidBlock, EachMistakeIsOneLocatedLine) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"P: 1, I: 2, output_limits: [1, -1]", "'output_limits' must have lo < hi"},
      {"P: 1, I: 2, output_limits: 5", "'output_limits' must be [lo, hi]"},
      {"P: 1, I: 2, output_limits: [-1, 1], anti_windup: banana", "'anti_windup' must be none, clamp or back_calculation"},
      {"P: 1, I: 2, anti_windup: clamp", "'anti_windup' needs 'output_limits'"},
      {"P: 1, output_limits: [-1, 1], anti_windup: clamp", "'anti_windup' needs an integral term 'I'"},
      {"P: 1, I: 2, output_limits: [-1, 1], anti_windup: back_calculation", "needs its gain 'Kt'"},
      {"P: 1, I: 2, output_limits: [-1, 1], anti_windup: back_calculation, Kt: -3", "'Kt' must be > 0"},
      {"P: 1, I: 2, output_limits: [-1, 1], Kt: 3", "'Kt' is the gain of anti_windup: back_calculation"},
      {"P: 1, D: Kd", "a derivative needs a filter time constant 'tau' > 0"},
  };
  for (const auto& [fields, message] : cases) {
    SCOPED_TRACE(fields);
    try {
      (void)Diagram::parse(diagram(fields), "p.yaml");
      ADD_FAILURE() << "accepted";
    } catch (const DiagramError& e) {
      ASSERT_EQ(e.diagnostics().size(), 1u) << e.what();
      EXPECT_EQ(e.diagnostics()[0].where.str().rfind("p.yaml:6:", 0), 0u) << e.what();
      EXPECT_NE(e.diagnostics()[0].message.find(message), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace dmbd::diagrams
