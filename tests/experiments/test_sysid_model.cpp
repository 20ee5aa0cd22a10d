// The RFSEA model of sim/sysid against independent formulations: the shipped diagram
// examples/diagrams/rfsea_plant.yaml (screw force as an algebraic combination,
// linearised by the diagrams module), a blocks:: transfer-function interconnection
// of the three equations, a time-domain simulation, the alias sum that defines the
// ZOH equivalent, and the numbers docs/paper-actuators.md prints.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/time_response.hpp"
#include "dmbd/diagrams/linearize.hpp"
#include "dmbd/experiments/sysid.hpp"

namespace {

using namespace dmbd;  // NOLINT
using blocks::TransferFunction;
using experiments::Complex;
using experiments::RfseaTest;

constexpr double kPi = 3.14159265358979323846;

// Table I knee values with a free shank-like load (docs/paper-actuators.md section 1).
experiments::RfseaParams free_load(double M_l, double K_l) {
  experiments::RfseaParams p;
  p.M_l = M_l;
  p.B_l = 2.0e4;
  p.K_l = K_l;
  return p;
}

double rel_err(Complex a, Complex b) { return std::abs(a - b) / std::abs(b); }

TEST(SysidModel, FreeResponseMatchesTheShippedDiagram) {
  // rfsea_plant.yaml has no load spring: K_l = 0. Every channel, 0.01 .. 500 Hz,
  // agrees to rounding (the diagram is linearised in double precision; 1e-9).
  const double M_l = 150;
  const auto d = diagrams::Diagram::load(std::string(DMBD_SOURCE_DIR) + "/examples/diagrams/rfsea_plant.yaml",
                                         {{"M_l", M_l}});
  const experiments::RfseaParams p = free_load(M_l, 0.0);
  const experiments::RfseaConstants c;
  const auto f = experiments::log_frequencies(0.01, 500, 60);
  const auto r = experiments::rfsea_response(RfseaTest::Free, p, c, f);
  std::vector<double> w;
  for (double x : f) w.push_back(2 * kPi * x);
  const std::pair<const char*, const std::vector<Complex>*> outs[] = {{"F", &r.F}, {"theta_m", &r.theta_m}, {"q", &r.q}};
  for (const auto& [name, resp] : outs) {
    SCOPED_TRACE(name);
    const auto h = blocks::frequency_response(diagrams::linearize(*d, "i", name), w);
    for (std::size_t k = 0; k < f.size(); ++k) EXPECT_LT(rel_err((*resp)[k], h[k](0, 0)), 1e-9) << f[k] << " Hz";
  }
}

TEST(SysidModel, ResponsesMatchATransferFunctionInterconnection) {
  // The three equations as blocks:: transfer functions: the rotor P_m' = 1/(J' s^2 + B' s)
  // moves x_m = x_l + x_r under G i - F_s; load and elastomer carry the same F_s in
  // series, so F_s = x_m / (P_l + P_r) and x_r = P_r F_s:
  //   x_m / i = G feedback(P_m', 1/(P_l + P_r)),  x_r = P_r / (P_l + P_r) x_m.
  // Locked: P_l = 0. Checked with a load spring (K_l = 3000 N/m).
  const experiments::RfseaParams p = free_load(400, 3000);
  const experiments::RfseaConstants c;
  const double Jp = p.J_m * c.N_m * c.N_m, Bp = p.B_m * c.N_m * c.N_m, G = c.k_tau * c.N_m;
  const TransferFunction Pm = TransferFunction::from_descending({1}, {Jp, Bp, 0});
  const TransferFunction Pr = TransferFunction::from_descending({1}, {p.M_r, p.B_r, p.K_r});
  const TransferFunction Pl = TransferFunction::from_descending({1}, {p.M_l, p.B_l, p.K_l});
  const auto f = experiments::log_frequencies(0.05, 400, 40);
  std::vector<double> w;
  for (double x : f) w.push_back(2 * kPi * x);
  for (RfseaTest test : {RfseaTest::Free, RfseaTest::Locked}) {
    SCOPED_TRACE(test == RfseaTest::Free ? "free" : "locked");
    const TransferFunction series = test == RfseaTest::Free ? Pl + Pr : Pr;
    const TransferFunction xm = TransferFunction(G) * blocks::feedback(Pm, TransferFunction(1.0) / series);
    const TransferFunction xr = Pr / series * xm;
    const auto hm = blocks::frequency_response(xm, w), hr = blocks::frequency_response(xr, w);
    const auto r = experiments::rfsea_response(test, p, c, f);
    for (std::size_t k = 0; k < f.size(); ++k) {
      EXPECT_LT(rel_err(r.F[k], p.K_r * hr[k]), 1e-9) << f[k] << " Hz";
      EXPECT_LT(rel_err(r.theta_m[k], c.N_m * hm[k]), 1e-9) << f[k] << " Hz";
      if (test == RfseaTest::Free) {
        EXPECT_LT(rel_err(r.q[k], c.N_l * (hm[k] - hr[k])), 1e-8) << f[k] << " Hz";
      } else {
        EXPECT_EQ(r.q[k], Complex(0.0));
      }
    }
  }
}

// The doc's realisation (rfsea_plant.yaml's equations) plus a load spring, written out
// here: states x_r, v_r, x_l, v_l; screw force
//   F_s = c_s [G i - B'(v_l + v_r) + (J'/M_r)(B_r v_r + K_r x_r) + (J'/M_l)(B_l v_l + K_l x_l)],
//   c_s = 1 / (1 + J'/M_l + J'/M_r).
blocks::StateSpace doc_realisation(const experiments::RfseaParams& p, const experiments::RfseaConstants& c) {
  const double Jp = p.J_m * c.N_m * c.N_m, Bp = p.B_m * c.N_m * c.N_m, G = c.k_tau * c.N_m;
  const double cs = 1.0 / (1.0 + Jp / p.M_l + Jp / p.M_r);
  // F_s = fs_x . [x_r v_r x_l v_l] + fs_i i
  Eigen::RowVector4d fs_x;
  fs_x << cs * Jp / p.M_r * p.K_r, cs * (-Bp + Jp / p.M_r * p.B_r), cs * Jp / p.M_l * p.K_l,
      cs * (-Bp + Jp / p.M_l * p.B_l);
  const double fs_i = cs * G;
  blocks::Matrix a = blocks::Matrix::Zero(4, 4), b = blocks::Matrix::Zero(4, 1), cc = blocks::Matrix::Zero(3, 4);
  a(0, 1) = 1;
  a(2, 3) = 1;
  // M_r a_r = F_s - K_r x_r - B_r v_r;  M_l a_l = F_s - K_l x_l - B_l v_l
  a.row(1) = fs_x / p.M_r;
  a(1, 0) -= p.K_r / p.M_r;
  a(1, 1) -= p.B_r / p.M_r;
  b(1, 0) = fs_i / p.M_r;
  a.row(3) = fs_x / p.M_l;
  a(3, 2) -= p.K_l / p.M_l;
  a(3, 3) -= p.B_l / p.M_l;
  b(3, 0) = fs_i / p.M_l;
  cc(0, 0) = p.K_r;
  cc(1, 0) = cc(1, 2) = c.N_m;
  cc(2, 2) = c.N_l;
  return blocks::StateSpace(a, b, cc, blocks::Matrix::Zero(3, 1));
}

TEST(SysidModel, StateSpaceSimulationMatchesTheDocsRealisation) {
  // Time domain: a 0.5 .. 100 Hz chirp through both realisations (exact ZOH at 2 kHz).
  // Same outputs to 1e-9 of their peak (two differently conditioned realisations).
  const experiments::RfseaParams p = free_load(150, 3000);
  const experiments::RfseaConstants c;
  const experiments::ExponentialChirp chirp{0.5, 100, 4, 2.0, 1.0, 0.1};
  const auto u = chirp.sample(2000, 0.0, 0.5);
  const blocks::Matrix um = Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size()));
  const auto a = blocks::lsim(experiments::rfsea_state_space(RfseaTest::Free, p, c), um, 5e-4);
  const auto b = blocks::lsim(doc_realisation(p, c), um, 5e-4);
  for (int j = 0; j < 3; ++j) {
    const double peak = b.y.col(j).cwiseAbs().maxCoeff();
    EXPECT_GT(peak, 0);
    EXPECT_LT((a.y.col(j) - b.y.col(j)).cwiseAbs().maxCoeff(), 1e-9 * peak) << "output " << j;
  }
}

