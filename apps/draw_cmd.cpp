#include "draw_cmd.hpp"

#include <filesystem>
#include <iostream>

#include "cli_values.hpp"
#include "diagram_picture.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/viz/diagram_drawing.hpp"

namespace dmbd::apps {

DrawCommand::DrawCommand(CLI::App& app)
    : Command(app, "draw", "Draw a block diagram as a PNG (layered layout, feedback routed below)") {
  cmd_->add_option("diagram", diagram_, "A diagram file (YAML)")->required();
  cmd_->add_option("--out", out_, "PNG file to write")->required();
  cmd_->add_option("--param", params_, "NAME=VALUE parameter override; repeatable");
}

int DrawCommand::run() {
  const blocks::ParameterMap params = parse_params(params_);
  if (std::filesystem::path(out_).extension() != ".png")
    throw InputError("--out '" + out_ + "': dmbd draw writes PNG images (expected a file name ending in .png)");
  check_output_file(out_, "--out");
  const auto d = diagrams::Diagram::load(diagram_, params);
  viz::save_diagram_png(diagram_picture(*d), out_);
  std::cout << "wrote " << out_ << "\n";
  return 0;
}

}  // namespace dmbd::apps
