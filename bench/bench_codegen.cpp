// Speed of the generated force-DOB controller (examples/diagrams/dob_controller.yaml at
// 2 kHz, double) side by side with a hand-written implementation of the same
// arithmetic and with the interpreter that sim/ will run. Deterministic inputs, so
// `valgrind --tool=callgrind` gives repeatable instruction counts.
#include <benchmark/benchmark.h>

#include <climits>
#include <cmath>
#include <cstdint>
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

constexpr int kSteps = 10000;

// The fixed-point controller written by hand as an engineer would: the generator's
// formats and coefficient words (examples/diagrams/dob_controller.yaml, 2 kHz, 32 bit),
// but plain 64-bit accumulation relying on the formats' headroom (no per-term checks),
// one rounding shift and one saturation per result.
class HandWrittenFixed {
 public:
  int32_t step(int32_t fd, int32_t fm) {  // F_d, F_m in Q17; returns i in Q25
    const int32_t err = narrow((int64_t{fd} << 30) - (int64_t{fm} << 30), 47 - 16);             // Q16
    const int32_t pd = narrow(((int64_t{err} * 1839845083) >> 2) + (int64_t{s_pd_} << 30), 47 - 16);  // b0 Q33, s1 Q17
    const int32_t ff = narrow(int64_t{fd} * 1850321944, 56 - 25);                                // Q25
    const int32_t u_r = narrow((int64_t{pd} << 30) + (int64_t{ff} << 21), 46 - 16);             // Q16
    const int32_t qbp = narrow(((int64_t{fm} * 1078227532) >> 1) + (int64_t{s_qb1_} << 30), 51 - 20);  // Q20
    const int32_t qa = s_qa1_;                                                                   // Q25
    const int32_t d_hat = narrow((int64_t{qbp} << 30) - (int64_t{qa} << 25), 50 - 20);          // Q20
    int32_t u = narrow((int64_t{u_r} << 30) - (int64_t{d_hat} << 26), 46 - 16);                 // Q16
    u = u < -1441792 ? -1441792 : (u > 1441792 ? 1441792 : u);                                  // +-22 A
    const int32_t i = u << 9;                                                                    // Q25
    s_pd_ = narrow(((int64_t{err} * -1782013582) >> 1) + ((int64_t{pd} * -1907231258) >> 1), 48 - 17);
    const int32_t qb1 = narrow(((int64_t{fm} * -2134077424) >> 3) + ((int64_t{qbp} * 1863479108) >> 1) + (int64_t{s_qb2_} << 28), 49 - 21);
    s_qb2_ = narrow(((int64_t{fm} * 2118894756) >> 3) + ((int64_t{qbp} * -1646278449) >> 1), 50 - 21);
    s_qb1_ = qb1;
    const int32_t qa1 = narrow(((int64_t{i} * 1115952555) >> 7) + ((int64_t{qa} * 1862838133) >> 1) + (int64_t{s_qa2_} << 29), 54 - 25);
    s_qa2_ = narrow(((int64_t{i} * 2042019727) >> 7) + ((int64_t{qa} * -1644972693) >> 1), 55 - 25);
    s_qa1_ = qa1;
    return i;
  }

 private:
  static int32_t narrow(int64_t acc, int shift) {  // round half up, saturate
    const int64_t v = (acc + (int64_t{1} << (shift - 1))) >> shift;
    return static_cast<int32_t>(v < INT32_MIN ? INT32_MIN : (v > INT32_MAX ? INT32_MAX : v));
  }
  int32_t s_pd_ = 0, s_qb1_ = 0, s_qb2_ = 0, s_qa1_ = 0, s_qa2_ = 0;
};

void BM_HandWrittenDobFixed32(benchmark::State& state) {
  const auto u = inputs(kSteps);
  dob_controller_fixed::fx::Status st{0};
  std::vector<int32_t> uq(u.size());
  for (size_t k = 0; k < u.size(); ++k)
    uq[k] = dob_controller_fixed::fx::quantize32(u[k], dob_controller_fixed::kInputQ[k % 2], st);
  HandWrittenFixed h;
  for (auto _ : state) {
    for (int k = 0; k < kSteps; ++k) benchmark::DoNotOptimize(h.step(uq[2 * static_cast<size_t>(k)], uq[2 * static_cast<size_t>(k) + 1]));
  }
  state.SetItemsProcessed(state.iterations() * kSteps);
}
BENCHMARK(BM_HandWrittenDobFixed32);

dmbd::codegen::LoopProgram program() {
  const auto d = dmbd::diagrams::Diagram::load(DMBD_EXAMPLES "/diagrams/dob_controller.yaml");
  dmbd::codegen::LowerOptions o;
  o.rate_hz = 2000.0;
  return dmbd::codegen::lower(*d, o);
}

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