TEST(SysidModel, ZohResponseIsTheAliasSum) {
  // The ZOH equivalent of a strictly proper H sampled every T is
  //   H_d(e^{jwT}) = (1 - e^{-jwT}) sum_k H(j(w + k ws)) / (j(w + k ws) T),
  // the terms falling as 1/k^3 (relative degree 2): 20000 terms each side leave ~1e-9.
  const experiments::RfseaParams p = free_load(150, 3000);
  const experiments::RfseaConstants c;
  const double ts = 5e-4, ws = 2 * kPi / ts;
  const std::vector<double> f{0.3, 3, 20, 45, 120, 200, 600};
  for (RfseaTest test : {RfseaTest::Locked, RfseaTest::Free}) {
    const auto d = experiments::rfsea_response(test, p, c, f, {ts, 0.0});
    for (std::size_t k = 0; k < f.size(); ++k) {
      const double w = 2 * kPi * f[k];
      std::vector<double> fk;
      const int K = 20000;
      for (int j = -K; j <= K; ++j) fk.push_back(std::abs((w + j * ws) / (2 * kPi)));
      const auto h = experiments::rfsea_response(test, p, c, fk);
      Complex sF = 0, sT = 0, sQ = 0;
      for (int j = -K; j <= K; ++j) {
        const double wj = w + j * ws;
        const auto i = static_cast<std::size_t>(j + K);
        // rfsea_response takes |f|: negative frequencies are the conjugates.
        auto val = [&](const std::vector<Complex>& v) { return wj >= 0 ? v[i] : std::conj(v[i]); };
        const Complex g = 1.0 / Complex(0.0, wj * ts);
        sF += val(h.F) * g;
        sT += val(h.theta_m) * g;
        sQ += val(h.q) * g;
      }
      const Complex hold = 1.0 - std::polar(1.0, -w * ts);
      EXPECT_LT(rel_err(d.F[k], hold * sF), 1e-7) << f[k] << " Hz";
      EXPECT_LT(rel_err(d.theta_m[k], hold * sT), 1e-7) << f[k] << " Hz";
      if (test == RfseaTest::Free) {
        EXPECT_LT(rel_err(d.q[k], hold * sQ), 1e-7) << f[k] << " Hz";
      }
    }
  }
  // The extra delay multiplies by e^{-j w ts d}.
  const auto a = experiments::rfsea_response(RfseaTest::Locked, p, c, {50}, {ts, 0.0});
  const auto b = experiments::rfsea_response(RfseaTest::Locked, p, c, {50}, {ts, 1.0});
  EXPECT_LT(rel_err(b.F[0], a.F[0] * std::polar(1.0, -2 * kPi * 50 * ts)), 1e-12);
}

