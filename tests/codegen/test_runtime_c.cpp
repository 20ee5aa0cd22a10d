// The C fixed-point runtime (codegen/runtime/fixed_point_c.inc), compiled as C99 by the
// system compiler with the generated code's flags, against the C++ runtime
// (codegen/runtime/fixed_point.inc) that the generated C++ and the fixed interpreter
// use: every function the generated C calls, on edge operands (word and accumulator
// limits, shifts by 0, by the width and beyond, exact rounding ties, NaN and infinities,
// a saturation counter at its sticky limit) and on random ones, gives the same result
// and the same saturation count. Operands for which the C++ runtime's behaviour would
// be undefined (the unchecked accumulation's overflow, outside the headroom rule (G))
// are not drawn.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "dmbd/codegen/verify.hpp"
#include "test_support.hpp"

namespace cxx_fx {
#include "fixed_point.inc"
}  // namespace cxx_fx

namespace dmbd::codegen {
namespace {

using namespace test;

// One call: the function (op) and its operands; the same layout in the C driver.
struct Case {
  int64_t op, a, b, c, d, e, g;
  int64_t saturations;  // the counter before the call
  double v;
};
struct Result {
  int64_t r;
  int64_t saturations;
  double x;
};

enum Op : int64_t {
  kShrRnd32, kShrRnd64, kShlSat32, kShlSat64, kConvert16, kConvert32, kClamp16, kClamp32, kNarrow16, kNarrow32,
  kMac16, kMac32, kAdd16, kSub16, kAdd32, kSub32, kQuantize16, kQuantize32, kDequantize16, kDequantize32,
  kConvert32To16, kNarrow32To16,  // mixed words: a 16-bit program's 32-bit states
  kNumOps
};

const char* const kDriver = R"(#include <stdint.h>
#include <stdio.h>
#include "fixed_point_c.inc"
struct Case { int64_t op, a, b, c, d, e, g, saturations; double v; };
struct Result { int64_t r, saturations; double x; };
int main(int argc, char** argv) {
  struct Case k;
  struct Result r;
  uint32_t s;
  FILE *in, *out;
  if (argc != 3 || !(in = fopen(argv[1], "rb")) || !(out = fopen(argv[2], "wb"))) return 1;
  while (fread(&k, sizeof k, 1, in) == 1) {
    int a = (int)k.a, b = (int)k.b, c = (int)k.c, d = (int)k.d, e = (int)k.e, g = (int)k.g;
    s = (uint32_t)k.saturations;
    r.r = 0;
    r.x = 0.0;
    switch (k.op) {
      case 0: r.r = fx_shr_rnd32((int32_t)k.a, b); break;
      case 1: r.r = fx_shr_rnd64(k.a, b); break;
      case 2: r.r = fx_shl_sat32((int32_t)k.a, b, (int32_t)k.c, (int32_t)k.d, &s); break;
      case 3: r.r = fx_shl_sat64(k.a, b, k.c, k.d, &s); break;
      case 4: r.r = fx_convert16((int16_t)a, b, c, &s); break;
      case 5: r.r = fx_convert32((int32_t)k.a, b, c, &s); break;
      case 6: r.r = fx_clamp16((int16_t)a, (int16_t)b, (int16_t)c); break;
      case 7: r.r = fx_clamp32((int32_t)k.a, (int32_t)k.b, (int32_t)k.c); break;
      case 8: r.r = fx_narrow16((int32_t)k.a, b, c, &s); break;
      case 9: r.r = fx_narrow32(k.a, b, c, &s); break;
      case 10: r.r = fx_mac16_g((int32_t)k.a, (int16_t)b, c, (int16_t)d, e, g); break;
      case 11: r.r = fx_mac32_g(k.a, (int32_t)k.b, c, (int32_t)k.d, e, g); break;
      case 12: r.r = fx_acc16_add_g((int32_t)k.a, (int16_t)b, c, d); break;
      case 13: r.r = fx_acc16_sub_g((int32_t)k.a, (int16_t)b, c, d); break;
      case 14: r.r = fx_acc32_add_g(k.a, (int32_t)k.b, c, d); break;
      case 15: r.r = fx_acc32_sub_g(k.a, (int32_t)k.b, c, d); break;
      case 16: r.r = fx_quantize16(k.v, a, &s); break;
      case 17: r.r = fx_quantize32(k.v, a, &s); break;
      case 18: r.x = fx_dequantize16((int16_t)a, b); break;
      case 19: r.x = fx_dequantize32((int32_t)k.a, b); break;
      case 20: r.r = fx_convert32_16((int32_t)k.a, b, c, &s); break;
      case 21: r.r = fx_narrow32_16(k.a, b, c, &s); break;
      default: return 2;
    }
    r.saturations = s;
    fwrite(&r, sizeof r, 1, out);
  }
  fclose(in);
  fclose(out);
  return 0;
}
)";

// What the C++ runtime gives for a case.
Result expected(const Case& k) {
  namespace fx = cxx_fx;
  fx::Status st{static_cast<uint32_t>(k.saturations)};
  const int a = static_cast<int>(k.a), b = static_cast<int>(k.b), c = static_cast<int>(k.c), d = static_cast<int>(k.d),
            e = static_cast<int>(k.e), g = static_cast<int>(k.g);
  const auto w16 = [](int64_t v) { return static_cast<int16_t>(v); };
  const auto w32 = [](int64_t v) { return static_cast<int32_t>(v); };
  Result r{0, 0, 0.0};
  switch (k.op) {
    case kShrRnd32: r.r = fx::shr_rnd32(w32(k.a), b); break;
    case kShrRnd64: r.r = fx::shr_rnd64(k.a, b); break;
    case kShlSat32: r.r = fx::shl_sat32(w32(k.a), b, w32(k.c), w32(k.d), st); break;
    case kShlSat64: r.r = fx::shl_sat64(k.a, b, k.c, k.d, st); break;
    case kConvert16: r.r = fx::convert16(w16(a), b, c, st); break;
    case kConvert32: r.r = fx::convert32(w32(k.a), b, c, st); break;
    case kClamp16: r.r = fx::clamp16(w16(a), w16(b), w16(c)); break;
    case kClamp32: r.r = fx::clamp32(w32(k.a), w32(k.b), w32(k.c)); break;
    case kNarrow16: r.r = fx::narrow16(w32(k.a), b, c, st); break;
    case kNarrow32: r.r = fx::narrow32(k.a, b, c, st); break;
    case kMac16: r.r = fx::mac16_g(w32(k.a), w16(b), c, w16(d), e, g); break;
    case kMac32: r.r = fx::mac32_g(k.a, w32(k.b), c, w32(k.d), e, g); break;
    case kAdd16: r.r = fx::acc16_add_g(w32(k.a), w16(b), c, d); break;
    case kSub16: r.r = fx::acc16_sub_g(w32(k.a), w16(b), c, d); break;
    case kAdd32: r.r = fx::acc32_add_g(k.a, w32(k.b), c, d); break;
    case kSub32: r.r = fx::acc32_sub_g(k.a, w32(k.b), c, d); break;
    case kQuantize16: r.r = fx::quantize16(k.v, a, st); break;
    case kQuantize32: r.r = fx::quantize32(k.v, a, st); break;
    case kDequantize16: r.x = fx::dequantize16(w16(a), b); break;
    case kDequantize32: r.x = fx::dequantize32(w32(k.a), b); break;
    case kConvert32To16: r.r = fx::convert32_16(w32(k.a), b, c, st); break;
    case kNarrow32To16: r.r = fx::narrow32_16(k.a, b, c, st); break;
    default: break;
  }
  r.saturations = st.saturations;
  return r;
}

__extension__ typedef __int128 i128;

// Whether an unchecked accumulation acc +- (v aligned from Q(q) to Q(qacc)) stays within
// an accumulator of `bits` bits, computed exactly: the headroom rule's promise, without
// which both runtimes overflow a signed integer (undefined). A left shift must also be
// one the runtime can form (1 << d below the sign bit).
bool fits_unchecked(int64_t acc, i128 v, int q, int qacc, int bits, bool sub) {
  const i128 lim = static_cast<i128>(1) << (bits - 1);
  i128 t;
  if (q >= qacc) {
    t = q - qacc >= bits ? (v < 0 ? -1 : 0) : v >> (q - qacc);
  } else {
    if (qacc - q > bits - 2) return false;
    t = v * (static_cast<i128>(1) << (qacc - q));
    if (t >= lim || t < -lim) return false;
  }
  const i128 sum = sub ? acc - t : acc + t;
  return sum < lim && sum >= -lim;
}

std::vector<Case> cases() {
  Rng rng(20240416);
  const int64_t i16[] = {0, 1, -1, 2, -2, 3, -3, INT16_MAX, INT16_MIN, INT16_MAX - 1, INT16_MIN + 1, 0x4000, -0x4000};
  const int64_t i32[] = {0, 1, -1, 2, -2, 3, -5, INT32_MAX, INT32_MIN, INT32_MAX - 1, INT32_MIN + 1, 0x40000000, -0x40000000,
                         INT16_MAX, INT16_MIN, INT16_MAX + 1, INT16_MIN - 1};
  const int64_t i64[] = {0, 1, -1, 2, -2, 7, -7, INT64_MAX, INT64_MIN, INT64_MAX - 1, INT64_MIN + 1, INT32_MAX, INT32_MIN,
                         static_cast<int64_t>(INT32_MAX) + 1, static_cast<int64_t>(INT32_MIN) - 1};
  const int64_t counters[] = {0, 7, 0xFFFFFFFE, 0xFFFFFFFF};
  // A value of `bits` bits, of random magnitude: an edge value one time in four.
  auto value = [&](int bits) -> int64_t {
    if (rng.next() % 4 == 0) {
      if (bits == 16) return i16[rng.next() % (sizeof i16 / sizeof *i16)];
      if (bits == 32) return i32[rng.next() % (sizeof i32 / sizeof *i32)];
      return i64[rng.next() % (sizeof i64 / sizeof *i64)];
    }
    const int64_t v = static_cast<int64_t>(rng.next()) >> (64 - bits);  // uniform over the type
    return v >> (rng.next() % static_cast<unsigned>(bits));            // of random magnitude
  };
  auto shift = [&](int lo, int hi) { return lo + static_cast<int>(rng.next() % static_cast<unsigned>(hi - lo + 1)); };
  auto real = [&]() -> double {
    switch (rng.next() % 8) {
      case 0: {
        const double special[] = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, -2.5, 0.49999999999999994, -0.49999999999999994,
                                  std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                                  -std::numeric_limits<double>::infinity(), 1e300, -1e300, 5e-324};
        return special[rng.next() % (sizeof special / sizeof *special)];
      }
      case 1: return (static_cast<double>(value(32)) + 0.5) * std::ldexp(1.0, -shift(0, 40));  // a tie at some format
      default: return rng.uniform(-1.0, 1.0) * std::ldexp(1.0, shift(-40, 40));
    }
  };
  std::vector<Case> all;
  for (int64_t op = 0; op < kNumOps; ++op)
    for (int n = 0; n < 10000; ++n) {
      Case k{op, 0, 0, 0, 0, 0, 0, counters[rng.next() % 4], 0.0};
      switch (op) {
        case kShrRnd32: k.a = value(32), k.b = shift(-3, 40); break;
        case kShrRnd64: k.a = value(64), k.b = shift(-3, 72); break;
        case kShlSat32: {  // lo <= 0 <= hi: the word or accumulator limits, or any
          const int64_t lo[] = {INT32_MIN, -INT32_MAX, INT16_MIN, -std::abs(value(32) / 2)};
          const int64_t hi[] = {INT32_MAX, INT16_MAX, std::abs(value(32) / 2)};
          k.a = value(32), k.b = shift(-2, 40), k.c = lo[rng.next() % 4], k.d = hi[rng.next() % 3];
          break;
        }
        case kShlSat64: {
          const int64_t lo[] = {INT64_MIN, -INT64_MAX, INT32_MIN, -std::abs(value(64) / 2)};
          const int64_t hi[] = {INT64_MAX, INT32_MAX, std::abs(value(64) / 2)};
          k.a = value(64), k.b = shift(-2, 72), k.c = lo[rng.next() % 4], k.d = hi[rng.next() % 3];
          break;
        }
        case kConvert16: case kNarrow16: k.a = value(op == kConvert16 ? 16 : 32), k.b = shift(-20, 45), k.c = shift(-20, 45); break;
        case kConvert32: case kNarrow32: k.a = value(op == kConvert32 ? 32 : 64), k.b = shift(-40, 80), k.c = shift(-40, 80); break;
        case kClamp16: k.a = value(16), k.b = value(16), k.c = value(16); break;
        case kClamp32: k.a = value(32), k.b = value(32), k.c = value(32); break;
        case kMac16: case kMac32: {
          const int bits = op == kMac16 ? 16 : 32;
          do {
            k.a = value(2 * bits), k.b = value(bits), k.c = shift(-10, 40), k.d = value(bits), k.e = shift(-10, 40),
            k.g = shift(-10, 90);
          } while (!fits_unchecked(k.a, static_cast<i128>(k.b) * k.d, static_cast<int>(k.c + k.e), static_cast<int>(k.g),
                                   2 * bits, false));
          break;
        }
        case kAdd16: case kSub16: case kAdd32: case kSub32: {
          const int bits = op == kAdd16 || op == kSub16 ? 16 : 32;
          do {
            k.a = value(2 * bits), k.b = value(bits), k.c = shift(-10, 40), k.d = shift(-10, 80);
          } while (!fits_unchecked(k.a, k.b, static_cast<int>(k.c), static_cast<int>(k.d), 2 * bits,
                                   op == kSub16 || op == kSub32));
          break;
        }
        case kQuantize16: case kQuantize32: k.v = real(), k.a = shift(-40, 60); break;
        case kDequantize16: k.a = value(16), k.b = shift(-60, 60); break;
        case kDequantize32: k.a = value(32), k.b = shift(-60, 60); break;
        case kConvert32To16: k.a = value(32), k.b = shift(-40, 60), k.c = shift(-40, 60); break;
        case kNarrow32To16: k.a = value(64), k.b = shift(-40, 90), k.c = shift(-40, 90); break;
        default: break;
      }
      all.push_back(k);
    }
  return all;
}

