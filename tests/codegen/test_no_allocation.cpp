// No heap allocation inside a control step (design.md): Interpreter::step is run many
// times under a global operator new that counts, per thread, while counting is on.
#include <gtest/gtest.h>

#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "test_support.hpp"

namespace {
thread_local bool g_counting = false;
thread_local long g_allocations = 0;

void* counted_new(std::size_t n) {
  if (g_counting) ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
}  // namespace

// Replacements of the global allocation functions (the nothrow and array forms of the
// standard library forward to these; the deallocation functions match malloc).
void* operator new(std::size_t n) { return counted_new(n); }
void* operator new[](std::size_t n) { return counted_new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return counted_new(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return counted_new(n);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace dmbd::codegen {
namespace {

using namespace test;

struct Counting {
  Counting() {
    g_allocations = 0;
    g_counting = true;
  }
  ~Counting() { g_counting = false; }
  long count() const { return g_allocations; }
};

// The counter itself works: an allocation while counting is seen (so a zero below is
// not a broken counter).
TEST(NoAllocation, CounterSeesAnAllocation) {
  long seen = 0;
  {
    Counting c;
    std::vector<double> v(static_cast<size_t>(100 + g_allocations), 1.0);
    volatile double sink = v[static_cast<size_t>(g_allocations)];
    (void)sink;
    seen = c.count();
  }
  EXPECT_GE(seen, 1);
}

template <class T>
long allocations_in_steps(const LoopProgram& p, int steps) {
  Interpreter<T> it(p);  // construction may allocate (slots, coefficients)
  std::vector<T> u(p.inputs.size()), y(p.outputs.size());
  Rng rng(3);
  std::vector<T> noise(static_cast<size_t>(steps));
  for (auto& v : noise) v = static_cast<T>(rng.uniform(-1.0, 1.0));
  Counting c;
  for (int k = 0; k < steps; ++k) {
    for (auto& v : u) v = noise[static_cast<size_t>(k)];
    it.step(u.data(), y.data());
    if (k == steps / 2) it.reset();
  }
  return c.count();
}

TEST(NoAllocation, InterpreterStepOfEveryExampleDiagram) {
  for (const std::string& name : example_diagrams()) {
    SCOPED_TRACE(name);
    const auto d = diagrams::Diagram::load(kExamples + "/diagrams/" + name + ".yaml");
    LowerOptions o;
    o.rate_hz = 2000.0;
    const LoopProgram p = lower(*d, o);
    EXPECT_EQ(allocations_in_steps<double>(p, 20000), 0);
    EXPECT_EQ(allocations_in_steps<float>(p, 20000), 0);
  }
}

TEST(NoAllocation, InterpreterStepOfAnEighthOrderFilter) {
  LowerOptions o;
  o.rate_hz = 1000.0;
  const LoopProgram p = lower(TransferFunction::parse("1/((s/300 + 1)^4*(s^2/40000 + 0.1*s/200 + 1)^2)"), "f", o);
  EXPECT_EQ(allocations_in_steps<double>(p, 50000), 0);
}

// Issue 28, row 13: a pid with output limits in each anti-windup mode (its clamps
// engage on the noise of amplitude 1 against limits of +-0.5).
TEST(NoAllocation, InterpreterStepOfALimitedPidInEveryAntiWindupMode) {
  for (const std::string mode : {"none", "clamp", "back_calculation, Kt: 40"}) {
    SCOPED_TRACE(mode);
    const auto d = parse("name: pid\ninputs:\n  e: {}\noutputs:\n  u: {}\nblocks:\n  C: {type: pid, P: 2, I: 30, D: 0.05, "
                         "tau: 0.002, output_limits: [-0.5, 0.5], anti_windup: " + mode + "}\nconnections:\n  - e -> C\n  - C -> u\n");
    const LoopProgram p = lower(*d, at(2000.0));
    EXPECT_EQ(allocations_in_steps<double>(p, 20000), 0);
    EXPECT_EQ(allocations_in_steps<float>(p, 20000), 0);
  }
}

}  // namespace
}  // namespace dmbd::codegen
