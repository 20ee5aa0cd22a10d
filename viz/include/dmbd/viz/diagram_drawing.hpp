#pragma once
// `dmbd draw`: a block diagram as a picture. Blocks are labelled boxes, connections
// arrows; the layout is layered (Sugiyama style): inputs on the left, outputs on the
// right, feedback connections routed in lanes below the blocks.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::viz {

// Where each node of a diagram goes (exposed for tests).
struct DiagramLayout {
  struct Node {
    std::string name;
    int kind = 0;   // 0 diagram input, 1 block, 2 diagram output, 3 bend point of a long connection
    int index = 0;  // into inputs / blocks / outputs
    int layer = 0, order = 0;
    cv::Rect box;   // pixels
  };
  struct Edge {
    int from = 0, to = 0;          // node indices
    int from_port = 0, to_port = 0;
    bool feedback = false;         // routed below, right to left
    std::vector<int> via;          // bend-point nodes of a connection spanning several layers
  };
  std::vector<Node> nodes;
  std::vector<Edge> edges;
  int layers = 0;
  cv::Size size;
};

DiagramLayout layout_diagram(const diagrams::Diagram& d);
cv::Mat draw_diagram(const diagrams::Diagram& d);
// Render and write a PNG atomically.
void save_diagram_png(const diagrams::Diagram& d, const std::string& path);

}  // namespace dmbd::viz
