#pragma once
// Root locus data: the closed-loop poles of k G in negative feedback over gains k
// (python-control's root_locus_map, MATLAB's rlocus).
#include <vector>

#include "dmbd/blocks/schur_exponential.hpp"
#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks {

// Row i: the roots of den + k_i num (the closed loop of k_i G, G = num/den, in negative
// feedback), one column per branch (order of G columns). Where den + k num loses degree
// (deg num = deg den, k = -lead den / lead num) the lost roots are +inf. Row 0 is sorted as
// sort_roots; each further row is matched to the row before it, root by root, each to the
// nearest remaining branch (python-control's _RLSortRoots), so a column follows a branch
// as long as the gains are dense enough. InputError for an improper G or a gain that is
// not finite.
ComplexMatrix root_locus(const TransferFunction& g, const std::vector<double>& gains);

// The same for the transfer of a SISO state-space model: the eigenvalues of
// A - k B (1 + k D)^-1 C (no polynomial is formed); where 1 + k D is 0 to rounding
// (4 eps) the roots of its transfer function's den + k num. A root going to infinity
// there is +inf, or very large when D is only near -1/k. InputError unless the model has one input and one output.
ComplexMatrix root_locus(const StateSpace& g, const std::vector<double>& gains);

// Gains that show the locus: 0 and 200 gains log-spaced over six decades around
// k0 = 1 / |G(j w0)| (w0 the geometric mean of the magnitudes of G's non-zero poles and
// zeros, or 1; on the unit circle when discrete): the poles start at G's poles and
// approach its zeros and asymptotes.
std::vector<double> default_root_locus_gains(const TransferFunction& g);

}  // namespace dmbd::blocks
