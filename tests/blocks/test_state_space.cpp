// dmbd::blocks::StateSpace: realisation round trips, poles, interconnection against
// the TF-level formulas, feedback with direct feedthrough, algebraic loops, minimal
// realisations, DC gain, similarity transforms and dimension checks.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <random>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/state_space.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

using test::complex_near;
using test::roots_near;
using test::tf_near;

// A few points in the complex plane away from every pole used below.
const std::vector<Complex> kPoints{{0.0, 0.3}, {0.0, 1.7}, {0.5, 4.0}, {-0.25, 11.0}, {2.0, -0.6}};

// The systems of the round-trip tests: orders 0..8, with and without D, integrators,
// complex pairs, right-half-plane zeros, badly scaled coefficients.
std::vector<TransferFunction> round_trip_systems() {
  std::vector<TransferFunction> out;
  out.push_back(TransferFunction(2.5));
  out.push_back(TransferFunction::parse("1/(s+1)"));
  out.push_back(TransferFunction::parse("(2*s^2 + 3*s + 1)/(s^2 + 0.4*s + 4)"));  // D = 2
  out.push_back(TransferFunction::parse("1/s^2"));
  out.push_back(TransferFunction::parse("(s-2)*(s+0.5)/((s+1)*(s+3)*(s^2+s+9))"));
  out.push_back(TransferFunction::parse("-3*(s+10)/((s+0.1)*(s+100))"));
  // Order 8 with D = 3: 3 + (s - 1)(s + 0.5)(s^2 + 2s + 2) / ((s+1)(s+2)...(s+8)).
  const TransferFunction tail = TransferFunction::parse("(s-1)*(s+0.5)*(s^2+2*s+2)/((s+1)*(s+2)*(s+3)*(s+4)*(s+5)*(s+6)*(s+7)*(s+8))");
  out.push_back(TransferFunction(3.0) + tail);
  // Order 6 with lightly damped pairs.
  out.push_back(TransferFunction::parse("(s^2+0.2*s+25)/((s^2+0.02*s+1)*(s^2+0.5*s+16)*(s+2)^2)"));
  // Discrete.
  out.push_back(TransferFunction::parse("(z-0.5)/(z^2 - 1.5*z + 0.7)", {}, 0.1));
  out.push_back(TransferFunction::parse("(2*z^3 - z + 0.25)/((z-0.9)*(z+0.3)*(z^2-z+0.5))", {}, 0.01));
  return out;
}

TEST(StateSpace, RoundTripTfSsTf) {
  for (const TransferFunction& g : round_trip_systems()) {
    SCOPED_TRACE(test::to_text(g.num().coeffs()) + " / " + test::to_text(g.den().coeffs()));
    const StateSpace ss = StateSpace::from_tf(g);
    EXPECT_EQ(ss.num_states(), g.order());
    EXPECT_EQ(ss.ts(), g.ts());
    // D is the direct feedthrough: the leading numerator coefficient when proper.
    // Exact: it is copied.
    EXPECT_EQ(ss.d()(0, 0), g.num()[g.order()]);
    const TransferFunction back = ss.to_tf();
    // Eigenvalues + interpolation on a circle: each coefficient to ~1e-12 of the largest
    // (the order-8 denominator spans 1 .. 1.1e5); 1e-9 relative leaves margin.
    EXPECT_TRUE(tf_near(back, g, 1e-9));
    // Relative degree is preserved exactly (rounding-level coefficients are zeroed).
    EXPECT_EQ(back.num().degree(), g.num().degree());
    // The value at test points, independent of coefficient scaling: 1e-9 relative.
    for (const Complex x0 : kPoints) {
      const Complex x = g.is_discrete() ? std::exp(x0 * 0.1) : x0;
      EXPECT_TRUE(complex_near(ss.evaluate(x)(0, 0), g.evaluate(x), 1e-9)) << "x = " << x;
    }
  }
}

