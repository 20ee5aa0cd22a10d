// State-space groups and per-block discretisation: a plant written as integrators and
// gains in a loop lowers without an algebraic-loop error and equals the Tustin
// discretisation of the whole linearised plant; a loop through a saturation with
// direct feedthrough everywhere is an InputError naming its blocks; a block's own
// `discretization:` and LowerOptions::block_methods / --block-method choose its
// realisation.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/linearize.hpp"
#include "test_support.hpp"

namespace dmbd::codegen {
namespace {

using namespace test;
using diagrams::Diagram;

LowerOptions at(double rate_hz, C2dMethod m = C2dMethod::Tustin) {
  LowerOptions o;
  o.rate_hz = rate_hz;
  o.method = m;
  return o;
}

// Simulate a discrete state-space model in long double from zero state.
std::vector<long double> simulate(const blocks::StateSpace& g, const std::vector<double>& u) {
  const LMatrix A = g.a().cast<long double>(), B = g.b().cast<long double>(), C = g.c().cast<long double>(),
                D = g.d().cast<long double>();
  LVector x = LVector::Zero(g.num_states());
  std::vector<long double> y;
  for (double v : u) {
    y.push_back((C * x)(0) + D(0, 0) * v);
    x = A * x + B * static_cast<long double>(v);
  }
  return y;
}

// The knee RFSEA plant of examples/diagrams/rfsea_plant.yaml (4 integrators in loops
// through gains and sums) at 2 kHz: one group, 4 states; every output equals the
// superposition over both inputs of c2d(linearize(d, input, output), Tustin),
// simulated in long double, to 1e-9 relative to the output's largest value.
TEST(StateSpaceGroup, RfseaPlantEqualsTustinOfTheLinearisedPlant) {
  const auto d = Diagram::load(kExamples + "/diagrams/rfsea_plant.yaml");
  const double rate = 2000.0, ts = 1.0 / rate;
  LoopProgram p;
  ASSERT_NO_THROW(p = lower(*d, at(rate)));
  EXPECT_EQ(p.states.size(), 4u);
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_NE(p.warnings[0].find("group"), std::string::npos) << p.warnings[0];
  const int n = 2000;
  std::vector<double> i_A(n), F_ext(n);
  for (int k = 0; k < n; ++k) {
    i_A[static_cast<size_t>(k)] = k >= 5 ? 1.0 + 0.5 * std::sin(2 * M_PI * 40.0 * k * ts) : 0.0;  // A
    F_ext[static_cast<size_t>(k)] = k >= 700 ? -300.0 * std::cos(2 * M_PI * 90.0 * k * ts) : 0.0;  // N
  }
  Sequence in;
  for (int k = 0; k < n; ++k) in.push_back({i_A[static_cast<size_t>(k)], F_ext[static_cast<size_t>(k)]});
  const Sequence got = interpret<double>(p, in);
  for (size_t j = 0; j < d->outputs().size(); ++j) {
    const std::string out = d->outputs()[j].name;
    SCOPED_TRACE(out);
    const auto y1 = simulate(blocks::c2d(diagrams::linearize(*d, "i", out), ts, C2dMethod::Tustin), i_A);
    const auto y2 = simulate(blocks::c2d(diagrams::linearize(*d, "F_ext", out), ts, C2dMethod::Tustin), F_ext);
    std::vector<long double> want(n);
    std::vector<double> g(n);
    for (int k = 0; k < n; ++k) {
      want[static_cast<size_t>(k)] = y1[static_cast<size_t>(k)] + y2[static_cast<size_t>(k)];
      g[static_cast<size_t>(k)] = got[static_cast<size_t>(k)][j];
    }
    EXPECT_TRUE(sequences_near(g, want, 1e-9));
  }
}

// The same on a hand-derived plant: m x'' = F - c x' - k x from integrators and gains;
// Tustin of 1/(m s^2 + c s + k) and s/(m s^2 + c s + k) (c2 = 2/T):
//   d0 x[n] + d1 x[n-1] + d2 x[n-2] = F[n] + 2 F[n-1] + F[n-2]
//   d0 v[n] + d1 v[n-1] + d2 v[n-2] = c2 (F[n] - F[n-2])
//   d0 = m c2^2 + c c2 + k, d1 = 2 (k - m c2^2), d2 = m c2^2 - c c2 + k.
TEST(StateSpaceGroup, IntegratorLoopEqualsHandDerivedTustin) {
  const auto d = Diagram::load(kData + "/msd_integrators.yaml");
  const double rate = 1000.0, T = 1.0 / rate;
  const LoopProgram p = lower(*d, at(rate));
  EXPECT_EQ(p.states.size(), 2u);
  const long double m = 2, c = 5, k = 400, c2 = 2.0L / T;
  const long double d0 = m * c2 * c2 + c * c2 + k, d1 = 2 * (k - m * c2 * c2), d2 = m * c2 * c2 - c * c2 + k;
  const int n = 1500;
  std::vector<long double> x(n), v(n);
  std::vector<double> F(n);
  auto at_ = [](const auto& s, int i) { return i >= 0 ? static_cast<long double>(s[static_cast<size_t>(i)]) : 0.0L; };
  Sequence in;
  for (int i = 0; i < n; ++i) {
    F[static_cast<size_t>(i)] = i >= 3 ? 10.0 * std::sin(2 * M_PI * 2.0 * i * T) + 4.0 : 0.0;
    in.push_back({F[static_cast<size_t>(i)]});
    x[static_cast<size_t>(i)] = (at_(F, i) + 2 * at_(F, i - 1) + at_(F, i - 2) - d1 * at_(x, i - 1) - d2 * at_(x, i - 2)) / d0;
    v[static_cast<size_t>(i)] = (c2 * (at_(F, i) - at_(F, i - 2)) - d1 * at_(v, i - 1) - d2 * at_(v, i - 2)) / d0;
  }
  const Sequence got = interpret<double>(p, in);
  std::vector<double> gx, gv;
  for (const auto& r : got) gx.push_back(r[0]), gv.push_back(r[1]);
  EXPECT_TRUE(sequences_near(gx, x, 1e-9));
  EXPECT_TRUE(sequences_near(gv, v, 1e-9));
}

// Under ZOH the integrators are strictly proper: the loop is not algebraic, no group
// is formed, and the program equals the blocks discretised one by one by ZOH and
// interconnected (the long-double reference of test_support.hpp), to 1e-9 relative.
TEST(StateSpaceGroup, NoGroupWhenTheLoopIsNotAlgebraic) {
  const auto d = Diagram::load(kData + "/msd_integrators.yaml");
  const LoopProgram p = lower(*d, at(1000.0, C2dMethod::Zoh));
  EXPECT_TRUE(p.warnings.empty()) << p.warnings.front();
  for (const auto& b : p.blocks) EXPECT_EQ(b.realisation.find("group"), std::string::npos) << b.path << ": " << b.realisation;
  DiscreteSimulation ref(*d, 1000.0, C2dMethod::Zoh);
  Sequence in;
  std::vector<long double> want;
  for (int i = 0; i < 1000; ++i) {
    in.push_back({i >= 3 ? 10.0 : 0.0});
    want.push_back(ref.step(in.back())[0]);
  }
  std::vector<double> got;
  for (const auto& r : interpret<double>(p, in)) got.push_back(r[0]);
  EXPECT_TRUE(sequences_near(got, want, 1e-9));
}

// A loop through a saturation in which every block has direct feedthrough once
// discretised (sum, saturation, Tustin integrator): InputError naming every block of
// the loop.
// Regression (fixed): the message lists the loop's blocks only up to the saturation in
// block order ("through e, lim...: the saturation block 'lim' ..."): 'integ' is
// missing.
TEST(StateSpaceGroup, SaturationInAlgebraicLoopNamesTheBlocks) {
  const auto d = Diagram::load(kData + "/sat_loop.yaml");
  try {
    lower(*d, at(1000.0));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("algebraic loop"), std::string::npos) << msg;
    for (const char* block : {"'lim'", "e", "integ"}) EXPECT_NE(msg.find(block), std::string::npos) << "no " << block << " in: " << msg;
  }
}

// The same when the saturation is declared first.
// Regression (fixed): the message then names the saturation alone ("through limiter...").
TEST(StateSpaceGroup, SaturationDeclaredFirstStillNamesEveryBlockOfTheLoop) {
  const auto d = parse(R"(
name: sat_first
inputs: {r: {}}
outputs: {y: {}}
blocks:
  limiter:    {type: saturation, lower: -1, upper: 1}
  error_sum:  {type: sum, signs: "+-"}
  integrator_block: {type: integrator, k: 50}
connections:
  - r -> error_sum.in1
  - error_sum -> limiter
  - limiter -> integrator_block
  - integrator_block -> [error_sum.in2, y]
)");
  try {
    lower(*d, at(1000.0));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const char* block : {"limiter", "error_sum", "integrator_block"})
      EXPECT_NE(msg.find(block), std::string::npos) << "no " << block << " in: " << msg;
  }
}

