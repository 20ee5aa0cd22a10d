// A pid block with output limits, term by term: the anti-windup needs the integral term
// and the unlimited output as signals of their own, which one transfer function's
// sections do not have.
#include "pid_lowering.hpp"

#include <utility>

namespace dmbd::codegen {

namespace b = dmbd::blocks;

namespace {

// I/s discretised by `m`: the integral term y = b0 e + x, the state x' = y + b1 e
// (Tustin: (I ts/2)(z + 1)/(z - 1); backward Euler: I ts z/(z - 1); ZOH, which is exact
// for the integrator of a held input: I ts/(z - 1)).
std::pair<double, double> integral_coefficients(double i, double ts, b::C2dMethod m) {
  if (m == b::C2dMethod::BackwardEuler) return {i * ts, 0.0};
  if (m == b::C2dMethod::Zoh) return {0.0, i * ts};
  return {0.5 * i * ts, 0.5 * i * ts};
}

void clamp(std::vector<Op>& v, int dst, int a, std::pair<double, double> limits, int block, const std::string& note) {
  Op o;
  o.kind = OpKind::Clamp;
  o.dst = dst;
  o.a = a;
  o.lo = limits.first;
  o.hi = limits.second;
  o.block = block;
  o.note = note;
  v.push_back(o);
}

// The filtered derivative D s/(tau s + 1) from e into a new signal; its slot and
// whether it passes e straight through.
std::pair<int, bool> derivative(Builder& bld, BlockCode& code, const diagrams::PidLaw& law, double ts, b::C2dMethod method,
                                int e, int block, const std::string& path) {
  const int yd = bld.new_slot(path + "_d", SlotKind::Signal, path);
  const b::TransferFunction g(b::Polynomial({0.0, law.d}), b::Polynomial({1.0, law.tau}));
  BlockCode dc;
  cascade(bld, dc, discretised_sections(g, ts, method), e, yd, block, path + "_d");
  code.out.insert(code.out.end(), dc.out.begin(), dc.out.end());
  code.upd.insert(code.upd.end(), dc.upd.begin(), dc.upd.end());
  return {yd, dc.feedthrough.front()};
}

}  // namespace

std::string lower_limited_pid(Builder& bld, BlockCode& code, const diagrams::PidLaw& law, double ts, b::C2dMethod method,
                              int e, int y, int block, const std::string& path) {
  const std::pair<double, double> limits = *law.output_limits;
  std::vector<std::pair<int, double>> terms{{e, law.p}};
  bool feedthrough = law.p != 0.0;
  int xi = -1, yi = -1;
  const auto [b0, b1] = integral_coefficients(law.i, ts, method);
  if (law.has_i) {
    xi = bld.new_slot(path + "_xi", SlotKind::State, path);
    bld.p.states.push_back(xi);
    yi = bld.new_slot(path + "_i", SlotKind::Signal, path);
    sum(code.out, yi, {{e, b0}, {xi, 1.0}}, block, "integral term: yi = b0 e + xi");
    if (law.anti_windup == diagrams::AntiWindup::Clamp) {
      const int held = bld.new_slot(path + "_i_held", SlotKind::Signal, path);
      clamp(code.out, held, yi, limits, block, "anti-windup (clamp): the integral term held within the output limits");
      yi = held;
    }
    terms.push_back({yi, 1.0});
    feedthrough = feedthrough || b0 != 0.0;
  }
  if (law.has_d) {
    const auto [yd, d_through] = derivative(bld, code, law, ts, method, e, block, path);
    terms.push_back({yd, 1.0});
    feedthrough = feedthrough || d_through;
  }
  const int u = bld.new_slot(path + "_u", SlotKind::Signal, path);
  sum(code.out, u, terms, block, "unlimited output: u = P e + yi + yd");
  clamp(code.out, y, u, limits, block, "output limits");
  if (law.has_i) {
    std::vector<std::pair<int, double>> next{{yi, 1.0}, {e, b1}};
    const bool back = law.anti_windup == diagrams::AntiWindup::BackCalculation;
    if (back) next.insert(next.end(), {{y, law.kt * ts}, {u, -law.kt * ts}});
    sum(code.upd, xi, next, block, back ? "integrator: xi = yi + b1 e + Kt ts (y - u)" : "integrator: xi = yi + b1 e");
  }
  code.feedthrough = {feedthrough};
  return std::string("term by term: P") + (law.has_i ? ", integral (" + std::string(b::to_string(method)) + ")" : "") +
         (law.has_d ? ", filtered derivative (" + std::string(b::to_string(method)) + ")" : "") + ", output limits, anti-windup " +
         diagrams::to_string(law.anti_windup);
}

}  // namespace dmbd::codegen