TEST(StateSpace, PolesEqualTfPoles) {
  for (const TransferFunction& g : round_trip_systems()) {
    SCOPED_TRACE(test::to_text(g.den().coeffs()));
    // Simple poles (the order-6 case has a double pole at -2, accurate to ~sqrt(eps)):
    // 1e-6 relative covers both; the simple ones are checked tighter below.
    EXPECT_TRUE(roots_near(StateSpace::from_tf(g).poles(), g.poles(), 1e-6));
  }
  const TransferFunction g = TransferFunction::parse("1/((s+1)*(s+2)*(s+3)*(s+4)*(s+5)*(s+6)*(s+7)*(s+8))");
  // Distinct real poles, condition ~1e3: 1e-10 relative.
  EXPECT_TRUE(roots_near(StateSpace::from_tf(g).poles(), g.poles(), 1e-10));
  EXPECT_TRUE(roots_near(StateSpace::from_tf(g).poles(), {-1.0, -2.0, -3.0, -4.0, -5.0, -6.0, -7.0, -8.0}, 1e-10));
}

TEST(StateSpace, ImproperTfHasNoRealisation) {
  EXPECT_THROW(StateSpace::from_tf(TransferFunction::parse("s^2/(s+1)")), InputError);
}

TEST(StateSpace, StaticGain) {
  Matrix d(2, 3);
  d << 1, 2, 3, 4, 5, 6;
  const StateSpace g = StateSpace::gain(d);
  EXPECT_EQ(g.num_states(), 0);
  EXPECT_EQ(g.num_inputs(), 3);
  EXPECT_EQ(g.num_outputs(), 2);
  EXPECT_EQ(g.dc_gain(), d);                                       // exact: copied
  EXPECT_EQ(g.evaluate(Complex(0.0, 3.0)), d.cast<Complex>());    // exact
  EXPECT_EQ(*g.to_tf(1, 2).dc_gain(), 6.0);                        // exact
  EXPECT_TRUE(g.is_stable());
}

// Series, parallel and feedback of state-space models equal the TF interconnection.
TEST(StateSpace, InterconnectionsMatchTransferFunctions) {
  const TransferFunction g1 = TransferFunction::parse("(s+3)/(s^2+2*s+5)");
  const TransferFunction g2 = TransferFunction::parse("(2*s-1)/(s+4)");  // D = 2
  const TransferFunction g3 = TransferFunction::parse("10/(s*(s+1))");
  const StateSpace s1 = StateSpace::from_tf(g1), s2 = StateSpace::from_tf(g2), s3 = StateSpace::from_tf(g3);

  struct Case {
    const char* name;
    StateSpace ss;
    TransferFunction tf;
  };
  const std::vector<Case> cases{
      {"series", series(s1, s2), g1 * g2},
      {"series reversed", series(s2, s1), g2 * g1},
      {"parallel", parallel(s1, s2), g1 + g2},
      {"feedback -", feedback(s1, s2), feedback(g1, g2)},
      {"feedback +", feedback(s1, s2, +1), feedback(g1, g2, +1)},
      {"unity feedback of a type-2-ish loop", feedback(s3, StateSpace::gain(Matrix::Ones(1, 1))), feedback(g3)},
      {"feedback with dynamic D path", feedback(s2, s3), feedback(g2, g3)},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    EXPECT_EQ(c.ss.num_states(), c.tf.order());
    for (const Complex x : kPoints) {
      // Two formulations of the same rational function at a point away from poles:
      // both are a few well-conditioned operations, 1e-9 relative (the brief's bound;
      // typically ~1e-14).
      EXPECT_TRUE(complex_near(c.ss.evaluate(x)(0, 0), c.tf.evaluate(x), 1e-9)) << "x = " << x;
    }
    // And through to_tf: coefficients relative to the largest, 1e-9.
    EXPECT_TRUE(tf_near(c.ss.to_tf(), c.tf, 1e-9));
  }
}

