#include "dmbd/blocks/sparse_state_space.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "dmbd/blocks/error.hpp"

namespace dmbd::blocks {

namespace {

bool all_finite(const SparseMatrix& m) {
  for (Eigen::Index k = 0; k < m.nonZeros(); ++k)
    if (!std::isfinite(m.valuePtr()[k])) return false;
  return true;
}

std::string dims(Eigen::Index r, Eigen::Index c) { return std::to_string(r) + "x" + std::to_string(c); }

// Column position of state j in a sorted list of (state, position) pairs, or -1.
int position(const std::vector<std::pair<int, int>>& sorted, int j) {
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(j, -1));
  return it != sorted.end() && it->first == j ? it->second : -1;
}

}  // namespace

SparseStateSpace::SparseStateSpace(SparseMatrix a, SparseMatrix b, SparseMatrix c, Matrix d, double ts)
    : a_(std::move(a)), b_(std::move(b)), c_(std::move(c)), d_(std::move(d)), ts_(ts) {
  if (!(ts >= 0.0) || !std::isfinite(ts)) throw InputError("sample time must be a finite number >= 0");
  const auto n = a_.rows();
  if (a_.cols() != n) throw InputError("state-space A must be square, got " + dims(a_.rows(), a_.cols()));
  if (b_.rows() != n || c_.cols() != n || d_.rows() != c_.rows() || d_.cols() != b_.cols())
    throw InputError("state-space sizes disagree: A " + dims(n, n) + ", B " + dims(b_.rows(), b_.cols()) + ", C " +
                     dims(c_.rows(), c_.cols()) + ", D " + dims(d_.rows(), d_.cols()));
  if (!all_finite(a_) || !all_finite(b_) || !all_finite(c_) || !d_.allFinite())
    throw InputError("state-space matrices must be finite");
  a_.makeCompressed();
  b_.makeCompressed();
  c_.makeCompressed();
}

SparseStateSpace::SparseStateSpace(const StateSpace& s)
    : SparseStateSpace(s.a().sparseView(0.0, 0.0), s.b().sparseView(0.0, 0.0), s.c().sparseView(0.0, 0.0), s.d(),
                       s.ts()) {}

StateSpace SparseStateSpace::dense() const { return StateSpace(Matrix(a_), Matrix(b_), Matrix(c_), d_, ts_); }

std::vector<std::vector<int>> SparseStateSpace::groups() const {
  std::vector<std::vector<int>> dep(static_cast<size_t>(a_.rows()));
  for (Eigen::Index i = 0; i < a_.outerSize(); ++i)
    for (SparseMatrix::InnerIterator it(a_, i); it; ++it)
      if (it.col() != i && it.value() != 0.0) dep[static_cast<size_t>(i)].push_back(static_cast<int>(it.col()));
  return strongly_connected_components(dep);
}

std::vector<Complex> SparseStateSpace::poles() const {
  std::vector<Complex> ev;
  for (const std::vector<int>& g : groups()) {
    const std::vector<Complex> part = group_eigenvalues(dense_block(a_, g, g), is_discrete());
    ev.insert(ev.end(), part.begin(), part.end());
  }
  sort_roots(ev);
  return ev;
}

SparseStateSpace SparseStateSpace::restricted(const std::vector<int>& keep) const {
  std::vector<int> pos(static_cast<size_t>(num_states()), -1);
  for (size_t k = 0; k < keep.size(); ++k) pos[static_cast<size_t>(keep[k])] = static_cast<int>(k);
  const auto n = static_cast<Eigen::Index>(keep.size());
  std::vector<Eigen::Triplet<double>> ta, tb, tc;
  for (size_t k = 0; k < keep.size(); ++k) {
    for (SparseMatrix::InnerIterator it(a_, keep[k]); it; ++it)
      if (pos[static_cast<size_t>(it.col())] >= 0)
        ta.emplace_back(static_cast<int>(k), pos[static_cast<size_t>(it.col())], it.value());
    for (SparseMatrix::InnerIterator it(b_, keep[k]); it; ++it) tb.emplace_back(static_cast<int>(k), it.col(), it.value());
  }
  for (Eigen::Index i = 0; i < c_.outerSize(); ++i)
    for (SparseMatrix::InnerIterator it(c_, i); it; ++it)
      if (pos[static_cast<size_t>(it.col())] >= 0) tc.emplace_back(i, pos[static_cast<size_t>(it.col())], it.value());
  SparseMatrix a(n, n), b(n, b_.cols()), c(c_.rows(), n);
  a.setFromTriplets(ta.begin(), ta.end());
  b.setFromTriplets(tb.begin(), tb.end());
  c.setFromTriplets(tc.begin(), tc.end());
  return SparseStateSpace(std::move(a), std::move(b), std::move(c), d_, ts_);
}

SparseStateSpace SparseStateSpace::balanced() const {
  const auto n = a_.rows();
  // Off-diagonal entries by column too, for the column norms.
  const Eigen::SparseMatrix<double, Eigen::ColMajor> by_col = a_;
  Vector scale = Vector::Ones(n);
  constexpr double radix = 2.0, sqrdx = radix * radix;
  bool done = false;
  for (int sweep = 0; !done && sweep < 100; ++sweep) {
    done = true;
    for (Eigen::Index i = 0; i < n; ++i) {
      double r = 0.0, c = 0.0;  // entries of D^-1 A D: a(i, j) d(j) / d(i)
      for (SparseMatrix::InnerIterator it(a_, i); it; ++it)
        if (it.col() != i) r += std::abs(it.value()) * scale(it.col()) / scale(i);
      for (decltype(by_col)::InnerIterator it(by_col, i); it; ++it)
        if (it.row() != i) c += std::abs(it.value()) * scale(i) / scale(it.row());
      if (c == 0.0 || r == 0.0) continue;
      double g = r / radix, f = 1.0;
      const double s = c + r;
      while (c < g) f *= radix, c *= sqrdx;
      g = r * radix;
      while (c > g) f /= radix, c /= sqrdx;
      if ((c + r) / f < 0.95 * s) {
        done = false;
        scale(i) *= f;
      }
    }
  }
  SparseMatrix a = a_, b = b_, c = c_;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (SparseMatrix::InnerIterator it(a, i); it; ++it) it.valueRef() *= scale(it.col()) / scale(i);
    for (SparseMatrix::InnerIterator it(b, i); it; ++it) it.valueRef() /= scale(i);
  }
  for (Eigen::Index i = 0; i < c.outerSize(); ++i)
    for (SparseMatrix::InnerIterator it(c, i); it; ++it) it.valueRef() *= scale(it.col());
  return SparseStateSpace(std::move(a), std::move(b), std::move(c), d_, ts_);
}

Matrix dense_block(const SparseMatrix& m, const std::vector<int>& rows, const std::vector<int>& cols) {
  std::vector<std::pair<int, int>> sorted;
  for (size_t k = 0; k < cols.size(); ++k) sorted.emplace_back(cols[k], static_cast<int>(k));
  std::sort(sorted.begin(), sorted.end());
  Matrix out = Matrix::Zero(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()));
  for (size_t r = 0; r < rows.size(); ++r)
    for (SparseMatrix::InnerIterator it(m, rows[r]); it; ++it) {
      const int p = position(sorted, static_cast<int>(it.col()));
      if (p >= 0) out(static_cast<Eigen::Index>(r), p) = it.value();
    }
  return out;
}

}  // namespace dmbd::blocks
