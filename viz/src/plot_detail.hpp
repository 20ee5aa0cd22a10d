#pragma once
// Internals shared by the viz sources (not installed, not part of the API).
#include <utility>
#include <vector>

namespace dmbd::viz::detail {

// 10^k, exact for |k| <= 22 (1/10^-k correctly rounded for negative k).
double pow10(int k);

// m * 10^e for integer-valued m, rounded once (3 * 0.2 -> 0.6, not 0.6000000000000001).
double scaled(double m, int e);
// A 1-2-5 step as mantissa (1, 2 or 5) and exponent.
std::pair<double, int> split_step(double step);

// The 1-2-5 x 10^k step for splitting `range` (> 0) into at most max_intervals parts;
// 0 when no finite step exists.
double nice_step(double range, int max_intervals);

// k * step, computed as (k * m) * 10^e when step is m * 10^e with integer m, so that
// 11 * 0.1 gives 1.1 rather than 1.1000000000000001.
double multiple_of(double k, double step);

// Multiples k*step within [lo, hi] (lo <= hi), with k*step computed so that values
// such as 0.6 come out as the nearest double; at most max_count of them (empty if
// more would be needed).
std::vector<double> multiples_within(double lo, double hi, double step, int max_count);

}  // namespace dmbd::viz::detail
