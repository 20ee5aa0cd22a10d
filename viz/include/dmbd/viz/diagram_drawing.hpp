#pragma once
// `dmbd draw`: a block diagram as a picture. Blocks are labelled boxes, connections
// arrows; the layout is layered (Sugiyama style): inputs on the left, outputs on the
// right, feedback connections routed in lanes below the blocks. viz draws a plain
// description of the diagram (apps/ builds it from a diagrams::Diagram): it does not
// know the diagram module.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace dmbd::viz {

// A block diagram to draw.
struct DiagramPicture {
  std::string title;
  std::vector<std::string> inputs, outputs;  // the diagram's inputs and outputs, e.g. "q_d [rad]"
  struct Block {
    std::string name, kind, summary;          // e.g. "Kd", "tf", "D_q*s/(tau_q*s + 1)"
    // One per port; written beside the ports of a block that has several (a sum's signs).
    std::vector<std::string> input_labels, output_labels;
  };
  std::vector<Block> blocks;
  // What drives a block input or a diagram output: a diagram input (block -1, port its
  // index) or the output port of a block.
  struct Source {
    int block = -1;
    int port = 0;
  };
  std::vector<std::vector<Source>> drivers;  // per block, per input port
  std::vector<Source> output_drivers;        // per diagram output
};

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
  std::vector<int> column_x, column_w;  // each layer's column: left edge and width (pixels)
  cv::Size size;
};

// Throws std::invalid_argument when drivers and blocks (or outputs) do not match.
DiagramLayout layout_diagram(const DiagramPicture& d);
// The largest side of a drawing in pixels (a 16384 x 16384 image is 800 MB; PNG readers
// and OpenCV's encoder refuse far less): a larger layout is an InputError.
constexpr int kMaxDrawingSide = 16384;
cv::Mat draw_diagram(const DiagramPicture& d);
// Render and write a PNG atomically.
void save_diagram_png(const DiagramPicture& d, const std::string& path);

}  // namespace dmbd::viz
