#include "diagram_picture.hpp"

namespace dmbd::apps {

namespace {

std::string label(const diagrams::SignalSpec& s) { return s.name + (s.unit.empty() ? "" : " [" + s.unit + "]"); }

std::string summary(const diagrams::Block& b) {
  std::string s;
  for (const auto& [k, v] : b.fields) {
    if (k == "description" || k == "parameters") continue;
    const std::string item = b.type == diagrams::BlockType::Tf && k == "expr" ? v : k + ": " + v;
    s += (s.empty() ? "" : ", ") + item;
  }
  return s;
}

viz::DiagramPicture::Block block(const diagrams::Block& b) {
  viz::DiagramPicture::Block out{b.name, diagrams::to_string(b.type), summary(b), {}, {}};
  for (std::size_t k = 0; k < b.inputs.size(); ++k)
    out.input_labels.push_back(b.type == diagrams::BlockType::Sum && k < b.signs.size() ? (b.signs[k] > 0 ? "+" : "-") : b.inputs[k].name);
  for (const auto& p : b.outputs) out.output_labels.push_back(p.name);
  return out;
}

}  // namespace

viz::DiagramPicture diagram_picture(const diagrams::Diagram& d) {
  viz::DiagramPicture p;
  p.title = d.name() + (d.description().empty() ? "" : ": " + d.description());
  for (const auto& s : d.inputs()) p.inputs.push_back(label(s));
  for (const auto& s : d.outputs()) p.outputs.push_back(label(s));
  for (int b = 0; b < static_cast<int>(d.blocks().size()); ++b) {
    p.blocks.push_back(block(d.blocks()[static_cast<std::size_t>(b)]));
    auto& drv = p.drivers.emplace_back();
    for (const auto& s : d.drivers(b)) drv.push_back({s.block, s.port});
  }
  for (int j = 0; j < static_cast<int>(d.outputs().size()); ++j) p.output_drivers.push_back({d.output_driver(j).block, d.output_driver(j).port});
  return p;
}

}  // namespace dmbd::apps
