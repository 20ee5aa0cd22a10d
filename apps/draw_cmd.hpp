#pragma once
// `dmbd draw DIAGRAM --out FILE.png`: a block diagram as a PNG (layered layout, feedback
// routed below; viz/diagram_drawing.hpp, laid out from the diagram in
// diagram_picture.cpp).
#include <string>
#include <vector>

#include "command.hpp"

namespace dmbd::apps {

class DrawCommand : public Command {
 public:
  explicit DrawCommand(CLI::App& app);
  int run() override;

 private:
  std::string diagram_, out_;
  std::vector<std::string> params_;
};

}  // namespace dmbd::apps
