#pragma once
// Time delays.
#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks {

// Padé approximant of e^{-s T} of the given order (numerator and denominator of that
// degree): N(s)/N(-s), N(s) = sum_k (2n-k)! n! / ((2n)! k! (n-k)!) (-s T)^k.
// Order 0 (or T = 0) is the unit gain. InputError for T < 0 (seconds) or an order outside
// 0..20.
TransferFunction pade(double delay_s, int order);
// z^-n with sample time ts (n whole samples of ts seconds). InputError for ts <= 0 or
// n < 0.
TransferFunction sample_delay(int n, double ts);
// Thiran all-pass fractional delay of `order` for a delay of `delay_samples` samples
// (maximally flat group delay at DC); an integer delay == order is exactly z^-order.
// InputError for ts <= 0, an order outside 1..20, or delay_samples <= order - 1 (where
// the filter would not be stable).
TransferFunction thiran(double delay_samples, int order, double ts);

}  // namespace dmbd::blocks
