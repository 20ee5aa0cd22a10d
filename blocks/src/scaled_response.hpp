#pragma once
// A transfer function's frequency response straight from its coefficients, safe at
// high order: on the imaginary axis above w = 1 both polynomials are evaluated in 1/s
// (reversed coefficients), so no power of w is ever formed and nothing overflows that
// the response itself does not. Private to blocks/.
#include <vector>

#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks {

// G(jw) = h (jw)^k (continuous), or G(e^{jw ts}) = h with k = 0 (discrete: |z| = 1
// needs no scaling).
struct ScaledResponse {
  Complex h;
  int k = 0;
  // h (jw)^k as one number (infinite or zero where that is out of range).
  Complex value(double w) const;
  // 20 log10 |G| and arg h + k pi/2, computed from h and k (finite where h is finite
  // and nonzero, however large (jw)^k).
  double mag_db(double w) const;
  double arg_rad(double w) const;
};

// G at every w[k] into out[k] (resized): one Horner pass per coefficient over all the
// frequencies, which the compiler vectorises.
void scaled_responses(const TransferFunction& g, const std::vector<double>& w, std::vector<ScaledResponse>& out);

}  // namespace dmbd::blocks
