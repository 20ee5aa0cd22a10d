// The dense Cholesky factor and its solve (dmbd/base/dense_cholesky.hpp).
#include "dmbd/base/dense_cholesky.hpp"

#include <cmath>

#include "dmbd/base/vector_clones.hpp"

namespace dmbd::base {

namespace {

// y[i] -= l0 x0[i], then l1 x1[i], l2 x2[i], l3 x3[i] (each element in that order, so the
// result is that of four single updates); the columns never overlap.
inline void update4(double* __restrict y, const double* __restrict x0, const double* __restrict x1, const double* __restrict x2,
             const double* __restrict x3, double l0, double l1, double l2, double l3, std::ptrdiff_t m) {
  for (std::ptrdiff_t i = 0; i < m; ++i) {
    double v = y[i];
    v -= l0 * x0[i];
    v -= l1 * x1[i];
    v -= l2 * x2[i];
    v -= l3 * x3[i];
    y[i] = v;
  }
}

inline void update1(double* __restrict y, const double* __restrict x, double l, std::ptrdiff_t m) {
  for (std::ptrdiff_t i = 0; i < m; ++i) y[i] -= l * x[i];
}

}  // namespace

// Column j of L: v = A(j:n, j) - sum over k < j of L(j, k) L(j:n, k), then v / sqrt(v_j).
DMBD_VECTOR_CLONES bool cholesky_in_place(double* a, std::ptrdiff_t lda, std::ptrdiff_t n, double* inv_diag) {
  for (std::ptrdiff_t j = 0; j < n; ++j) {
    double* cj = a + j * lda;
    const std::ptrdiff_t m = n - j;  // rows j..n-1
    std::ptrdiff_t k = 0;
    for (; k + 4 <= j; k += 4) {
      const double *c0 = a + k * lda + j, *c1 = c0 + lda, *c2 = c1 + lda, *c3 = c2 + lda;
      update4(cj + j, c0, c1, c2, c3, c0[0], c1[0], c2[0], c3[0], m);
    }
    for (; k < j; ++k) update1(cj + j, a + k * lda + j, a[k * lda + j], m);
    const double d = cj[j];
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double s = std::sqrt(d), r = 1.0 / s;
    cj[j] = s;
    inv_diag[j] = r;
    for (std::ptrdiff_t i = j + 1; i < n; ++i) cj[i] *= r;
  }
  return true;
}

// The solves multiply by the diagonal's reciprocals (no division on the chain from one
// unknown to the next), and Lᵀ x = y takes its dot products in four partial sums (a
// column of L against the unknowns below: one long dependent chain of multiply-adds
// otherwise, latency-bound; perf had the solve at half the factorisation's time).
DMBD_VECTOR_CLONES void cholesky_solve_in_place(const double* l, std::ptrdiff_t lda, std::ptrdiff_t n, const double* r,
                                                double* x) {
  for (std::ptrdiff_t j = 0; j < n; ++j) {  // L y = b, a column at a time
    const double* cj = l + j * lda;
    const double yj = x[j] * r[j];
    x[j] = yj;
    for (std::ptrdiff_t i = j + 1; i < n; ++i) x[i] -= yj * cj[i];
  }
  for (std::ptrdiff_t j = n - 1; j >= 0; --j) {  // Lᵀ x = y: row j of Lᵀ is column j of L
    const double* cj = l + j * lda;
    double s0 = x[j], s1 = 0.0, s2 = 0.0, s3 = 0.0;
    std::ptrdiff_t i = j + 1;
    for (; i + 4 <= n; i += 4) {
      s0 -= cj[i] * x[i];
      s1 -= cj[i + 1] * x[i + 1];
      s2 -= cj[i + 2] * x[i + 2];
      s3 -= cj[i + 3] * x[i + 3];
    }
    for (; i < n; ++i) s0 -= cj[i] * x[i];
    x[j] = ((s0 + s1) + (s2 + s3)) * r[j];
  }
}

}  // namespace dmbd::base
