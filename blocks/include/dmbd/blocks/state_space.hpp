#pragma once
// MIMO state-space models  x' = A x + B u, y = C x + D u  (continuous, ts == 0) or
// x[k+1] = A x[k] + B u[k], y[k] = C x[k] + D u[k]  (discrete, ts > 0).
#include <Eigen/Core>
#include <vector>

#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks {

// Dense real matrices (column-major, dynamic size) of the state-space models.
using Matrix = Eigen::MatrixXd;
// Dense real column vectors: states, initial conditions, scales.
using Vector = Eigen::VectorXd;

// A MIMO linear model (A, B, C, D) with sample time ts (0: continuous, x' = A x + B u;
// > 0 seconds: discrete, x[k+1] = A x[k] + B u[k]); y = C x + D u either way. Sizes:
// A n x n, B n x inputs, C outputs x n, D outputs x inputs; n may be 0 (a static gain).
// An immutable value: every operation returns a new model.
class StateSpace {
 public:
  // The empty model: no states, inputs or outputs, continuous.
  StateSpace() = default;
  // Throws InputError on inconsistent sizes, non-finite entries or a bad sample time.
  StateSpace(Matrix a, Matrix b, Matrix c, Matrix d, double ts = 0.0);
  // A static gain (no states).
  static StateSpace gain(const Matrix& d, double ts = 0.0);
  // Realisation of a proper TF, balanced by a diagonal similarity so that badly scaled
  // coefficients do not hurt later arithmetic. With den = (x - x0)^k q (x0 = 0, or 1 for
  // a discrete TF; the roots at x0 decided by Polynomial::without_root): q in
  // controllable canonical form, followed by k states with A(i, i) = x0 exactly, so
  // that an integrator stays an exact eigenvalue wherever the block is interconnected.
  // InputError if improper.
  static StateSpace from_tf(const TransferFunction& tf);

  const Matrix& a() const { return a_; }  // A: states x states, the dynamics
  const Matrix& b() const { return b_; }  // B: states x inputs
  const Matrix& c() const { return c_; }  // C: outputs x states
  const Matrix& d() const { return d_; }  // D: outputs x inputs, the direct feedthrough
  // Sample time in seconds; 0 for a continuous model.
  double ts() const { return ts_; }
  // ts() > 0: a difference equation (poles in z, stable inside the unit circle).
  bool is_discrete() const { return ts_ > 0.0; }
  int num_states() const { return static_cast<int>(a_.rows()); }    // n, the rows of A
  int num_inputs() const { return static_cast<int>(b_.cols()); }    // the columns of B (and D)
  int num_outputs() const { return static_cast<int>(c_.rows()); }  // the rows of C (and D)

  // Transfer function from input `in` to output `out` (0-based):
  // D + C (xI-A)^-1 B with denominator prod(x - p_i) over all the eigenvalues p = poles()
  // (nothing cancelled: minimal() first for a minimal one) and the numerator() interpolated
  // on a circle. InputError for a channel that does not exist.
  TransferFunction to_tf(int out = 0, int in = 0) const;
  // The numerator of channel (out, in) over prod(x - p_i), p = `poles` (the eigenvalues
  // of A, as poles() gives them): interpolated at n + 1 points on a circle, as to_tf.
  // InputError for a missing channel or when `poles` does not have n entries.
  Polynomial numerator(const std::vector<Complex>& poles, int out = 0, int in = 0) const;
  // Eigenvalues of A, found group by group: the states split into strongly connected
  // groups (x_i depends on x_j when A(i, j) != 0), in which order A is block
  // triangular, and each group's block is balanced and solved alone (exact for a
  // one-state group, so a from_tf integrator is exactly 0, or 1 when discrete). An
  // eigenvalue of a larger group within 1e-10 x (the group's norm; at least 1 when
  // discrete) of 0 (of 1) is returned as exactly that. Sorted as Polynomial::roots().
  std::vector<Complex> poles() const;
  // Every pole strictly stable: Re p < 0 (continuous) or |p| < 1 (discrete); a pole on
  // the boundary (an integrator) is unstable. Uncontrollable and unobservable modes
  // count too.
  bool is_stable() const;
  // Steady-state gain D - C A^-1 B (continuous) or D + C (I-A)^-1 B (discrete);
  // InputError if singular (a pole at DC).
  Matrix dc_gain() const;
  // C (xI - A)^-1 B + D at one complex point (s or z).
  Eigen::MatrixXcd evaluate(Complex x) const;

  // Remove uncontrollable then unobservable states (orthogonal staircase, rank decided
  // by tol relative to the largest singular value). InputError naming 'tol' unless tol
  // is a finite number >= 0.
  StateSpace minimal(double tol = 1e-9) const;
  // Same system, similarity transform T: A' = T^-1 A T, B' = T^-1 B, C' = C T. InputError
  // unless T is n x n and invertible.
  StateSpace transformed(const Matrix& t) const;
  // Diagonal power-of-two similarity that equalises row and column norms of A
  // (Parlett–Reinsch, as LAPACK's dgebal; Eigen does not expose one).
  StateSpace balanced() const;
  // Sub-system from some inputs to some outputs (0-based indices, in the order given,
  // repeats allowed); A unchanged. InputError for an index out of range.
  StateSpace select(const std::vector<int>& outputs, const std::vector<int>& inputs) const;

 private:
  Matrix a_, b_, c_, d_;
  double ts_ = 0.0;
};

// second after first: u -> first -> second -> y. InputError when the sample times differ
// or first's outputs do not match second's inputs (as for every interconnection below).
StateSpace series(const StateSpace& first, const StateSpace& second);
// y = a(u) + b(u): the same inputs and outputs in both (InputError otherwise).
StateSpace parallel(const StateSpace& a, const StateSpace& b);
// u = r + sign * back(y), y = forward(u); sign = -1 is negative feedback. Handles
// non-zero D of both; InputError for an algebraic loop (I - sign D_f D_b singular).
StateSpace feedback(const StateSpace& forward, const StateSpace& back, int sign = -1);
// Block-diagonal stacking: inputs and outputs concatenated.
StateSpace append(const StateSpace& a, const StateSpace& b);

// Strongly connected components of a dependency graph (dep[i]: the nodes i depends
// on), Tarjan's algorithm; every component comes after the components it depends on.
std::vector<std::vector<int>> strongly_connected_components(const std::vector<std::vector<int>>& dep);

// Solve (I - G) U = R for a sparse G by substitution in dependency order (U_i depends
// on U_j where G(i, j) != 0), with a dense solve only inside each strongly connected
// group: the algebraic equations of a block diagram, where chains of large gains make
// a general LU of I - G lose every digit. InputError when a group is singular (an
// algebraic loop of gain 1).
Matrix solve_in_dependency_order(const Matrix& g, const Matrix& r);

// Balancing scales for a square matrix (powers of two): returns d with
// D^-1 M D balanced, D = diag(d).
Vector balancing_scales(const Matrix& m);

// The strongly connected groups of the states of A (x_i depends on x_j when
// A(i, j) != 0, i != j), each after the groups it depends on: in that order A is block
// lower triangular.
std::vector<std::vector<int>> state_groups(const Matrix& a);
// Eigenvalues of one group's diagonal block of A, as StateSpace::poles() computes them.
std::vector<Complex> group_eigenvalues(const Matrix& block, bool discrete);
// By real part, then imaginary part.
void sort_roots(std::vector<Complex>& roots);

}  // namespace dmbd::blocks