TEST(StateSpace, FeedbackWithDirectFeedthroughInBothPaths) {
  // f = (s+2)/(s+1) (D = 1), h = (2s+1)/(s+3) (D = 2), negative feedback:
  // f/(1 + f h) = (s+2)(s+3) / ((s+1)(s+3) + (s+2)(2s+1)) = (s^2+5s+6)/(3s^2+9s+5).
  const StateSpace f = StateSpace::from_tf(TransferFunction::parse("(s+2)/(s+1)"));
  const StateSpace h = StateSpace::from_tf(TransferFunction::parse("(2*s+1)/(s+3)"));
  const StateSpace cl = feedback(f, h);
  // D of the loop: D_f / (1 + D_f D_h) = 1/3; one division: 1e-15 relative.
  EXPECT_NEAR(cl.d()(0, 0), 1.0 / 3.0, 1e-15);
  const TransferFunction hand = TransferFunction::from_descending({1.0, 5.0, 6.0}, {3.0, 9.0, 5.0});
  // Interpolated numerator and eigenvalue-based denominator: 1e-12 relative.
  EXPECT_TRUE(tf_near(cl.to_tf(), hand, 1e-12));
  // Closed-loop poles: roots of 3 s^2 + 9 s + 5 = (-9 +- sqrt(21))/6.
  EXPECT_TRUE(roots_near(cl.poles(), {(-9.0 - std::sqrt(21.0)) / 6.0, (-9.0 + std::sqrt(21.0)) / 6.0}, 1e-13));
  // DC: 6/5 (1e-14: LU solve of a 2x2).
  EXPECT_NEAR(cl.dc_gain()(0, 0), 1.2, 1e-14);
  // Positive feedback: f/(1 - f h) = (s^2+5s+6)/((s+1)(s+3) - (s+2)(2s+1)) = (s^2+5s+6)/(-s^2 - s + 1).
  const TransferFunction hand_pos = TransferFunction::from_descending({1.0, 5.0, 6.0}, {-1.0, -1.0, 1.0});
  EXPECT_TRUE(tf_near(feedback(f, h, +1).to_tf(), hand_pos, 1e-12));  // same accuracy as above
}

TEST(StateSpace, AlgebraicLoopThrows) {
  const StateSpace one = StateSpace::gain(Matrix::Ones(1, 1));
  // u = r + y, y = u: I - D_f D_b = 0.
  EXPECT_THROW(feedback(one, one, +1), InputError);
  // With dynamics but the same feedthrough: f = (s+2)/(s+1) has D = 1.
  const StateSpace f = StateSpace::from_tf(TransferFunction::parse("(s+2)/(s+1)"));
  EXPECT_THROW(feedback(f, one, +1), InputError);
  // D_f D_b = -1 with negative feedback: also singular.
  const StateSpace minus_one = StateSpace::gain(-Matrix::Ones(1, 1));
  EXPECT_THROW(feedback(one, minus_one, -1), InputError);
  // Well posed: negative unity feedback of the static gain 1: y = 1/2 r (exact). Neither
  // system has states: under UBSan (scripts/sanitize) this caught a null reference in
  // the LU solve of an empty right-hand side (issue 13, item 12).
  EXPECT_EQ(feedback(one, one).d()(0, 0), 0.5);
}

TEST(StateSpace, MinimalRemovesCancelledPair) {
  // (s+1)/((s+1)(s+2)): the controllable canonical form is unobservable.
  const StateSpace ss = StateSpace::from_tf(TransferFunction::parse("(s+1)/((s+1)*(s+2))"));
  ASSERT_EQ(ss.num_states(), 2);
  const StateSpace m = ss.minimal();
  EXPECT_EQ(m.num_states(), 1);
  // The remaining pole is -2 (orthogonal projections: ~eps, 1e-12).
  EXPECT_TRUE(roots_near(m.poles(), {-2.0}, 1e-12));
  EXPECT_TRUE(tf_near(m.to_tf(), TransferFunction::parse("1/(s+2)"), 1e-12));
}

