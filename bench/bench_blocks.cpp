// Speed of the LTI core (issue 2): frequency response of a 10-state system at 1000
// frequencies, ZOH discretisation of a 10-state system, and lsim of 10^6 samples of a
// 4-state system. Systems are fixed (seeded) so instruction counts are repeatable
// under `valgrind --tool=callgrind`.
#include <benchmark/benchmark.h>

#include <random>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/time_response.hpp"

#include <Eigen/Eigenvalues>

namespace {

using namespace dmbd::blocks;  // NOLINT: no SimTK here

// A stable random n-state system: A = Q diag-block(stable modes) Q^T.
StateSpace random_stable(int n, int inputs, int outputs, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd;
  Matrix m(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m(i, j) = nd(rng);
  // Shift the spectrum into the left half-plane.
  Eigen::EigenSolver<Matrix> es(m, false);
  double max_re = 0.0;
  for (int i = 0; i < n; ++i) max_re = std::max(max_re, es.eigenvalues()[i].real());
  m -= (max_re + 0.5) * Matrix::Identity(n, n);
  Matrix b(n, inputs), c(outputs, n);
  for (int i = 0; i < b.size(); ++i) b.data()[i] = nd(rng);
  for (int i = 0; i < c.size(); ++i) c.data()[i] = nd(rng);
  return StateSpace(m, b, c, Matrix::Zero(outputs, inputs));
}

void BM_FrequencyResponse10States1000Freqs(benchmark::State& state) {
  const StateSpace sys = random_stable(10, 1, 1, 1);
  const std::vector<double> w = logspace(1e-2, 1e3, 1000);
  for (auto _ : state) benchmark::DoNotOptimize(frequency_response(sys, w));
}
BENCHMARK(BM_FrequencyResponse10States1000Freqs)->Unit(benchmark::kMicrosecond);

void BM_BodeTf10States1000Freqs(benchmark::State& state) {
  const TransferFunction g = random_stable(10, 1, 1, 1).to_tf();
  const std::vector<double> w = logspace(1e-2, 1e3, 1000);
  for (auto _ : state) benchmark::DoNotOptimize(bode(g, w));
}
BENCHMARK(BM_BodeTf10States1000Freqs)->Unit(benchmark::kMicrosecond);

void BM_Zoh10States(benchmark::State& state) {
  const StateSpace sys = random_stable(10, 2, 2, 2);
  for (auto _ : state) benchmark::DoNotOptimize(c2d(sys, 1e-3, C2dMethod::Zoh));
}
BENCHMARK(BM_Zoh10States)->Unit(benchmark::kMicrosecond);

void BM_Lsim4States1e6Samples(benchmark::State& state) {
  const StateSpace sys = random_stable(4, 1, 1, 3);
  const int n = 1'000'000;
  Matrix u(n, 1);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> ud(-1.0, 1.0);
  for (int k = 0; k < n; ++k) u(k, 0) = ud(rng);
  for (auto _ : state) benchmark::DoNotOptimize(lsim(sys, u, 1e-3));
  state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK(BM_Lsim4States1e6Samples)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
