// Speed of the generated force-DOB controller (examples/diagrams/dob_controller.yaml at
// 2 kHz, double) side by side with a hand-written implementation of the same
// arithmetic and with the interpreter that sim/ will run. Deterministic inputs, so
// `valgrind --tool=callgrind` gives repeatable instruction counts.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dob_controller.hpp"        // generated at build time by dmbd codegen
#include "dob_controller_fixed.hpp"  // the same, --scalar fixed (32-bit words)

namespace {

std::vector<double> inputs(int n) {
  std::vector<double> u(2 * static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    u[2 * static_cast<size_t>(k)] = 3000.0 * std::sin(0.01 * k);
    u[2 * static_cast<size_t>(k) + 1] = 2900.0 * std::sin(0.01 * k - 0.05);
  }
  return u;
}

// The same controller written by hand: the same sections and the same operation order
// as the generated code, coefficients from the lowering of the same diagram.
class HandWritten {
 public:
  explicit HandWritten(const dmbd::codegen::LoopProgram& p) {
    // Pull the coefficients out of the program in emission order.
    for (const auto* ops : {&p.output_ops, &p.update_ops})
      for (const auto& o : *ops) c_.push_back(o.c);
  }
  double step(double f_d, double f_m) {
    const double* c = c_.data();
    const double err = f_d - f_m;
    const double pd = c[2] * err + s_pd_;
    const double u_r = pd + c[4] * f_d;
    const double qbp = c[7] * f_m + s_qb1_;
    const double qa = s_qa1_;
    const double d_hat = qbp - qa;
    double u = u_r - d_hat;
    u = u < -22.0 ? -22.0 : (u > 22.0 ? 22.0 : u);
    // state updates
    s_pd_ = c[16] * err + c[17] * pd;
    s_qb1_ = c[18] * f_m + c[19] * qbp + s_qb2_;
    s_qb2_ = c[21] * f_m + c[22] * qbp;
    s_qa1_ = c[23] * u + c[24] * qa + s_qa2_;
    s_qa2_ = c[26] * u + c[27] * qa;
    return u;
  }

 private:
  std::vector<double> c_;
  double s_pd_ = 0, s_qb1_ = 0, s_qb2_ = 0, s_qa1_ = 0, s_qa2_ = 0;
};

dmbd::codegen::LoopProgram program() {
  const auto d = dmbd::diagrams::Diagram::load(DMBD_EXAMPLES "/diagrams/dob_controller.yaml");
  dmbd::codegen::LowerOptions o;
  o.rate_hz = 2000.0;
  return dmbd::codegen::lower(*d, o);
}

constexpr int kSteps = 10000;

void BM_GeneratedDobDouble(benchmark::State& state) {
  const auto u = inputs(kSteps);
  dob_controller::Controller c;
  double y = 0;
  for (auto _ : state) {
    for (int k = 0; k < kSteps; ++k) {
      c.step(&u[2 * static_cast<size_t>(k)], &y);
      benchmark::DoNotOptimize(y);
    }
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}
BENCHMARK(BM_GeneratedDobDouble);

void BM_GeneratedDobFixed32(benchmark::State& state) {
  const auto u = inputs(kSteps);
  dob_controller_fixed::Controller c;
  dob_controller_fixed::fx::Status st{0};
  std::vector<int32_t> uq(u.size());
  for (size_t k = 0; k < u.size(); ++k)
    uq[k] = dob_controller_fixed::fx::quantize32(u[k], dob_controller_fixed::kInputQ[k % 2], st);
  int32_t y = 0;
  for (auto _ : state) {
    for (int k = 0; k < kSteps; ++k) {
      c.step(&uq[2 * static_cast<size_t>(k)], &y);
      benchmark::DoNotOptimize(y);
    }
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}
BENCHMARK(BM_GeneratedDobFixed32);

void BM_HandWrittenDobDouble(benchmark::State& state) {
  const auto u = inputs(kSteps);
  const auto p = program();
  HandWritten h(p);
  for (auto _ : state) {
    for (int k = 0; k < kSteps; ++k) benchmark::DoNotOptimize(h.step(u[2 * static_cast<size_t>(k)], u[2 * static_cast<size_t>(k) + 1]));
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}
BENCHMARK(BM_HandWrittenDobDouble);

void BM_InterpretedDobDouble(benchmark::State& state) {
  const auto u = inputs(kSteps);
  const auto p = program();
  dmbd::codegen::Interpreter<double> it(p);
  double y = 0;
  for (auto _ : state) {
    for (int k = 0; k < kSteps; ++k) {
      it.step(&u[2 * static_cast<size_t>(k)], &y);
      benchmark::DoNotOptimize(y);
    }
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}
BENCHMARK(BM_InterpretedDobDouble);

}  // namespace

BENCHMARK_MAIN();