TEST(SysidModel, NumbersOfTheDoc) {
  // docs/paper-actuators.md section 1 at M_l = 2953 kg, K_l = 0:
  //   P_{i->F} poles -7.877, -19.73 +- 127.61j, DC gain 206.4 N/A = k_tau N_m B_l/(B_l + B');
  // locked (M_l -> oo): 4.0035e6 / (s^2 + 35.17 s + 13474.5). The doc prints 4-5 digits.
  const experiments::RfseaConstants c;
  experiments::RfseaParams p = free_load(2953, 0.0);
  const auto free_f = experiments::rfsea_state_space(RfseaTest::Free, p, c).select({0}, {0}).minimal(1e-9).to_tf();
  auto poles = free_f.poles();
  ASSERT_EQ(poles.size(), 3u);
  std::sort(poles.begin(), poles.end(), [](Complex a, Complex b) { return a.imag() < b.imag(); });
  EXPECT_NEAR(poles[0].real(), -19.73, 0.01);
  EXPECT_NEAR(poles[0].imag(), -127.61, 0.01);
  EXPECT_NEAR(poles[1].real(), -7.877, 0.001);
  EXPECT_NEAR(*free_f.dc_gain(), 206.4, 0.05);
  const auto locked = experiments::rfsea_state_space(RfseaTest::Locked, p, c).select({0}, {0}).to_tf();
  ASSERT_EQ(locked.den().degree(), 2);
  EXPECT_NEAR(locked.den().coeffs()[1], 35.17, 0.005);
  EXPECT_NEAR(locked.den().coeffs()[0], 13474.5, 0.05);
  EXPECT_NEAR(locked.num().coeffs()[0], 4.0035e6, 50);
  // Locked: theta_m = N_m F / K_r exactly.
  const auto r = experiments::rfsea_response(RfseaTest::Locked, p, c, {0.1, 18.5, 150});
  for (std::size_t k = 0; k < 3; ++k) EXPECT_LT(rel_err(r.theta_m[k], c.N_m / p.K_r * r.F[k]), 1e-14);
  // And the free test tends to the locked one as the load grows.
  p.M_l = 1e9;
  p.B_l = 1e12;
  const auto rf = experiments::rfsea_response(RfseaTest::Free, p, c, {0.1, 18.5, 150});
  for (std::size_t k = 0; k < 3; ++k) EXPECT_LT(rel_err(rf.F[k], r.F[k]), 1e-5);
}

TEST(SysidModel, RejectsNonPhysicalParameters) {
  experiments::RfseaParams p = free_load(150, 0.0);
  p.M_r = 0;
  EXPECT_THROW(experiments::rfsea_response(RfseaTest::Locked, p, {}, {1.0}), InputError);
  p = free_load(0.0, 0.0);
  EXPECT_NO_THROW(experiments::rfsea_response(RfseaTest::Locked, p, {}, {1.0}));  // the load does not enter
  EXPECT_THROW(experiments::rfsea_response(RfseaTest::Free, p, {}, {1.0}), InputError);
}

}  // namespace