TEST(RuntimeC, EveryFunctionMatchesTheCppRuntime) {
  const std::string dir = fresh_dir("runtime_c");
  const std::vector<Case> all = cases();
  {
    std::ofstream f(dir + "/cases.bin", std::ios::binary);
    f.write(reinterpret_cast<const char*>(all.data()), static_cast<std::streamsize>(all.size() * sizeof(Case)));
  }
  std::ofstream(dir + "/driver.c") << kDriver;
  const std::string compile = compile_command(Language::C, {dir + "/driver.c"}, dir + "/driver", "-I'" DMBD_CODEGEN_RUNTIME "'");
  ASSERT_EQ(std::system((compile + " > '" + dir + "/compile.log' 2>&1").c_str()), 0) << read_text(dir + "/compile.log");
  ASSERT_EQ(std::system(("'" + dir + "/driver' '" + dir + "/cases.bin' '" + dir + "/results.bin'").c_str()), 0);
  std::vector<Result> got(all.size());
  std::ifstream f(dir + "/results.bin", std::ios::binary);
  ASSERT_TRUE(f.read(reinterpret_cast<char*>(got.data()), static_cast<std::streamsize>(got.size() * sizeof(Result))));
  std::vector<int> bad(kNumOps, 0), saturating(kNumOps, 0);
  for (size_t i = 0; i < all.size(); ++i) {
    const Result want = expected(all[i]);
    const int op = static_cast<int>(all[i].op);
    saturating[static_cast<size_t>(op)] += want.saturations != all[i].saturations;
    if (got[i].r != want.r || got[i].saturations != want.saturations || std::memcmp(&got[i].x, &want.x, sizeof(double)) != 0) {
      if (++bad[static_cast<size_t>(op)] <= 3)
        ADD_FAILURE() << "op " << op << " (" << all[i].a << ", " << all[i].b << ", " << all[i].c << ", " << all[i].d << ", "
                      << all[i].e << ", " << all[i].g << ", v " << all[i].v << ", counter " << all[i].saturations
                      << "): C " << got[i].r << " / " << got[i].saturations << " / " << got[i].x << ", C++ " << want.r
                      << " / " << want.saturations << " / " << want.x;
    }
  }
  // The cases do reach saturation (and the counter's sticky limit) where a function can saturate.
  for (int op : {kShlSat32, kShlSat64, kConvert16, kConvert32, kNarrow16, kNarrow32, kQuantize16, kQuantize32,
                 kConvert32To16, kNarrow32To16})
    EXPECT_GT(saturating[static_cast<size_t>(op)], 100) << "op " << op;
}

}  // namespace
}  // namespace dmbd::codegen
