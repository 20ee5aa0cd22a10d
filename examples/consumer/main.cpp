// A program of one's own built on draco-mbd's installed libraries (docs/library.md):
// a transfer function's poles and margins (dmbd::blocks), a diagram linearised between
// two of its signals (dmbd::diagrams), and DRACO's robot description (dmbd::model).
//   consumer DIAGRAM.yaml FROM TO
#include <cstdio>
#include <exception>
#include <string>

#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/state_space.hpp"
#include "dmbd/blocks/transfer_function.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/linearize.hpp"
#include "dmbd/model/robot_folder.hpp"
#include "dmbd/model/robot_description.hpp"

namespace b = dmbd::blocks;

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: consumer DIAGRAM.yaml FROM TO\n");
    return 2;
  }
  try {
    // A PD loop around a second-order plant: its closed-loop poles and the loop's margins.
    const b::TransferFunction loop = b::TransferFunction::parse("(20 + 2*s) / (s*(s + 4))");
    for (const auto& p : b::feedback(loop).poles()) std::printf("closed-loop pole %.6f %+.6fj\n", p.real(), p.imag());
    const b::Margins m = b::margins(loop);
    std::printf("phase margin %.3f deg at %.4f rad/s\n", m.phase_margin_deg.value_or(0.0), m.gain_crossover_rad_s.value_or(0.0));

    const auto diagram = dmbd::diagrams::Diagram::load(argv[1]);
    const b::StateSpace sys = dmbd::diagrams::linearize(*diagram, argv[2], argv[3]);
    std::printf("%s -> %s: order %d, dc gain %.6g\n", argv[2], argv[3], static_cast<int>(sys.poles().size()),
                sys.to_tf().dc_gain().value_or(0.0));

    const auto robot = dmbd::model::load_urdf(dmbd::model::find_robot("draco").urdf);
    std::printf("DRACO: %.3f kg\n", robot.total_mass_kg());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 2;
  }
  return 0;
}
