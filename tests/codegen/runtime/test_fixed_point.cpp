// Tests of the fixed-point runtime fragment codegen/runtime/fixed_point.inc.
//
// The fragment is pasted inside a namespace exactly as the code emitter does.  Every
// operation is checked against an independent exact reference written with __int128
// division (no shifts, no rounding tricks): round half up rnd(v) = floor(v + 1/2), then
// saturation to the word or accumulator, and whether a saturation had to be counted.
// Tolerances: none.  Every comparison is exact (0 LSB), except the documented bounds
// of quantise/dequantise (1/2 LSB) and of per-term rounded accumulation (N/2 LSB of
// the accumulator + 1/2 LSB of the result).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace fxtest {
namespace fx {
#include "fixed_point.inc"
}  // namespace fx
}  // namespace fxtest

namespace {

using fxtest::fx::Status;
namespace fx = fxtest::fx;

__extension__ typedef __int128 i128;

// --------------------------------------------------------------------------------
// Exact references.
// --------------------------------------------------------------------------------

// floor(v / 2^s) for 0 <= s <= 125, by integer division (truncating) plus correction.
i128 floor_div_pow2(i128 v, int s) {
  const i128 d = static_cast<i128>(1) << s;
  i128 q = v / d;
  if (v % d != 0 && v < 0) --q;
  return q;
}

struct Ref {
  int64_t value;
  bool saturated;
};

// clamp(rnd(v * 2^-s), lo, hi) exactly, for |v| <= 2^64 and any s; rnd = floor(x + 1/2).
Ref ref_scale(i128 v, int s, int64_t lo, int64_t hi) {
  i128 r;
  if (s == 0) {
    r = v;
  } else if (s > 0) {
    r = s > 100 ? 0 : floor_div_pow2(v + (static_cast<i128>(1) << (s - 1)), s);
  } else {
    const int n = -s;
    if (v == 0) {
      r = 0;
    } else if (n >= 64) {  // |v| * 2^n >= 2^64: beyond every limit
      r = v > 0 ? static_cast<i128>(hi) + 1 : static_cast<i128>(lo) - 1;
    } else {
      r = v * (static_cast<i128>(1) << n);
    }
  }
  if (r > hi) return {hi, true};
  if (r < lo) return {lo, true};
  return {static_cast<int64_t>(r), false};
}

// --------------------------------------------------------------------------------
// Deterministic pseudo-random numbers (splitmix64; portable, no library distributions).
// --------------------------------------------------------------------------------
struct Rng {
  uint64_t s;
  explicit Rng(uint64_t seed) : s(seed) {}
  uint64_t next() {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  int uniform_int(int lo, int hi) {  // inclusive
    return lo + static_cast<int>(next() % static_cast<uint64_t>(hi - lo + 1));
  }
  // A word biased towards the interesting places: limits, zero, powers of two +-1,
  // small values, and otherwise uniform.
  int64_t word(int bits) {
    const int64_t max = bits == 64 ? INT64_MAX : (static_cast<int64_t>(1) << (bits - 1)) - 1;
    const int64_t min = -max - 1;
    const uint64_t kind = next() % 8;
    const uint64_t r = next();
    switch (kind) {
      case 0: {
        const int64_t e[] = {min, min + 1, -1, 0, 1, max - 1, max};
        return e[r % 7];
      }
      case 1: {
        const int p = static_cast<int>(r % static_cast<uint64_t>(bits - 1));
        const int64_t v = (static_cast<int64_t>(1) << p) + static_cast<int64_t>((r >> 8) % 3) - 1;
        return (r >> 16) & 1 ? -v : v;
      }
      case 2:
        return static_cast<int64_t>(r % 33) - 16;
      default: {
        if (bits == 64) return static_cast<int64_t>(r);
        const uint64_t u = r >> (64 - bits);  // uniform in [0, 2^bits)
        return static_cast<int64_t>(u) + min;
      }
    }
  }
  int16_t w16() { return static_cast<int16_t>(word(16)); }
  int32_t w32() { return static_cast<int32_t>(word(32)); }
};

// Collects mismatches of a long loop: counts them and keeps the first description.
struct Mismatches {
  long count = 0;
  std::string first;
  void add(const std::string& what) {
    if (count++ == 0) first = what;
  }
};

std::string describe(const char* op, int64_t a, int64_t b, int qa, int qb, int qy, int64_t got,
                     int64_t want) {
  std::ostringstream o;
  o << op << "(" << a << " Q" << qa << ", " << b << " Q" << qb << " -> Q" << qy << ") = " << got
    << ", expected " << want;
  return o.str();
}

// Values every 16-bit sampled coefficient set contains.
std::vector<int16_t> coefficient_sample16(Rng& rng, int random_count) {
  std::vector<int16_t> c = {INT16_MIN, INT16_MIN + 1, -16385, -16384, -16383, -2, -1, 0,
                            1,         2,             3,      16383,  16384,  16385, INT16_MAX - 1,
                            INT16_MAX};
  for (int i = 0; i < random_count; ++i) c.push_back(static_cast<int16_t>(rng.next() >> 48));
  return c;
}

// Checks mul16 for every 16-bit x against every coefficient c of the sample.
void check_mul16_all_x(const std::vector<int16_t>& coefficients, int qx, int qc, int qy,
                       Mismatches& bad, long& checked, long& saturations) {
  for (const int16_t c : coefficients) {
    for (int xi = INT16_MIN; xi <= INT16_MAX; ++xi) {
      const int16_t x = static_cast<int16_t>(xi);
      Status st = {0};
      const int16_t y = fx::mul16(x, qx, c, qc, qy, st);
      const Ref r = ref_scale(static_cast<i128>(x) * c, qx + qc - qy, INT16_MIN, INT16_MAX);
      if (y != r.value || st.saturations != (r.saturated ? 1u : 0u))
        bad.add(describe("mul16", x, c, qx, qc, qy, y, r.value) + (r.saturated ? " (sat)" : ""));
      saturations += r.saturated;
      ++checked;
    }
  }
}

// --------------------------------------------------------------------------------
// Building blocks.
// --------------------------------------------------------------------------------

TEST(FixedPointRounding, RoundedRightShiftIsExactRoundHalfUpForAllShifts) {
  Rng rng(1);
  Mismatches bad;
  for (int i = 0; i < 20000; ++i) {
    const int32_t v32 = rng.w32();
    const int64_t v64 = static_cast<int64_t>(rng.word(64));
    for (int s = 0; s <= 40; ++s) {
      const Ref r = ref_scale(v32, s, INT32_MIN, INT32_MAX);
      if (fx::shr_rnd32(v32, s) != r.value) bad.add(describe("shr_rnd32", v32, 0, s, 0, 0, fx::shr_rnd32(v32, s), r.value));
    }
    for (int s = 0; s <= 70; ++s) {
      const Ref r = ref_scale(v64, s, INT64_MIN, INT64_MAX);
      if (fx::shr_rnd64(v64, s) != r.value) bad.add(describe("shr_rnd64", v64, 0, s, 0, 0, fx::shr_rnd64(v64, s), r.value));
    }
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  // Exact ties go towards +infinity: 3/2 -> 2, -3/2 -> -1, -1/2 -> 0, 1/2 -> 1.
  EXPECT_EQ(fx::shr_rnd32(3, 1), 2);
  EXPECT_EQ(fx::shr_rnd32(-3, 1), -1);
  EXPECT_EQ(fx::shr_rnd32(-1, 1), 0);
  EXPECT_EQ(fx::shr_rnd32(1, 1), 1);
  EXPECT_EQ(fx::shr_rnd32(-5, 1), -2);   // -2.5 -> -2
  EXPECT_EQ(fx::shr_rnd32(-7, 2), -2);   // -1.75 -> -2
  EXPECT_EQ(fx::shr_rnd32(INT32_MIN, 31), -1);
  EXPECT_EQ(fx::shr_rnd32(INT32_MIN, 32), 0);   // -1/2 -> 0
  EXPECT_EQ(fx::shr_rnd32(INT32_MAX, 1), 1073741824);  // no overflow in the rounding add
  EXPECT_EQ(fx::shr_rnd64(INT64_MAX, 1), INT64_C(4611686018427387904));
  EXPECT_EQ(fx::shr_rnd64(INT64_MIN, 63), -1);
  EXPECT_EQ(fx::shr_rnd64(INT64_MIN, 64), 0);
  EXPECT_EQ(fx::shr_rnd64(INT64_C(3) << 40, 41), 2);
  EXPECT_EQ(fx::shr_rnd64(-(INT64_C(3) << 40), 41), -1);
}

TEST(FixedPointRounding, SaturatingLeftShiftIsExactAndCountsOnce) {
  Rng rng(2);
  Mismatches bad;
  for (int i = 0; i < 20000; ++i) {
    const int32_t v32 = rng.w32();
    const int64_t v64 = static_cast<int64_t>(rng.word(64));
    for (int n = 0; n <= 40; ++n) {
      Status st = {0};
      const int32_t got = fx::shl_sat32(v32, n, INT32_MIN, INT32_MAX, st);
      const Ref r = ref_scale(v32, -n, INT32_MIN, INT32_MAX);
      if (got != r.value || st.saturations != (r.saturated ? 1u : 0u))
        bad.add(describe("shl_sat32", v32, 0, n, 0, 0, got, r.value));
    }
    for (int n = 0; n <= 70; ++n) {
      Status st = {0};
      const int64_t got = fx::shl_sat64(v64, n, INT64_MIN, INT64_MAX, st);
      const Ref r = ref_scale(v64, -n, INT64_MIN, INT64_MAX);
      if (got != r.value || st.saturations != (r.saturated ? 1u : 0u))
        bad.add(describe("shl_sat64", v64, 0, n, 0, 0, got, r.value));
    }
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  // The single representable results at the edge: -1 * 2^31 and -1 * 2^63.
  Status st = {0};
  EXPECT_EQ(fx::shl_sat32(-1, 31, INT32_MIN, INT32_MAX, st), INT32_MIN);
  EXPECT_EQ(fx::shl_sat64(-1, 63, INT64_MIN, INT64_MAX, st), INT64_MIN);
  EXPECT_EQ(st.saturations, 0u);
  EXPECT_EQ(fx::shl_sat32(1, 31, INT32_MIN, INT32_MAX, st), INT32_MAX);
  EXPECT_EQ(fx::shl_sat64(-2, 62, INT64_MIN, INT64_MAX, st), INT64_MIN);
  EXPECT_EQ(fx::shl_sat64(-3, 62, INT64_MIN, INT64_MAX, st), INT64_MIN);
  EXPECT_EQ(st.saturations, 2u);  // -2 * 2^62 == INT64_MIN fits; 1 * 2^31 and -3 * 2^62 do not
}

TEST(FixedPointStatus, CounterIsStickyAtMaximum) {
  Status st = {0xFFFFFFFEu};
  fx::count_saturation(st);
  EXPECT_EQ(st.saturations, 0xFFFFFFFFu);
  fx::count_saturation(st);
  EXPECT_EQ(st.saturations, 0xFFFFFFFFu);
}

// --------------------------------------------------------------------------------
// 16-bit words.
// --------------------------------------------------------------------------------

// Every x against 80 coefficients (16 edges + 64 random) in three formats: the usual
// Q15 x Q15 -> Q15 (right shift 15), a right shift of 12, and a left shift of 3.
TEST(FixedPoint16, MulMatchesExactForEveryWordTimesSampledCoefficients) {
  Rng rng(3);
  Mismatches bad;
  long checked = 0, saturations = 0;
  const int formats[][3] = {{15, 15, 15}, {10, 15, 13}, {3, 2, 8}};
  for (const auto& f : formats)
    check_mul16_all_x(coefficient_sample16(rng, 64), f[0], f[1], f[2], bad, checked, saturations);
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_EQ(checked, 3L * 80 * 65536);
  EXPECT_GT(saturations, 0);  // the saturation paths were exercised
  std::printf("[ info     ] mul16: %ld products exhaustive in x, %ld saturated\n", checked, saturations);
}

// Random pairs in random formats, shifts from -24 (left) to +40 (right).
TEST(FixedPoint16, MulMatchesExactForRandomPairsAndFormats) {
  Rng rng(4);
  Mismatches bad;
  long saturations = 0;
  const long n = 2000000;
  for (long i = 0; i < n; ++i) {
    const int16_t x = rng.w16(), c = rng.w16();
    const int qx = rng.uniform_int(-4, 20), qc = rng.uniform_int(-4, 20);
    const int qy = qx + qc - rng.uniform_int(-24, 40);
    Status st = {0};
    const int16_t y = fx::mul16(x, qx, c, qc, qy, st);
    const Ref r = ref_scale(static_cast<i128>(x) * c, qx + qc - qy, INT16_MIN, INT16_MAX);
    if (y != r.value || st.saturations != (r.saturated ? 1u : 0u))
      bad.add(describe("mul16", x, c, qx, qc, qy, y, r.value));
    saturations += r.saturated;
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_GT(saturations, n / 20);
  EXPECT_LT(saturations, n / 2);
}

TEST(FixedPoint16, MulRoundsExactTiesHalfUp) {
  Status st = {0};
  // Q15 x Q15 -> Q15: x * 16384 / 32768 = x / 2.
  EXPECT_EQ(fx::mul16(1, 15, 16384, 15, 15, st), 1);     //  0.5 ->  1
  EXPECT_EQ(fx::mul16(-1, 15, 16384, 15, 15, st), 0);    // -0.5 ->  0
  EXPECT_EQ(fx::mul16(3, 15, 16384, 15, 15, st), 2);     //  1.5 ->  2
  EXPECT_EQ(fx::mul16(-3, 15, 16384, 15, 15, st), -1);   // -1.5 -> -1
  EXPECT_EQ(fx::mul16(-5, 15, 16384, 15, 15, st), -2);   // -2.5 -> -2
  EXPECT_EQ(fx::mul16(5, 15, 16384, 15, 15, st), 3);     //  2.5 ->  3
  // Not ties: -0.5 - 2^-15 rounds down, 0.5 - 2^-15 rounds to 0.
  EXPECT_EQ(fx::mul16(-16385, 15, 1, 0, 0, st), -1);     // -16385 / 32768 = -0.50003
  EXPECT_EQ(fx::mul16(16383, 15, 1, 0, 0, st), 0);       //  0.49997 -> 0
  EXPECT_EQ(fx::mul16(-16384, 15, 1, 0, 0, st), 0);      // -0.5 exactly -> 0
  EXPECT_EQ(fx::mul16(16384, 15, 1, 0, 0, st), 1);       //  0.5 exactly -> 1
  EXPECT_EQ(st.saturations, 0u);
}

TEST(FixedPoint16, MulSaturatesBothWaysAndCounts) {
  Status st = {0};
  // -1 * -1 = +1 is not representable in Q15: saturates to 32767.
  EXPECT_EQ(fx::mul16(INT16_MIN, 15, INT16_MIN, 15, 15, st), INT16_MAX);
  EXPECT_EQ(st.saturations, 1u);
  // -1 * (1 - 2^-15) fits exactly.
  EXPECT_EQ(fx::mul16(INT16_MIN, 15, INT16_MAX, 15, 15, st), -INT16_MAX);
  EXPECT_EQ(st.saturations, 1u);
  // Left shift (Q3 * Q2 -> Q8): 100/8 * 100/4 = 312.5, needs 80000 > 32767 LSBs.
  EXPECT_EQ(fx::mul16(100, 3, 100, 2, 8, st), INT16_MAX);
  EXPECT_EQ(fx::mul16(-100, 3, 100, 2, 8, st), INT16_MIN);
  EXPECT_EQ(st.saturations, 3u);
  // Left shift exactly reaching INT16_MIN is not a saturation: -4096 * 1 * 2^3.
  EXPECT_EQ(fx::mul16(-4096, 3, 1, 2, 8, st), INT16_MIN);
  EXPECT_EQ(fx::mul16(4095, 3, 1, 2, 8, st), 32760);
  EXPECT_EQ(fx::mul16(4096, 3, 1, 2, 8, st), INT16_MAX);
  EXPECT_EQ(st.saturations, 4u);
  // Right shift with rounding that carries past the maximum: 32767.5 -> 32768 -> saturate.
  EXPECT_EQ(fx::mul16(INT16_MAX, 0, 2, 0, -1, st), INT16_MAX);  // exact 32767
  EXPECT_EQ(st.saturations, 4u);
  EXPECT_EQ(fx::narrow16(65535, 1, 0, st), INT16_MAX);  // 32767.5 -> 32768 -> 32767
  EXPECT_EQ(st.saturations, 5u);
  EXPECT_EQ(fx::narrow16(-65537, 1, 0, st), INT16_MIN);  // -32768.5 -> -32768: no saturation
  EXPECT_EQ(st.saturations, 5u);
  EXPECT_EQ(fx::narrow16(-65538, 1, 0, st), INT16_MIN);  // -32769 -> saturate
  EXPECT_EQ(st.saturations, 6u);
}

TEST(FixedPoint16, AddAndSubtractSaturateAndCount) {
  Rng rng(5);
  Mismatches bad;
  long sats = 0;
  const std::vector<int16_t> bs = coefficient_sample16(rng, 16);
  for (const int16_t b : bs) {
    for (int ai = INT16_MIN; ai <= INT16_MAX; ++ai) {
      const int16_t a = static_cast<int16_t>(ai);
      Status st = {0};
      const int16_t s = fx::add16(a, b, st), d = fx::sub16(a, b, st);
      const Ref rs = ref_scale(static_cast<i128>(a) + b, 0, INT16_MIN, INT16_MAX);
      const Ref rd = ref_scale(static_cast<i128>(a) - b, 0, INT16_MIN, INT16_MAX);
      if (s != rs.value || d != rd.value || st.saturations != static_cast<uint32_t>(rs.saturated + rd.saturated))
        bad.add(describe("add16/sub16", a, b, 0, 0, 0, s, rs.value));
      sats += rs.saturated + rd.saturated;
    }
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_GT(sats, 0);
  Status st = {0};
  EXPECT_EQ(fx::add16(INT16_MAX, 1, st), INT16_MAX);
  EXPECT_EQ(fx::add16(INT16_MIN, -1, st), INT16_MIN);
  EXPECT_EQ(fx::sub16(0, INT16_MIN, st), INT16_MAX);
  EXPECT_EQ(fx::sub16(-1, INT16_MIN, st), INT16_MAX);  // exact: 32767, not a saturation
  EXPECT_EQ(st.saturations, 3u);
}

TEST(FixedPoint16, ConvertMatchesExactForEveryWord) {
  Mismatches bad;
  long sats = 0;
  const int qs[] = {-3, 0, 1, 7, 14, 15, 20, 31, 40};
  for (const int qx : qs) {
    for (const int qy : qs) {
      for (int xi = INT16_MIN; xi <= INT16_MAX; ++xi) {
        const int16_t x = static_cast<int16_t>(xi);
        Status st = {0};
        const int16_t y = fx::convert16(x, qx, qy, st);
        const Ref r = ref_scale(x, qx - qy, INT16_MIN, INT16_MAX);
        if (y != r.value || st.saturations != (r.saturated ? 1u : 0u))
          bad.add(describe("convert16", x, 0, qx, 0, qy, y, r.value));
        sats += r.saturated;
      }
    }
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_GT(sats, 0);
  Status st = {0};
  EXPECT_EQ(fx::convert16(3, 2, 1, st), 2);     // 0.75 -> Q1: 1.5 LSB -> 2
  EXPECT_EQ(fx::convert16(-3, 2, 1, st), -1);   // -1.5 LSB -> -1
  EXPECT_EQ(fx::convert16(-16384, 14, 15, st), INT16_MIN);  // -1.0 fits in Q15
  EXPECT_EQ(fx::convert16(16384, 14, 15, st), INT16_MAX);   // +1.0 does not
  EXPECT_EQ(st.saturations, 1u);
}

TEST(FixedPoint16, ClampLimitsWithoutCounting) {
  const int16_t limits[][2] = {{-1000, 2000}, {INT16_MIN, INT16_MAX}, {0, 0}, {-5, -5}, {100, -100}};
  Mismatches bad;
  for (const auto& l : limits) {
    for (int xi = INT16_MIN; xi <= INT16_MAX; ++xi) {
      const int16_t x = static_cast<int16_t>(xi);
      const int want = std::min<int>(std::max<int>(x, l[0]), l[1]);
      const int16_t got = fx::clamp16(x, l[0], l[1]);
      if (got != want) bad.add(describe("clamp16", x, l[0], 0, 0, l[1], got, want));
    }
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_EQ(fx::clamp32(INT32_MAX, -7, 9), 9);
  EXPECT_EQ(fx::clamp32(INT32_MIN, -7, 9), -7);
  EXPECT_EQ(fx::clamp32(3, -7, 9), 3);
  EXPECT_EQ(fx::clamp32(3, 9, -7), -7);  // lo > hi: hi wins
}

// The terms of one accumulation (16- or 32-bit words).
struct Term {
  enum Kind { kMac, kAdd, kSub } kind;
  int64_t x, c;
  int qx, qc;  // qc unused for kAdd/kSub
};

// Step-by-step exact reference of an accumulation with the documented semantics:
// t_i aligned to Q(qacc) (rounded if right-shifted, clamped to the accumulator range if
// left-shifted: [MIN, MAX] for mac/add, [-MAX, MAX] for sub), then the clamped sum.
Ref ref_accumulate(const std::vector<Term>& terms, int qacc, int64_t acc_min, int64_t acc_max,
                   uint32_t* saturations) {
  int64_t acc = 0;
  for (const Term& t : terms) {
    const i128 v = t.kind == Term::kMac ? static_cast<i128>(t.x) * t.c : static_cast<i128>(t.x);
    const int q = t.kind == Term::kMac ? t.qx + t.qc : t.qx;
    const Ref a = ref_scale(v, q - qacc, t.kind == Term::kSub ? -acc_max : acc_min, acc_max);
    *saturations += a.saturated;
    const i128 sum = t.kind == Term::kSub ? static_cast<i128>(acc) - a.value : static_cast<i128>(acc) + a.value;
    const Ref s = ref_scale(sum, 0, acc_min, acc_max);
    *saturations += s.saturated;
    acc = s.value;
  }
  return {acc, false};
}

int32_t run_accumulate16(const std::vector<Term>& terms, int qacc, Status& st) {
  int32_t acc = 0;
  for (const Term& t : terms) {
    const int16_t x = static_cast<int16_t>(t.x);
    if (t.kind == Term::kMac) acc = fx::mac16(acc, x, t.qx, static_cast<int16_t>(t.c), t.qc, qacc, st);
    if (t.kind == Term::kAdd) acc = fx::acc16_add(acc, x, t.qx, qacc, st);
    if (t.kind == Term::kSub) acc = fx::acc16_sub(acc, x, t.qx, qacc, st);
  }
  return acc;
}

int64_t run_accumulate32(const std::vector<Term>& terms, int qacc, Status& st) {
  int64_t acc = 0;
  for (const Term& t : terms) {
    const int32_t x = static_cast<int32_t>(t.x);
    if (t.kind == Term::kMac) acc = fx::mac32(acc, x, t.qx, static_cast<int32_t>(t.c), t.qc, qacc, st);
    if (t.kind == Term::kAdd) acc = fx::acc32_add(acc, x, t.qx, qacc, st);
    if (t.kind == Term::kSub) acc = fx::acc32_sub(acc, x, t.qx, qacc, st);
  }
  return acc;
}

// A random accumulation of 1..8 terms whose formats are all <= qacc (exact alignment by
// left shifts) and whose magnitudes satisfy the headroom rule (G): sum |t_i| <= 2^(A-1)-1.
std::vector<Term> exact_terms(Rng& rng, int bits, int qacc) {
  const int count = rng.uniform_int(1, 8);
  const int guard = count <= 1 ? 0 : (count <= 3 ? 1 : (count <= 7 ? 2 : 3));  // ceil(log2(N+1)) - 1
  std::vector<Term> terms;
  for (int i = 0; i < count; ++i) {
    Term t;
    const int kind = rng.uniform_int(0, 3);
    t.kind = kind <= 1 ? Term::kMac : (kind == 2 ? Term::kAdd : Term::kSub);
    const int up = rng.uniform_int(0, 5);  // left shift of the term into Q(qacc)
    if (t.kind == Term::kMac) {
      // |x| <= 2^(bits-1), |c| <= 2^(bits-1-up-guard): |t| <= 2^(2 bits - 2 - guard).
      t.x = rng.word(bits);
      t.c = rng.word(bits) >> (up + guard);
      t.qx = rng.uniform_int(-2, bits - 1);
      t.qc = qacc - up - t.qx;
    } else {
      // |x| <= 2^(bits-1), left shift <= bits-1-guard: |t| <= 2^(2 bits - 2 - guard).
      t.x = rng.word(bits);
      t.c = 0;
      t.qx = qacc - rng.uniform_int(0, bits - 1 - guard);
    }
    terms.push_back(t);
  }
  return terms;
}

TEST(FixedPoint16, AccumulateThenNarrowEqualsExactRoundedSum) {
  Rng rng(6);
  Mismatches bad;
  long accumulations = 0;
  for (int i = 0; i < 200000; ++i) {
    const int qacc = rng.uniform_int(10, 34);
    const std::vector<Term> terms = exact_terms(rng, 16, qacc);
    i128 exact = 0;  // the exact sum in Q(qacc)
    for (const Term& t : terms) {
      const int q = t.kind == Term::kMac ? t.qx + t.qc : t.qx;
      const i128 v = (t.kind == Term::kMac ? static_cast<i128>(t.x) * t.c : static_cast<i128>(t.x)) *
                     (static_cast<i128>(1) << (qacc - q));
      exact += t.kind == Term::kSub ? -v : v;
    }
    Status st = {0};
    const int32_t acc = run_accumulate16(terms, qacc, st);
    const int qy = qacc - rng.uniform_int(-3, 24);
    const int16_t y = fx::narrow16(acc, qacc, qy, st);
    const Ref r = ref_scale(exact, qacc - qy, INT16_MIN, INT16_MAX);
    if (acc != exact || y != r.value || st.saturations != (r.saturated ? 1u : 0u))
      bad.add(describe("accumulate16+narrow16", static_cast<int64_t>(exact), acc, qacc, 0, qy, y, r.value));
    ++accumulations;
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
}

// Per-term rounding (qacc below the product formats) follows the documented step-by-step
// semantics exactly, and stays within N/2 LSB(acc) + 1/2 LSB(y) of the exact real sum.
TEST(FixedPoint16, AccumulateWithRoundedTermsMatchesSemanticsAndErrorBound) {
  Rng rng(7);
  Mismatches bad, bound;
  for (int i = 0; i < 200000; ++i) {
    const int count = rng.uniform_int(1, 7);
    const int qacc = rng.uniform_int(8, 26);
    std::vector<Term> terms;
    long double exact_real = 0;
    for (int k = 0; k < count; ++k) {
      Term t;
      t.kind = rng.uniform_int(0, 2) ? Term::kMac : (rng.uniform_int(0, 1) ? Term::kAdd : Term::kSub);
      t.x = rng.w16();
      t.c = rng.w16();
      const int down = rng.uniform_int(0, 12);
      t.qx = t.kind == Term::kMac ? rng.uniform_int(0, 15) : qacc + down;
      t.qc = qacc + down + 2 - t.qx;  // products are at least 2 bits finer than Q(qacc): 2 guard bits
      const long double v = t.kind == Term::kMac
                                ? static_cast<long double>(t.x) * t.c * std::ldexp(1.0L, -(t.qx + t.qc))
                                : static_cast<long double>(t.x) * std::ldexp(1.0L, -t.qx);
      exact_real += t.kind == Term::kSub ? -v : v;
      terms.push_back(t);
    }
    uint32_t ref_sats = 0;
    const Ref want = ref_accumulate(terms, qacc, INT32_MIN, INT32_MAX, &ref_sats);
    Status st = {0};
    const int32_t acc = run_accumulate16(terms, qacc, st);
    if (acc != want.value || st.saturations != ref_sats)
      bad.add(describe("accumulate16 rounded", acc, 0, qacc, 0, 0, acc, want.value));
    EXPECT_EQ(ref_sats, 0u);  // 2 guard bits, <= 7 terms: the headroom rule holds
    const int qy = qacc - rng.uniform_int(0, 12);
    const int16_t y = fx::narrow16(acc, qacc, qy, st);
    if (st.saturations == 0) {
      const long double err = std::fabs(static_cast<long double>(y) * std::ldexp(1.0L, -qy) - exact_real);
      const long double tol = count * 0.5L * std::ldexp(1.0L, -qacc) + 0.5L * std::ldexp(1.0L, -qy);
      if (err > tol) bound.add(describe("rounded accumulation error bound", acc, 0, qacc, 0, qy, y, 0));
    }
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_EQ(bound.count, 0) << bound.first;
}

// The headroom rule: N = 2^(g+1) - 1 worst-case terms fit with g guard bits; one more
// overflows, and the overflow is clamped and counted, never silent.
TEST(FixedPoint16, HeadroomRuleWorstCaseFitsAndOneMoreTermIsCounted) {
  for (int g = 0; g <= 5; ++g) {
    const int qacc = 30 - g;  // Q15 x Q15 products are Q30
    const int n = (1 << (g + 1)) - 1;
    Status st = {0};
    int32_t up = 0, down = 0;
    for (int i = 0; i < n; ++i) {
      up = fx::mac16(up, INT16_MIN, 15, INT16_MIN, 15, qacc, st);    // +2^30 each (largest product)
      down = fx::mac16(down, INT16_MIN, 15, INT16_MAX, 15, qacc, st);  // most negative product
    }
    EXPECT_EQ(st.saturations, 0u) << "g = " << g;
    EXPECT_EQ(up, static_cast<int64_t>(n) << (30 - g));
    EXPECT_EQ(down, -(static_cast<int64_t>(n) * ((INT64_C(1) << 30) - (1 << 15)) >> g));
    up = fx::mac16(up, INT16_MIN, 15, INT16_MIN, 15, qacc, st);  // would be 2^31: overflow
    EXPECT_EQ(up, INT32_MAX);
    EXPECT_EQ(st.saturations, 1u) << "g = " << g;
    // The negative side has one product of room more (-(2^30 - 2^15) each): n + 2 overflow.
    down = fx::mac16(down, INT16_MIN, 15, INT16_MAX, 15, qacc, st);
    EXPECT_EQ(st.saturations, 1u) << "g = " << g;
    down = fx::mac16(down, INT16_MIN, 15, INT16_MAX, 15, qacc, st);
    EXPECT_EQ(down, INT32_MIN);
    EXPECT_EQ(st.saturations, 2u) << "g = " << g;
  }
  // Subtraction past the minimum is clamped and counted too.
  Status st = {0};
  int32_t acc = INT32_MIN + 5;
  acc = fx::acc16_sub(acc, 5, 0, 0, st);
  EXPECT_EQ(acc, INT32_MIN);
  EXPECT_EQ(st.saturations, 0u);
  acc = fx::acc16_sub(acc, 1, 0, 0, st);
  EXPECT_EQ(acc, INT32_MIN);
  EXPECT_EQ(st.saturations, 1u);
  acc = fx::acc16_add(INT32_MAX - 1, 1, 0, 0, st);
  EXPECT_EQ(acc, INT32_MAX);
  acc = fx::acc16_add(acc, 1, 0, 0, st);
  EXPECT_EQ(acc, INT32_MAX);
  EXPECT_EQ(st.saturations, 2u);
}

// --------------------------------------------------------------------------------
// 32-bit words.
// --------------------------------------------------------------------------------

TEST(FixedPoint32, MulMatchesExactForRandomPairsAndFormats) {
  Rng rng(8);
  Mismatches bad;
  long saturations = 0, left = 0;
  const long n = 2000000;
  for (long i = 0; i < n; ++i) {
    const int32_t x = rng.w32(), c = rng.w32();
    const int qx = rng.uniform_int(-8, 40), qc = rng.uniform_int(-8, 40);
    const int shift = rng.uniform_int(-40, 70);
    const int qy = qx + qc - shift;
    Status st = {0};
    const int32_t y = fx::mul32(x, qx, c, qc, qy, st);
    const Ref r = ref_scale(static_cast<i128>(x) * c, shift, INT32_MIN, INT32_MAX);
    if (y != r.value || st.saturations != (r.saturated ? 1u : 0u))
      bad.add(describe("mul32", x, c, qx, qc, qy, y, r.value));
    saturations += r.saturated;
    left += shift < 0;
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_GT(saturations, n / 20);
  EXPECT_GT(left, n / 10);
}

// Every pair of edge values in every shift from -33 to 65.
TEST(FixedPoint32, MulMatchesExactForAllEdgePairsAndShifts) {
  const int32_t e[] = {INT32_MIN, INT32_MIN + 1, -1073741825, -1073741824, -65536, -3, -2, -1, 0,
                       1,         2,             3,           65535,       65536,  1073741824, INT32_MAX - 1,
                       INT32_MAX};
  Mismatches bad;
  for (const int32_t x : e)
    for (const int32_t c : e)
      for (int shift = -33; shift <= 65; ++shift) {
        Status st = {0};
        const int32_t y = fx::mul32(x, 31, c, 31, 62 - shift, st);
        const Ref r = ref_scale(static_cast<i128>(x) * c, shift, INT32_MIN, INT32_MAX);
        if (y != r.value || st.saturations != (r.saturated ? 1u : 0u))
          bad.add(describe("mul32", x, c, 31, 31, 62 - shift, y, r.value));
      }
  EXPECT_EQ(bad.count, 0) << bad.first;
}

TEST(FixedPoint32, MulRoundsExactTiesHalfUpAndSaturates) {
  Status st = {0};
  const int32_t half = 1 << 30;  // 0.5 in Q31
  EXPECT_EQ(fx::mul32(1, 31, half, 31, 31, st), 1);     //  0.5 LSB ->  1
  EXPECT_EQ(fx::mul32(-1, 31, half, 31, 31, st), 0);    // -0.5 LSB ->  0
  EXPECT_EQ(fx::mul32(-3, 31, half, 31, 31, st), -1);   // -1.5 LSB -> -1
  EXPECT_EQ(fx::mul32(3, 31, half, 31, 31, st), 2);     //  1.5 LSB ->  2
  EXPECT_EQ(fx::mul32(-5, 31, half, 31, 31, st), -2);   // -2.5 LSB -> -2
  EXPECT_EQ(st.saturations, 0u);
  EXPECT_EQ(fx::mul32(INT32_MIN, 31, INT32_MIN, 31, 31, st), INT32_MAX);  // (-1)(-1) = 1
  EXPECT_EQ(st.saturations, 1u);
  EXPECT_EQ(fx::mul32(INT32_MIN, 31, INT32_MAX, 31, 31, st), -INT32_MAX);
  EXPECT_EQ(fx::mul32(-65536, 0, 32768, 0, 0, st), INT32_MIN);  // exactly -2^31: fits
  EXPECT_EQ(st.saturations, 1u);
  EXPECT_EQ(fx::mul32(-65536, 0, 32769, 0, 0, st), INT32_MIN);
  EXPECT_EQ(fx::mul32(65536, 0, 32768, 0, 0, st), INT32_MAX);
  EXPECT_EQ(fx::mul32(1, 0, 1, 0, 31, st), INT32_MAX);   // left shift 31 of +1
  EXPECT_EQ(fx::mul32(-1, 0, 1, 0, 31, st), INT32_MIN);  // -2^31: fits
  EXPECT_EQ(st.saturations, 4u);
}

TEST(FixedPoint32, ConvertAddSubMatchExact) {
  Rng rng(9);
  Mismatches bad;
  for (int i = 0; i < 1000000; ++i) {
    const int32_t a = rng.w32(), b = rng.w32();
    const int qx = rng.uniform_int(-8, 40), qy = rng.uniform_int(-8, 40);
    Status st = {0};
    const int32_t y = fx::convert32(a, qx, qy, st);
    const Ref r = ref_scale(a, qx - qy, INT32_MIN, INT32_MAX);
    if (y != r.value || st.saturations != (r.saturated ? 1u : 0u))
      bad.add(describe("convert32", a, 0, qx, 0, qy, y, r.value));
    Status st2 = {0};
    const int32_t s = fx::add32(a, b, st2), d = fx::sub32(a, b, st2);
    const Ref rs = ref_scale(static_cast<i128>(a) + b, 0, INT32_MIN, INT32_MAX);
    const Ref rd = ref_scale(static_cast<i128>(a) - b, 0, INT32_MIN, INT32_MAX);
    if (s != rs.value || d != rd.value || st2.saturations != static_cast<uint32_t>(rs.saturated + rd.saturated))
      bad.add(describe("add32/sub32", a, b, 0, 0, 0, s, rs.value));
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  Status st = {0};
  EXPECT_EQ(fx::add32(INT32_MAX, 1, st), INT32_MAX);
  EXPECT_EQ(fx::sub32(INT32_MIN, 1, st), INT32_MIN);
  EXPECT_EQ(fx::sub32(0, INT32_MIN, st), INT32_MAX);
  EXPECT_EQ(fx::convert32(-1073741824, 30, 31, st), INT32_MIN);  // -1.0 fits in Q31
  EXPECT_EQ(fx::convert32(1073741824, 30, 31, st), INT32_MAX);   // +1.0 does not
  EXPECT_EQ(st.saturations, 4u);
}

// Mixed words (a 16-bit program's 32-bit states): a 32-bit word or a 64-bit accumulator
// narrowed to a 16-bit word, rounded half up and saturated, counted once.
TEST(FixedPointMixed, ConvertAndNarrowTo16BitsMatchExact) {
  Rng rng(12);
  Mismatches bad;
  long sats = 0;
  for (int i = 0; i < 1000000; ++i) {
    const int32_t a = rng.w32();
    const int64_t v = rng.word(64) >> rng.uniform_int(0, 63);  // of random magnitude
    const int qx = rng.uniform_int(-8, 60), qy = rng.uniform_int(-8, 40);
    Status st = {0};
    const int16_t y = fx::convert32_16(a, qx, qy, st);
    const Ref r = ref_scale(a, qx - qy, INT16_MIN, INT16_MAX);
    if (y != r.value || st.saturations != (r.saturated ? 1u : 0u))
      bad.add(describe("convert32_16", a, 0, qx, 0, qy, y, r.value));
    Status st2 = {0};
    const int16_t z = fx::narrow32_16(v, qx, qy, st2);
    const Ref rz = ref_scale(v, qx - qy, INT16_MIN, INT16_MAX);
    if (z != rz.value || st2.saturations != (rz.saturated ? 1u : 0u))
      bad.add(describe("narrow32_16", v, 0, qx, 0, qy, z, rz.value));
    sats += r.saturated + rz.saturated;
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_GT(sats, 1000);
  Status st = {0};
  EXPECT_EQ(fx::convert32_16(3 << 16, 18, 1, st), 2);     // 0.75 -> Q1: 1.5 LSB -> 2
  EXPECT_EQ(fx::convert32_16(-(3 << 16), 18, 1, st), -1); // -1.5 LSB -> -1
  EXPECT_EQ(fx::narrow32_16(-(INT64_C(1) << 55), 55, 15, st), INT16_MIN);  // -1.0 fits in Q15
  EXPECT_EQ(fx::narrow32_16(INT64_C(1) << 55, 55, 15, st), INT16_MAX);     // +1.0 does not
  EXPECT_EQ(fx::narrow32_16(INT64_C(1), 0, 20, st), INT16_MAX);          // an exact left shift that saturates
  EXPECT_EQ(st.saturations, 2u);
}

TEST(FixedPoint32, AccumulateThenNarrowEqualsExactRoundedSum) {
  Rng rng(10);
  Mismatches bad;
  for (int i = 0; i < 200000; ++i) {
    const int qacc = rng.uniform_int(30, 66);
    const std::vector<Term> terms = exact_terms(rng, 32, qacc);
    i128 exact = 0;
    for (const Term& t : terms) {
      const int q = t.kind == Term::kMac ? t.qx + t.qc : t.qx;
      const i128 v = (t.kind == Term::kMac ? static_cast<i128>(t.x) * t.c : static_cast<i128>(t.x)) *
                     (static_cast<i128>(1) << (qacc - q));
      exact += t.kind == Term::kSub ? -v : v;
    }
    Status st = {0};
    const int64_t acc = run_accumulate32(terms, qacc, st);
    const int qy = qacc - rng.uniform_int(-3, 40);
    const int32_t y = fx::narrow32(acc, qacc, qy, st);
    const Ref r = ref_scale(exact, qacc - qy, INT32_MIN, INT32_MAX);
    if (acc != exact || y != r.value || st.saturations != (r.saturated ? 1u : 0u))
      bad.add(describe("accumulate32+narrow32", static_cast<int64_t>(exact), acc, qacc, 0, qy, y, r.value));
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
}

TEST(FixedPoint32, AccumulateWithRoundedTermsMatchesSemantics) {
  Rng rng(11);
  Mismatches bad;
  long sats = 0;
  for (int i = 0; i < 200000; ++i) {
    const int count = rng.uniform_int(1, 9);
    const int qacc = rng.uniform_int(20, 62);
    std::vector<Term> terms;
    for (int k = 0; k < count; ++k) {
      Term t;
      t.kind = rng.uniform_int(0, 2) ? Term::kMac : (rng.uniform_int(0, 1) ? Term::kAdd : Term::kSub);
      t.x = rng.w32();
      t.c = rng.w32();
      t.qx = rng.uniform_int(-4, 40);
      t.qc = qacc + rng.uniform_int(-4, 20) - t.qx;  // mostly rounded, sometimes left-shifted
      terms.push_back(t);
    }
    uint32_t ref_sats = 0;
    const Ref want = ref_accumulate(terms, qacc, INT64_MIN, INT64_MAX, &ref_sats);
    Status st = {0};
    const int64_t acc = run_accumulate32(terms, qacc, st);
    if (acc != want.value || st.saturations != ref_sats)
      bad.add(describe("accumulate32 rounded", acc, st.saturations, qacc, 0, 0, acc, want.value));
    sats += ref_sats;
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_GT(sats, 0);  // overflow paths (beyond the headroom rule) were exercised
}

TEST(FixedPoint32, HeadroomRuleWorstCaseFitsAndOneMoreTermIsCounted) {
  for (int g = 0; g <= 5; ++g) {
    const int qacc = 62 - g;  // Q31 x Q31 products are Q62; INT32_MIN^2 = 2^62
    const int n = (1 << (g + 1)) - 1;
    Status st = {0};
    int64_t up = 0, down = 0;
    for (int i = 0; i < n; ++i) {
      up = fx::mac32(up, INT32_MIN, 31, INT32_MIN, 31, qacc, st);
      down = fx::mac32(down, INT32_MIN, 31, INT32_MAX, 31, qacc, st);
    }
    EXPECT_EQ(st.saturations, 0u) << "g = " << g;
    EXPECT_EQ(up, static_cast<int64_t>(n) << (62 - g));
    EXPECT_EQ(down, -(static_cast<int64_t>(n) * ((INT64_C(1) << (62 - g)) - (INT64_C(1) << (31 - g)))));
    up = fx::mac32(up, INT32_MIN, 31, INT32_MIN, 31, qacc, st);  // would be 2^63: overflow
    EXPECT_EQ(up, INT64_MAX);
    EXPECT_EQ(st.saturations, 1u) << "g = " << g;
    down = fx::mac32(down, INT32_MIN, 31, INT32_MAX, 31, qacc, st);
    EXPECT_EQ(st.saturations, 1u) << "g = " << g;
    down = fx::mac32(down, INT32_MIN, 31, INT32_MAX, 31, qacc, st);
    EXPECT_EQ(down, INT64_MIN);
    EXPECT_EQ(st.saturations, 2u) << "g = " << g;
  }
  Status st = {0};
  EXPECT_EQ(fx::acc32_sub(INT64_MIN + 1, 1, 0, 0, st), INT64_MIN);
  EXPECT_EQ(fx::acc32_sub(INT64_MIN, 1, 0, 0, st), INT64_MIN);
  EXPECT_EQ(fx::acc32_add(INT64_MAX, 1, 0, 0, st), INT64_MAX);
  EXPECT_EQ(fx::acc32_add(INT64_MIN, -1, 0, 0, st), INT64_MIN);
  EXPECT_EQ(st.saturations, 3u);
  EXPECT_EQ(fx::narrow32(INT64_MAX, 62, 31, st), INT32_MAX);  // 2^63 / 2^31 = 2^32: saturate
  EXPECT_EQ(fx::narrow32(INT64_MIN, 62, 30, st), INT32_MIN);  // -2^31: fits exactly
  EXPECT_EQ(st.saturations, 4u);
}

// --------------------------------------------------------------------------------
// Host-side quantise / dequantise.
// --------------------------------------------------------------------------------

// Exact round-half-up reference on doubles: floor is exact and s - floor(s) is exact.
int64_t ref_quantize(double s) {
  const double f = std::floor(s);
  return static_cast<int64_t>(f) + (s - f >= 0.5 ? 1 : 0);
}

TEST(FixedPointHost, QuantizeOfDequantizeIsIdentityForEveryWord) {
  Mismatches bad;
  const int qs[] = {-3, 0, 7, 15, 20};
  for (const int q : qs)
    for (int xi = INT16_MIN; xi <= INT16_MAX; ++xi) {
      const int16_t x = static_cast<int16_t>(xi);
      Status st = {0};
      const double v = fx::dequantize16(x, q);
      if (v != std::ldexp(static_cast<double>(x), -q)) bad.add("dequantize16 not exact");
      const int16_t back = fx::quantize16(v, q, st);
      if (back != x || st.saturations != 0u) bad.add(describe("quantize16", x, 0, q, 0, q, back, x));
    }
  Rng rng(12);
  for (int i = 0; i < 200000; ++i) {
    const int32_t x = rng.w32();
    const int q = rng.uniform_int(-10, 60);
    Status st = {0};
    const double v = fx::dequantize32(x, q);
    const int32_t back = fx::quantize32(v, q, st);
    if (v != std::ldexp(static_cast<double>(x), -q) || back != x || st.saturations != 0u)
      bad.add(describe("quantize32", x, 0, q, 0, q, back, x));
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
}

TEST(FixedPointHost, QuantizeRoundsHalfUpWithinHalfLsbAndSaturates) {
  Rng rng(13);
  Mismatches bad;
  long in_range = 0;
  for (int i = 0; i < 1000000; ++i) {
    const int q = rng.uniform_int(-4, 40);
    const bool wide = i % 2;
    const double lim = std::ldexp(wide ? 2147483648.0 : 32768.0, -q);
    // Uniform in [-1.25 lim, 1.25 lim], and every 4th value an exact tie or a neighbour.
    double v = (std::ldexp(static_cast<double>(rng.next() >> 11), -53) * 2.5 - 1.25) * lim;
    if (i % 4 == 0) {
      const double lsb = std::ldexp(1.0, -q);
      v = (std::floor(v / lsb) + 0.5) * lsb;
      if (i % 8 == 0) v = std::nextafter(v, (i % 16 == 0) ? 1e300 : -1e300);
    }
    const double s = std::ldexp(v, q);
    const int64_t lo = wide ? INT32_MIN : INT16_MIN, hi = wide ? INT32_MAX : INT16_MAX;
    int64_t want = ref_quantize(s);
    const bool sat = want > hi || want < lo;
    want = std::min(std::max(want, lo), hi);
    Status st = {0};
    const int64_t got = wide ? fx::quantize32(v, q, st) : fx::quantize16(v, q, st);
    if (got != want || st.saturations != (sat ? 1u : 0u))
      bad.add(describe(wide ? "quantize32" : "quantize16", static_cast<int64_t>(s), 0, q, 0, q, got, want));
    if (!sat) {
      ++in_range;
      const double back = wide ? fx::dequantize32(static_cast<int32_t>(got), q)
                               : fx::dequantize16(static_cast<int16_t>(got), q);
      if (std::fabs(back - v) > 0.5 * std::ldexp(1.0, -q)) bad.add("round trip beyond 1/2 LSB");
    }
  }
  EXPECT_EQ(bad.count, 0) << bad.first;
  EXPECT_GT(in_range, 500000);

  Status st = {0};
  EXPECT_EQ(fx::quantize16(0.5 / 32768, 15, st), 1);     //  1/2 LSB -> 1
  EXPECT_EQ(fx::quantize16(-0.5 / 32768, 15, st), 0);    // -1/2 LSB -> 0
  EXPECT_EQ(fx::quantize16(-1.5 / 32768, 15, st), -1);   // -3/2 LSB -> -1
  EXPECT_EQ(fx::quantize16(2.5, 0, st), 3);
  EXPECT_EQ(fx::quantize16(-2.5, 0, st), -2);
  EXPECT_EQ(fx::quantize16(0.49999999999999994, 0, st), 0);  // the classic floor(x + 0.5) trap
  EXPECT_EQ(fx::quantize16(-0.5000000000000001, 0, st), -1);
  EXPECT_EQ(fx::quantize16(-1.0, 15, st), INT16_MIN);                    // exact, no saturation
  EXPECT_EQ(fx::quantize16(-1.0 - 0.5 / 32768, 15, st), INT16_MIN);      // -32768.5 -> -32768
  EXPECT_EQ(fx::quantize16(32767.49, 0, st), INT16_MAX);
  EXPECT_EQ(fx::quantize32(-1.0, 31, st), INT32_MIN);
  EXPECT_EQ(fx::quantize32(2147483646.5, 0, st), INT32_MAX);
  EXPECT_EQ(st.saturations, 0u);
  EXPECT_EQ(fx::quantize16(1.0, 15, st), INT16_MAX);                     // +1 is not in Q15
  EXPECT_EQ(fx::quantize16(32767.5, 0, st), INT16_MAX);
  EXPECT_EQ(fx::quantize16(-32769.0, 0, st), INT16_MIN);
  EXPECT_EQ(fx::quantize32(2147483647.5, 0, st), INT32_MAX);
  EXPECT_EQ(fx::quantize32(1e300, 0, st), INT32_MAX);
  EXPECT_EQ(fx::quantize32(-std::numeric_limits<double>::infinity(), 10, st), INT32_MIN);
  EXPECT_EQ(st.saturations, 6u);
  EXPECT_EQ(fx::quantize16(std::numeric_limits<double>::quiet_NaN(), 15, st), 0);
  EXPECT_EQ(fx::quantize32(std::numeric_limits<double>::quiet_NaN(), 15, st), 0);
  EXPECT_EQ(st.saturations, 8u);
  EXPECT_EQ(fx::dequantize16(INT16_MIN, 15), -1.0);
  EXPECT_EQ(fx::dequantize32(3, -2), 12.0);
  EXPECT_EQ(fx::dequantize_acc32(INT64_C(3) << 40, 41), 1.5);
  EXPECT_EQ(fx::pow2(-1074), std::ldexp(1.0, -1074));
  EXPECT_EQ(fx::pow2(1023), std::ldexp(1.0, 1023));
}

// --------------------------------------------------------------------------------
// The fragment itself: nothing that would break pasting it into a namespace of a
// self-contained, allocation-free, exception-free header.
// --------------------------------------------------------------------------------

TEST(FixedPointSource, ContainsNoDirectiveAllocationExceptionOrLibraryUse) {
  std::ifstream in(FX_INC_PATH);
  ASSERT_TRUE(in.good()) << "cannot read " << FX_INC_PATH;
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  ASSERT_GT(text.size(), 1000u);

  // No preprocessor directive at all: #include would nest a header inside the
  // generated namespace, and a #define would leak to global scope.
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    const size_t first = line.find_first_not_of(" \t");
    if (first != std::string::npos) {
      EXPECT_NE(line[first], '#') << "line " << number << ": " << line;
    }
  }
  EXPECT_EQ(text.find("#include"), std::string::npos);
  EXPECT_EQ(text.find("std::"), std::string::npos);
  EXPECT_EQ(text.find("::std"), std::string::npos);

  // Forbidden identifiers anywhere (comments included), as whole tokens.
  const std::set<std::string> forbidden = {"new",     "delete", "throw",   "try",    "catch",
                                           "virtual", "typeid", "dynamic_cast", "malloc", "calloc",
                                           "realloc", "operator", "using",  "asm",    "goto",
                                           "std",     "extern"};
  std::string token;
  for (size_t i = 0; i <= text.size(); ++i) {
    const char ch = i < text.size() ? text[i] : ' ';
    if ((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_') {
      token += ch;
    } else {
      if (!token.empty()) {
        EXPECT_EQ(forbidden.count(token), 0u) << "forbidden token '" << token << "'";
      }
      token.clear();
    }
  }
  // Nothing with static storage that is not a function or type: every definition is
  // an inline function, a typedef, a struct or a static_assert.
  EXPECT_EQ(text.find("static "), std::string::npos) << "no static variables/functions, only inline";
}

}  // namespace