// The same loop with ZOH (integrator strictly proper) lowers, and the saturation clamps.
TEST(StateSpaceGroup, SaturationLoopUnderZohLowersAndClamps) {
  const auto d = Diagram::load(kData + "/sat_loop.yaml");
  const LoopProgram p = lower(*d, at(1000.0, C2dMethod::Zoh));
  // y[n+1] = y[n] + 50 T clamp(r - y[n], -1, 1): from 0 towards r = 10 at 0.05 per sample.
  Sequence in(100, std::vector<double>{10.0});
  const Sequence y = interpret<double>(p, in);
  EXPECT_EQ(y[0][0], 0.0);
  for (int i = 1; i < 100; ++i) EXPECT_NEAR(y[static_cast<size_t>(i)][0] - y[static_cast<size_t>(i - 1)][0], 0.05, 1e-12) << i;
}

// A block's `discretization: zoh` realises it by ZOH under a Tustin default; the
// option block_methods overrides both the field and the default, per block path.
TEST(BlockMethod, FieldAndOverrideChooseTheRealisation) {
  const auto d = Diagram::load(kData + "/methods.yaml");
  const double rate = 1000.0, ts = 1e-3;
  const TransferFunction g = TransferFunction::parse("wc^2/(s^2 + sqrt(2)*wc*s + wc^2)", {{"wc", 2 * M_PI * 60.0}});
  const auto u = chirp(1500, rate, 1.0, 400.0);
  Sequence in;
  for (double v : u) in.push_back({v});
  auto outputs = [&](const LoopProgram& p) {
    std::vector<double> a, b;
    for (const auto& r : interpret<double>(p, in)) a.push_back(r[0]), b.push_back(r[1]);
    return std::make_pair(a, b);
  };
  auto realisation = [](const LoopProgram& p, const std::string& path) {
    for (const auto& b : p.blocks)
      if (b.path == path) return b.realisation;
    return std::string("(no block " + path + ")");
  };
  {
    const LoopProgram p = lower(*d, at(rate));
    EXPECT_NE(realisation(p, "A").find("zoh"), std::string::npos) << realisation(p, "A");
    EXPECT_NE(realisation(p, "B").find("tustin"), std::string::npos) << realisation(p, "B");
    const auto [a, b] = outputs(p);
    EXPECT_TRUE(sequences_near(a, direct_form_1(blocks::c2d(g, ts, C2dMethod::Zoh), u), 1e-9, 1.0));
    EXPECT_TRUE(sequences_near(b, direct_form_1(blocks::c2d(g, ts, C2dMethod::Tustin), u), 1e-9, 1.0));
    EXPECT_EQ(a[0], 0.0);  // ZOH: no feedthrough
  }
  {
    LowerOptions o = at(rate);
    o.block_methods = {{"A", C2dMethod::Tustin}, {"B", C2dMethod::BackwardEuler}};
    const LoopProgram p = lower(*d, o);
    EXPECT_NE(realisation(p, "A").find("tustin"), std::string::npos) << realisation(p, "A");
    EXPECT_NE(realisation(p, "B").find("backward-euler"), std::string::npos) << realisation(p, "B");
    const auto [a, b] = outputs(p);
    EXPECT_TRUE(sequences_near(a, direct_form_1(blocks::c2d(g, ts, C2dMethod::Tustin), u), 1e-9, 1.0));
    EXPECT_TRUE(sequences_near(b, direct_form_1(blocks::c2d(g, ts, C2dMethod::BackwardEuler), u), 1e-9, 1.0));
  }
  {
    // A global ZOH: both by ZOH (A's own field agrees), outputs identical.
    const LoopProgram p = lower(*d, at(rate, C2dMethod::Zoh));
    const auto [a, b] = outputs(p);
    EXPECT_TRUE(sequences_near(b, direct_form_1(blocks::c2d(g, ts, C2dMethod::Zoh), u), 1e-9, 1.0));
    EXPECT_TRUE(sequences_near(a, b, 1e-12, 1.0));
  }
}

