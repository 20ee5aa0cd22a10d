#pragma once
// State-space models with sparse A, B, C: interconnections of thousands of blocks,
// where a dense n x n matrix (and anything cubic in n) is out of reach.
#include <Eigen/SparseCore>
#include <optional>
#include <vector>

#include "dmbd/blocks/schur_exponential.hpp"
#include "dmbd/blocks/state_space.hpp"
#include "dmbd/blocks/time_response.hpp"

namespace dmbd::blocks {

// Sparse real matrices, row-major: a row of A (a state's equation) is contiguous.
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// A MIMO state-space model as StateSpace (same equations, ts == 0 continuous, ts > 0
// seconds discrete), with A, B, C sparse and D dense (outputs x inputs): the linearised
// diagram (diagrams::linearize_sparse) and what Siso takes apart. Immutable.
class SparseStateSpace {
 public:
  // The empty model: no states, inputs or outputs, continuous.
  SparseStateSpace() = default;
  // Throws InputError on inconsistent sizes, non-finite entries or a bad sample time.
  SparseStateSpace(SparseMatrix a, SparseMatrix b, SparseMatrix c, Matrix d, double ts = 0.0);
  // The same model with the exact zeros of A, B, C left out.
  explicit SparseStateSpace(const StateSpace& dense);
  // The same model with dense matrices (n x n memory: for small systems or after
  // restricted()).
  StateSpace dense() const;

  const SparseMatrix& a() const { return a_; }  // A: states x states, compressed
  const SparseMatrix& b() const { return b_; }  // B: states x inputs, compressed
  const SparseMatrix& c() const { return c_; }  // C: outputs x states, compressed
  const Matrix& d() const { return d_; }        // D: outputs x inputs, dense
  // Sample time in seconds; 0 for a continuous model.
  double ts() const { return ts_; }
  // ts() > 0: a difference equation.
  bool is_discrete() const { return ts_ > 0.0; }
  int num_states() const { return static_cast<int>(a_.rows()); }    // n, the rows of A
  int num_inputs() const { return static_cast<int>(b_.cols()); }    // the columns of B (and D)
  int num_outputs() const { return static_cast<int>(c_.rows()); }  // the rows of C (and D)

  // The strongly connected groups of the states, each after the groups it depends on
  // (as state_groups()); O(nonzeros).
  std::vector<std::vector<int>> groups() const;
  // Eigenvalues of A, group by group as StateSpace::poles() (one small dense problem
  // per group), sorted.
  std::vector<Complex> poles() const;
  // The same system with only the states `keep`, in that order (A, B, C restricted:
  // exact when the others do not reach `keep` and the outputs, or are not reached
  // from the inputs and `keep`).
  SparseStateSpace restricted(const std::vector<int>& keep) const;
  // Diagonal power-of-two similarity equalising row and column norms of A
  // (Parlett-Reinsch, as StateSpace::balanced()); O(nonzeros) per sweep.
  SparseStateSpace balanced() const;

 private:
  SparseMatrix a_, b_, c_;
  Matrix d_;
  double ts_ = 0.0;
};

// v -> e^{tM} v for a sparse square M, never forming a dense matrix: the shift
// mu = trace(M)/n is taken out exactly, and the rest is a Taylor series on
// s = ceil(||M - mu I||_1 t / 4) steps of t/s (each step's matrix of 1-norm <= 4), its
// terms summed until they fall below rounding. Cost: about 30 s products with M.
class ExponentialAction {
 public:
  // Keeps M (square) and precomputes mu and ||M - mu I||_1.
  explicit ExponentialAction(SparseMatrix m);
  // e^{tM} v (any real t; v of M's size). InputError when t is so long for M's norm that
  // more than 1e9 steps would be needed.
  Vector apply(const Vector& v, double t) const;

 private:
  SparseMatrix m_;
  double mu_ = 0.0, norm1_ = 0.0;
};

// Unit step on input `in` from rest, n samples from 0 to t_end (a discrete system: at
// its own k ts up to t_end), exact at the samples and, for a continuous system, at any
// time between them: the state [x; u] of the augmented [A B; 0 0] is propagated by
// ExponentialAction (a dense matrix exponential when there are at most 60 states,
// whose cost does not grow with stiffness).
class SparseStep {
 public:
  // Computes the response at construction. InputError for an input `in` that does not
  // exist, t_end <= 0 (seconds), n < 2, or a discrete horizon of more than 5e7 samples.
  SparseStep(const SparseStateSpace& sys, double t_end, int n, int in = 0);
  // The samples: t in seconds (k t_end/(n - 1), or k ts), y samples x outputs.
  const TimeResponse& response() const { return response_; }
  // Output `out` at t in [0, t_end]: exact (continuous), or the sample at or before t.
  // InputError for an output that does not exist.
  double at(double t, int out = 0) const;

 private:
  Vector advance(const Vector& z, double t) const;  // augmented state after t (large systems)
  void exact_samples(int n);                         // small continuous systems
  SparseStateSpace sys_;
  int in_ = 0, stride_ = 1;
  double dt_ = 0.0;
  std::optional<ExponentialAction> action_;
  std::optional<SchurExponential> exact_;
  SparseMatrix augmented_;
  std::vector<Vector> checkpoints_;  // augmented state every stride_ samples
  TimeResponse response_;
};

// Rows `rows` and columns `cols` of a sparse matrix, dense.
Matrix dense_block(const SparseMatrix& m, const std::vector<int>& rows, const std::vector<int>& cols);

}  // namespace dmbd::blocks
