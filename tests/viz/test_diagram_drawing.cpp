// Block-diagram pictures (dmbd draw; issue 13, item 5): a wire from the second diagram
// input starts at that input's box, terminal boxes hold their whole label, a block
// with several ports is wide enough for its port names beside its own text, nodes of a
// column do not overlap, and the picture draws.
#include "dmbd/viz/diagram_drawing.hpp"
#include "dmbd/base/error.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace dmbd::viz {
namespace {

// u1, u2 -> sum(+,-) -> plant (3 outputs) -> y1 [rad], a_long_output_name [N m], y3.
DiagramPicture picture() {
  DiagramPicture p;
  p.title = "test";
  p.inputs = {"u1 [A]", "second_input_with_a_long_name [N]"};
  p.outputs = {"y1 [rad]", "a_long_output_name [N m]", "y3"};
  p.blocks.push_back({"err", "sum", "signs: +-", {"+", "-"}, {"y"}});
  p.blocks.push_back({"plant", "subsystem", "file: a_subsystem_file.yaml", {"in"}, {"theta_motor", "x_elastomer", "q"}});
  p.drivers = {{{-1, 0}, {-1, 1}}, {{0, 0}}};
  p.output_drivers = {{1, 0}, {1, 1}, {1, 2}};
  return p;
}

int text_width(const std::string& t, double scale) {
  int base = 0;
  return cv::getTextSize(t, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &base).width;
}

TEST(DiagramDrawing, PortsBoxesAndColumns) {
  const DiagramPicture p = picture();
  const DiagramLayout L = layout_diagram(p);
  for (const auto& e : L.edges) {
    if (L.nodes[static_cast<std::size_t>(e.from)].kind == 0) {
      EXPECT_EQ(e.from_port, 0) << "a diagram input node has one port";
    }
  }
  for (const auto& nd : L.nodes) {
    if (nd.kind == 0 || nd.kind == 2) {
      const std::string& label = nd.kind == 0 ? p.inputs[static_cast<std::size_t>(nd.index)] : p.outputs[static_cast<std::size_t>(nd.index)];
      EXPECT_GE(nd.box.width, text_width(label, 0.55) + 8) << label << " does not fit its box";
    }
    if (nd.kind == 1 && nd.index == 1) {  // the plant: port names on the right, its text in the middle
      EXPECT_GE(nd.box.width, text_width("file: a_subsystem_file.yaml", 0.4) + 2 * text_width("x_elastomer", 0.4));
    }
    const auto l = static_cast<std::size_t>(nd.layer);
    EXPECT_GE(nd.box.x, L.column_x[l] - 1);
    EXPECT_LE(nd.box.x + nd.box.width, L.column_x[l] + L.column_w[l] + 1);
  }
  for (std::size_t a = 0; a < L.nodes.size(); ++a) {
    for (std::size_t b = a + 1; b < L.nodes.size(); ++b) {
      if (L.nodes[a].kind == 3 || L.nodes[b].kind == 3) continue;
      EXPECT_TRUE((L.nodes[a].box & L.nodes[b].box).empty()) << L.nodes[a].name << " overlaps " << L.nodes[b].name;
    }
  }
  const cv::Mat img = draw_diagram(p);
  EXPECT_EQ(img.size(), L.size);
}

TEST(DiagramDrawing, MismatchedDriversAreRefused) {
  DiagramPicture p = picture();
  p.drivers.pop_back();
  EXPECT_THROW(layout_diagram(p), std::invalid_argument);
}

// Issue 13, item 10: 10,000 blocks in a chain would be a 3,000,000-pixel-wide image that
// cannot be encoded (2,000 here: 600,000 pixels): a user error naming the size, before
// any pixel is allocated.
TEST(DiagramDrawing, ADrawingTooLargeIsRefusedWithItsSize) {
  DiagramPicture p;
  p.title = "chain";
  p.inputs = {"u"};
  p.outputs = {"y"};
  for (int k = 0; k < 2000; ++k) {
    p.blocks.push_back({"g" + std::to_string(k), "gain", "k: 1", {"u"}, {"y"}});
    p.drivers.push_back({k == 0 ? DiagramPicture::Source{-1, 0} : DiagramPicture::Source{k - 1, 0}});
  }
  p.output_drivers = {{1999, 0}};
  try {
    draw_diagram(p);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("2000 blocks"), std::string::npos) << m;
    EXPECT_NE(m.find("more than 16384 a side"), std::string::npos) << m;
  }
  p.blocks.resize(20);  // a chain of 20 fits
  p.drivers.resize(20);
  p.output_drivers = {{19, 0}};
  EXPECT_LE(draw_diagram(p).cols, kMaxDrawingSide);
}

}  // namespace
}  // namespace dmbd::viz
