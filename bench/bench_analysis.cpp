// Speed of diagram analysis at scale (issue 13, item 11): what `dmbd analyze DIAGRAM
// --from u --to y` computes for chains of 1000 and 10000 blocks (first-order filters
// 10/(s + 10), or gains), from the YAML text: loading, the sparse linearisation, the
// structural factorisation (blocks::Siso), margins, bandwidth, a 600-point Bode and a
// 1000-sample step response (the --bode/--step-plot defaults). Also the parts alone.
#include <benchmark/benchmark.h>

#include <string>

#include "dmbd/blocks/siso.hpp"
#include "dmbd/blocks/zpk.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/linearize.hpp"
#include "../tests/support/chain_diagram.hpp"

namespace {

namespace b = dmbd::blocks;
namespace d = dmbd::diagrams;

using dmbd::test::chain_diagram;

const char* kLag = "{type: tf, expr: \"10/(s+10)\"}";
const char* kGain = "{type: gain, k: 1.0001}";

// Everything the report needs, as apps/analyze.cpp computes it.
void analyse(const std::string& yaml, bool with_step) {
  const auto diagram = d::Diagram::parse(yaml, "chain.yaml");
  const b::Siso g = b::Siso::from_state_space(d::linearize_sparse(*diagram, "u", "y"));
  benchmark::DoNotOptimize(b::margins(g.zpk()));
  benchmark::DoNotOptimize(b::bandwidth(g.zpk()));
  benchmark::DoNotOptimize(b::bode(g.zpk(), b::default_frequency_grid(g.zpk(), 600)));
  if (with_step) benchmark::DoNotOptimize(g.step(g.default_step_horizon(), 1000));
}

void BM_AnalyseLagChain(benchmark::State& state) {
  const std::string yaml = chain_diagram(static_cast<int>(state.range(0)), kLag);
  for (auto _ : state) analyse(yaml, true);
}
BENCHMARK(BM_AnalyseLagChain)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

void BM_AnalyseLagChainWithoutStep(benchmark::State& state) {
  const std::string yaml = chain_diagram(static_cast<int>(state.range(0)), kLag);
  for (auto _ : state) analyse(yaml, false);
}
BENCHMARK(BM_AnalyseLagChainWithoutStep)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

void BM_AnalyseGainChain(benchmark::State& state) {
  const std::string yaml = chain_diagram(static_cast<int>(state.range(0)), kGain);
  for (auto _ : state) analyse(yaml, true);
}
BENCHMARK(BM_AnalyseGainChain)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

void BM_LoadLagChain(benchmark::State& state) {
  const std::string yaml = chain_diagram(static_cast<int>(state.range(0)), kLag);
  for (auto _ : state) benchmark::DoNotOptimize(d::Diagram::parse(yaml, "chain.yaml"));
}
BENCHMARK(BM_LoadLagChain)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