TEST(StateSpace, MinimalRemovesUnobservableAndUncontrollableStates) {
  Matrix a(3, 3), b(3, 1), c(1, 3), d(1, 1);
  a << -1, 0, 0, 0, -2, 0, 0, 0, -3;
  b << 1, 1, 0;  // state 3 is uncontrollable
  c << 1, 0, 1;  // state 2 is unobservable
  d << 0.5;
  const StateSpace ss(a, b, c, d);
  const StateSpace m = ss.minimal();
  EXPECT_EQ(m.num_states(), 1);
  // 1/(s+1) + 0.5; orthogonal projections, 1e-12.
  EXPECT_TRUE(roots_near(m.poles(), {-1.0}, 1e-12));
  for (const Complex x : kPoints)
    EXPECT_TRUE(complex_near(m.evaluate(x)(0, 0), ss.evaluate(x)(0, 0), 1e-12)) << "x = " << x;
  // A minimal system is left alone.
  const StateSpace g = StateSpace::from_tf(TransferFunction::parse("(s+3)/((s+1)*(s^2+s+4))"));
  EXPECT_EQ(g.minimal().num_states(), 3);
}

// Issue 28, row 11: a NaN tolerance compared false against every singular value and
// removed every state (the zero system); inf did the same, a negative one kept all.
TEST(StateSpace, MinimalRefusesANonFiniteOrNegativeTolerance) {
  const StateSpace g(Matrix::Constant(1, 1, -1.0), Matrix::Constant(1, 1, 1.0), Matrix::Constant(1, 1, 1.0),
                     Matrix::Zero(1, 1));
  for (double tol : {std::nan(""), HUGE_VAL, -HUGE_VAL, -1e-9}) {
    try {
      (void)g.minimal(tol);
      ADD_FAILURE() << "tol = " << tol << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("minimal: the tolerance 'tol' must be a finite number >= 0"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(g.minimal(0.0).num_states(), 1);  // 0 is a tolerance (keep every state that is not exactly lost)
  EXPECT_THROW((void)TransferFunction::parse("(s+1)/((s+1)*(s+2))").minreal(std::nan("")), InputError);
}

TEST(StateSpace, DcGain) {
  // (s+2)/((s+1)(s+4)) -> 2/4 = 0.5; LU solve, 1e-14.
  EXPECT_NEAR(StateSpace::from_tf(TransferFunction::parse("(s+2)/((s+1)*(s+4))")).dc_gain()(0, 0), 0.5, 1e-14);
  // With feedthrough: 3 + 1/(s+2) -> 3.5.
  EXPECT_NEAR(StateSpace::from_tf(TransferFunction::parse("3 + 1/(s+2)")).dc_gain()(0, 0), 3.5, 1e-14);
  // Discrete: 0.5/(z - 0.5) -> 1 (D + C (I - A)^-1 B), 1e-14.
  EXPECT_NEAR(StateSpace::from_tf(TransferFunction::parse("0.5/(z-0.5)", {}, 0.1)).dc_gain()(0, 0), 1.0, 1e-14);
  // MIMO: A = diag(-1, -2), B = I, C = [1 1; 0 1] -> -C A^-1 B = [1 0.5; 0 0.5] (exact halves).
  Matrix a(2, 2), c(2, 2);
  a << -1, 0, 0, -2;
  c << 1, 1, 0, 1;
  const Matrix g = StateSpace(a, Matrix::Identity(2, 2), c, Matrix::Zero(2, 2)).dc_gain();
  Matrix want(2, 2);
  want << 1.0, 0.5, 0.0, 0.5;
  EXPECT_LT((g - want).norm(), 1e-15);  // exact in binary; 1e-15 absolute for the LU
  // Agrees with the TF DC gain of each channel (1e-14).
  const StateSpace mimo(a, Matrix::Identity(2, 2), c, Matrix::Zero(2, 2));
  EXPECT_NEAR(*mimo.to_tf(0, 1).dc_gain(), 0.5, 1e-14);
  // A pole at DC: InputError.
  EXPECT_THROW(StateSpace::from_tf(TransferFunction::parse("1/(s*(s+1))")).dc_gain(), InputError);
  EXPECT_THROW(StateSpace::from_tf(TransferFunction::parse("1/(z-1)", {}, 0.1)).dc_gain(), InputError);
}

TEST(StateSpace, TransformedKeepsTheTransferFunction) {
  const TransferFunction g = TransferFunction::parse("(s-2)*(s+0.5)/((s+1)*(s+3)*(s^2+s+9))");
  const StateSpace ss = StateSpace::from_tf(g);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix t = Matrix::Identity(4, 4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) t(i, j) += 0.4 * u(rng);
  const StateSpace tr = ss.transformed(t);
  // A' = T^-1 A T: T A' == A T, residual at rounding level of |A||T| (1e-12 absolute).
  EXPECT_LT((t * tr.a() - ss.a() * t).norm(), 1e-12 * ss.a().norm() * t.norm());
  EXPECT_LT((t * tr.b() - ss.b()).norm(), 1e-12 * t.norm());
  EXPECT_LT((tr.c() - ss.c() * t).norm(), 1e-12 * ss.c().norm() * t.norm());
  // Same TF and poles: a well-conditioned T (cond ~ 5) costs a few digits at most, 1e-10.
  EXPECT_TRUE(tf_near(tr.to_tf(), g, 1e-10));
  EXPECT_TRUE(roots_near(tr.poles(), g.poles(), 1e-10));
  for (const Complex x : kPoints) EXPECT_TRUE(complex_near(tr.evaluate(x)(0, 0), g.evaluate(x), 1e-10));
  // Balancing is a similarity too (powers of two: the TF is unchanged to ~eps, 1e-12).
  EXPECT_TRUE(tf_near(tr.balanced().to_tf(), g, 1e-10));
  // Wrong size or singular T: InputError.
  EXPECT_THROW(ss.transformed(Matrix::Identity(3, 3)), InputError);
  EXPECT_THROW(ss.transformed(Matrix::Zero(4, 4)), InputError);
}

TEST(StateSpace, DimensionErrorsThrow) {
  const Matrix a = Matrix::Identity(2, 2), b = Matrix::Ones(2, 1), c = Matrix::Ones(1, 2), d = Matrix::Zero(1, 1);
  EXPECT_NO_THROW(StateSpace(a, b, c, d));
  EXPECT_THROW(StateSpace(Matrix::Ones(2, 3), b, c, d), InputError);  // A not square
  EXPECT_THROW(StateSpace(a, Matrix::Ones(3, 1), c, d), InputError);  // B rows
  EXPECT_THROW(StateSpace(a, b, Matrix::Ones(1, 3), d), InputError);  // C columns
  EXPECT_THROW(StateSpace(a, b, c, Matrix::Zero(2, 1)), InputError);  // D rows
  EXPECT_THROW(StateSpace(a, b, c, Matrix::Zero(1, 2)), InputError);  // D columns
  Matrix bad = a;
  bad(0, 1) = NAN;
  EXPECT_THROW(StateSpace(bad, b, c, d), InputError);  // non-finite
  EXPECT_THROW(StateSpace(a, b, c, d, -0.1), InputError);  // sample time
  // Interconnection size mismatches.
  const StateSpace siso(a, b, c, d);
  const StateSpace two_in(a, Matrix::Ones(2, 2), c, Matrix::Zero(1, 2));
  EXPECT_THROW(series(siso, two_in), InputError);  // 1 output feeds 2 inputs
  EXPECT_THROW(parallel(siso, two_in), InputError);
  EXPECT_THROW(feedback(siso, two_in), InputError);
  EXPECT_THROW(siso.to_tf(1, 0), InputError);
  EXPECT_THROW(siso.to_tf(0, -1), InputError);
  EXPECT_THROW(siso.select({0}, {1}), InputError);
  // Sample time mismatch.
  const StateSpace disc(a * 0.5, b, c, d, 0.1);
  EXPECT_THROW(series(siso, disc), InputError);
  EXPECT_THROW(parallel(siso, disc), InputError);
  EXPECT_THROW(feedback(siso, disc), InputError);
  EXPECT_THROW(append(siso, disc), InputError);
}

TEST(StateSpace, AppendAndSelect) {
  const TransferFunction g1 = TransferFunction::parse("1/(s+1)");
  const TransferFunction g2 = TransferFunction::parse("(s+3)/(s^2+s+2)");
  const StateSpace ab = append(StateSpace::from_tf(g1), StateSpace::from_tf(g2));
  EXPECT_EQ(ab.num_inputs(), 2);
  EXPECT_EQ(ab.num_outputs(), 2);
  EXPECT_EQ(ab.num_states(), 3);
  const Complex x(0.1, 2.0);
  const Eigen::MatrixXcd v = ab.evaluate(x);
  // Block diagonal: off-diagonal channels exactly zero, diagonal ones equal g1, g2 (1e-13).
  EXPECT_EQ(v(0, 1), Complex(0.0));
  EXPECT_EQ(v(1, 0), Complex(0.0));
  EXPECT_TRUE(complex_near(v(0, 0), g1.evaluate(x), 1e-13));
  EXPECT_TRUE(complex_near(v(1, 1), g2.evaluate(x), 1e-13));
  EXPECT_TRUE(complex_near(ab.select({1}, {1}).evaluate(x)(0, 0), g2.evaluate(x), 1e-13));
  EXPECT_TRUE(tf_near(ab.to_tf(1, 1).minreal(), g2, 1e-10));  // interpolation + cancellation, 1e-10
}

TEST(StateSpace, MimoInterconnectionsMatchMatrixFormulas) {
  // F: 4 states, 2 inputs, 2 outputs with D; H: 2 states, 2 -> 2 with D. At a point x,
  // feedback is (I - sign F H)^-1 F, series(F, G) is G F, parallel is F + G.
  std::mt19937 rng(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto random = [&](int r, int c) {
    Matrix m(r, c);
    for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = n01(rng);
    return m;
  };
  const StateSpace f(random(4, 4) - 3.0 * Matrix::Identity(4, 4), random(4, 2), random(2, 4), 0.5 * random(2, 2));
  const StateSpace h(random(2, 2) - 2.0 * Matrix::Identity(2, 2), random(2, 2), random(2, 2), 0.3 * random(2, 2));
  const StateSpace g3(random(3, 3) - 2.0 * Matrix::Identity(3, 3), random(3, 2), random(1, 3), random(1, 2));
  for (const Complex x : kPoints) {
    const Eigen::MatrixXcd fx = f.evaluate(x), hx = h.evaluate(x);
    const Eigen::MatrixXcd id = Eigen::MatrixXcd::Identity(2, 2);
    for (const int sign : {-1, +1}) {
      const Eigen::MatrixXcd want = (id - static_cast<double>(sign) * fx * hx).lu().solve(fx);
      // Well-conditioned random data: 1e-11 norm-wise relative.
      EXPECT_LT((feedback(f, h, sign).evaluate(x) - want).norm(), 1e-11 * want.norm()) << "sign " << sign << " x " << x;
    }
    const Eigen::MatrixXcd ser = g3.evaluate(x) * fx;  // u -> f -> g3
    EXPECT_LT((series(f, g3).evaluate(x) - ser).norm(), 1e-12 * ser.norm()) << x;  // 1e-12 relative
    const Eigen::MatrixXcd par = fx + hx;
    EXPECT_LT((parallel(f, h).evaluate(x) - par).norm(), 1e-12 * par.norm()) << x;
  }
}

// Regression (fixed): StateSpace::to_tf interpolates the numerator on a
// circle whose radius is the geometric mean of the non-zero |poles|. A pole at s = 0
// that the eigenvalue solver returns as 1e-16 (or a double integrator returned as
// +-5e-8) instead of exactly 0 shrinks that circle to ~1e-8, and the numerator
// coefficients come out as garbage (e.g. 3e4 s^3 for a numerator s + 3). These tests
// fail until blocks/src/state_space.cpp is fixed.
TEST(StateSpace, ToTfOfIntegratingSystemsInGeneralCoordinates) {
  // (s+3)/(s^2+2s+5) followed by 1/s: (s + 3)/(s^3 + 2 s^2 + 5 s).
  const StateSpace lag = StateSpace::from_tf(TransferFunction::parse("(s+3)/(s^2+2*s+5)"));
  const StateSpace integ = StateSpace::from_tf(TransferFunction::parse("1/s"));
  const TransferFunction want1 = TransferFunction::parse("(s+3)/(s*(s^2+2*s+5))");
  // The realisation is exact (evaluation agrees to 1e-12)...
  for (const Complex x : kPoints)
    EXPECT_TRUE(complex_near(series(lag, integ).evaluate(x)(0, 0), want1.evaluate(x), 1e-12)) << x;
  // ...so its TF must be the same to 1e-9 of the largest coefficient (as for every other
  // interconnection above).
  EXPECT_TRUE(tf_near(series(lag, integ).to_tf(), want1, 1e-9));
  EXPECT_TRUE(tf_near(series(integ, lag).to_tf(), want1, 1e-9));

  // A PID (paper eq. frc_ctrl style, with filter) in series with 1/(s (s+1)): a loop
  // with a double integrator. TF algebra gives the exact reference.
  const TransferFunction c = TransferFunction::parse("2 + 5/s + 0.25*s/(0.02*s+1)");
  const TransferFunction p = TransferFunction::parse("1/(s*(s+1))");
  EXPECT_TRUE(tf_near(series(StateSpace::from_tf(c), StateSpace::from_tf(p)).to_tf(), c * p, 1e-9));

  // 1/(s (s+1)) in coordinates x = T x' (a similarity keeps the TF; cf.
  // TransformedKeepsTheTransferFunction).
  Matrix a(2, 2), t(2, 2);
  a << 0, 1, 0, -1;
  t << 1, 0.3, 0.7, 1.1;
  const StateSpace plant(a, (Matrix(2, 1) << 0, 1).finished(), (Matrix(1, 2) << 1, 0).finished(), Matrix::Zero(1, 1));
  EXPECT_TRUE(tf_near(plant.to_tf(), p, 1e-12));  // canonical coordinates: fine
  EXPECT_TRUE(tf_near(plant.transformed(t).to_tf(), p, 1e-9));
}

TEST(StateSpace, RandomMimoToTfMatchesEvaluate) {
  // A random stable 6-state, 2-input, 3-output system: every channel's to_tf agrees with
  // the direct evaluation C (xI - A)^-1 B + D.
  std::mt19937 rng(42);
  std::normal_distribution<double> n01(0.0, 1.0);
  const int n = 6;
  Matrix a(n, n), b(n, 2), c(3, n), d(3, 2);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) a(i, j) = n01(rng);
  a -= 4.0 * Matrix::Identity(n, n);
  for (int i = 0; i < n; ++i) b(i, 0) = n01(rng), b(i, 1) = n01(rng);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < n; ++j) c(i, j) = n01(rng);
  for (int i = 0; i < 3; ++i) d(i, 0) = n01(rng), d(i, 1) = 0.0;
  const StateSpace ss(a, b, c, d);
  for (int out = 0; out < 3; ++out)
    for (int in = 0; in < 2; ++in) {
      const TransferFunction g = ss.to_tf(out, in);
      EXPECT_EQ(g.order(), n);
      for (const Complex x : kPoints) {
        // Random, well-conditioned data: 1e-9 relative (brief), typically 1e-13.
        EXPECT_TRUE(complex_near(g.evaluate(x), ss.evaluate(x)(out, in), 1e-9))
            << "channel " << out << "," << in << " at " << x;
      }
    }
}

}  // namespace
}  // namespace dmbd::blocks
