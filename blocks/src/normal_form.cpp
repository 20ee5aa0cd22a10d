#include "dmbd/blocks/normal_form.hpp"

#include <string>

#include "dmbd/blocks/error.hpp"

namespace dmbd::blocks {

NormalForm normal_form(const TransferFunction& plant) {
  if (plant.num().is_zero()) throw InputError("normal form of a zero transfer function");
  if (!plant.is_strictly_proper())
    throw InputError("normal form needs a strictly proper plant (relative degree >= 1), got relative degree " +
                     std::to_string(plant.relative_degree()));
  NormalForm nf;
  const Polynomial& a = plant.den();  // monic
  nf.g = plant.num().leading();
  const Polynomial bm = plant.num().monic();
  const int m = bm.degree(), n = a.degree();
  nf.relative_degree = n - m;
  const auto [q, r] = Polynomial::divide(a, bm);
  nf.phi.resize(nf.relative_degree);
  for (int k = 0; k < nf.relative_degree; ++k) nf.phi(k) = -q[k];
  nf.psi.resize(m);
  for (int k = 0; k < m; ++k) nf.psi(k) = -r[k];
  nf.S = Matrix::Zero(m, m);
  for (int k = 0; k + 1 < m; ++k) nf.S(k, k + 1) = 1.0;
  for (int k = 0; k < m; ++k) nf.S(m - 1, k) = -bm[k];
  nf.G = Matrix::Zero(m, nf.relative_degree);
  if (m > 0) nf.G(m - 1, 0) = 1.0;
  return nf;
}

Matrix dob_fast_subsystem(const Matrix& a, const Matrix& b, const Matrix& c, double r) {
  const int n = static_cast<int>(a.rows());
  if (a.cols() != n || b.rows() != n || b.cols() != 1 || c.rows() != 1 || c.cols() != n)
    throw InputError("dob_fast_subsystem needs a SISO filter realisation (A n x n, B n x 1, C 1 x n)");
  const Matrix bc = b * c;
  Matrix m(2 * n, 2 * n);
  m << a - r * bc, r * bc, -bc, a + bc;
  return m;
}

}  // namespace dmbd::blocks
