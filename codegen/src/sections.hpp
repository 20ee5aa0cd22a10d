#pragma once
#include <vector>

#include "dmbd/blocks/polynomial.hpp"
#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen {

// Sections of k prod(z - z_i) / prod(z - p_j) (conjugate pairs exact).
std::vector<Section> sections_from_roots(const std::vector<blocks::Complex>& zeros,
                                         const std::vector<blocks::Complex>& poles, double gain);

}  // namespace dmbd::codegen
