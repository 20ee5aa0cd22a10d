#include "dmbd/codegen/quantisation.hpp"

#include <algorithm>
#include <cmath>

#include "dmbd/blocks/frequency.hpp"
#include "dmbd/codegen/fixed.hpp"

namespace dmbd::codegen {

namespace b = dmbd::blocks;

QuantisationEffect quantisation_effect(const LoopProgram& exact, const LoopProgram& quantised) {
  const b::StateSpace e = program_state_space(exact), q = program_state_space(quantised);
  QuantisationEffect out;
  out.poles_exact = e.poles();
  out.poles_quantised = q.poles();
  const auto w = b::logspace(2 * M_PI * 0.01, M_PI * exact.rate_hz * 0.999, 400);
  const auto he = b::frequency_response(e, w), hq = b::frequency_response(q, w);
  for (size_t k = 0; k < w.size(); ++k)
    for (int r = 0; r < he[k].rows(); ++r)
      for (int c = 0; c < he[k].cols(); ++c) {
        const b::Complex a = he[k](r, c), z = hq[k](r, c);
        if (std::abs(a) == 0.0 || std::abs(z) == 0.0) continue;
        out.max_db = std::max(out.max_db, std::abs(20 * std::log10(std::abs(z) / std::abs(a))));
        out.max_deg = std::max(out.max_deg, std::abs(std::arg(z / a)) * 180 / M_PI);
      }
  return out;
}

}  // namespace dmbd::codegen