// force_dob.yaml's Q_A filter carries `discretization: zoh` so that the DOB loop
// u -> Q_A -> d_hat -> u is not algebraic: Q_A is realised on its own by ZOH (not
// merged into a group) and the only group is the plant's.
TEST(BlockMethod, ForceDobQaIsZohAndOutsideAnyGroup) {
  const auto d = Diagram::load(kExamples + "/diagrams/force_dob.yaml");
  const LoopProgram p = lower(*d, at(2000.0));
  for (const auto& b : p.blocks) {
    if (b.path == "Q_A") {
      EXPECT_NE(b.realisation.find("zoh"), std::string::npos) << b.realisation;
      EXPECT_EQ(b.realisation.find("group"), std::string::npos) << b.realisation;
    }
    if (b.path == "C_tau" || b.path == "QB_Pinv") {
      EXPECT_NE(b.realisation.find("tustin"), std::string::npos) << b.path << ": " << b.realisation;
    }
  }
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_NE(p.warnings[0].find("plant."), std::string::npos) << p.warnings[0];
  EXPECT_EQ(p.warnings[0].find("Q_A"), std::string::npos) << p.warnings[0];
}

// A block_methods entry that names no block is a user mistake (a typo in
// --block-method would silently generate the default method): InputError naming it.
// Regression (fixed): it is silently ignored (design.md: user mistakes throw).
TEST(BlockMethod, UnknownBlockPathIsAnInputError) {
  const auto d = Diagram::load(kData + "/methods.yaml");
  LowerOptions o = at(1000.0);
  o.block_methods = {{"Bee", C2dMethod::Zoh}};
  try {
    lower(*d, o);
    FAIL() << "expected an InputError for the unknown block 'Bee'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Bee"), std::string::npos) << e.what();
  }
}

// The command line: --block-method B=zoh changes B's realisation in the header's block
// list; without it B is Tustin.
TEST(BlockMethod, CommandLineOverride) {
  const std::string dir = fresh_dir("block_method");
  auto b_line = [&](const std::string& header) {
    std::istringstream s(read_text(header));
    std::string line;
    while (std::getline(s, line))
      if (line.rfind("//   B (", 0) == 0) return line;
    return std::string();
  };
  CliResult r = run_cli("codegen '" + kData + "/methods.yaml' --rate 1000 --out '" + dir + "'", dir);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(b_line(dir + "/methods.hpp").find("tustin"), std::string::npos) << b_line(dir + "/methods.hpp");
  r = run_cli("codegen '" + kData + "/methods.yaml' --rate 1000 --block-method B=zoh --out '" + dir + "'", dir);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(b_line(dir + "/methods.hpp").find("zoh"), std::string::npos) << b_line(dir + "/methods.hpp");
  r = run_cli("codegen '" + kData + "/methods.yaml' --rate 1000 --block-method B=magic --out '" + dir + "'", dir);
  EXPECT_EQ(r.status, 2) << r.output;
}

}  // namespace
}  // namespace dmbd::codegen
