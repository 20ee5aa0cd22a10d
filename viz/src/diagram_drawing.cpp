#include "dmbd/viz/diagram_drawing.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "dmbd/viz/plot.hpp"

namespace dmbd::viz {

namespace {

constexpr int kBoxW = 190, kBoxH = 78, kIoW = 120, kIoH = 40;
constexpr int kLayerGap = 110, kRowGap = 50, kMargin = 50, kLane = 26;
const cv::Scalar kInk(40, 40, 40), kBlue(180, 119, 31), kGrey(120, 120, 120), kFill(250, 244, 236),
    kIoFill(236, 246, 236);

int text_width(const std::string& text, double scale, int thickness) {
  int base = 0;
  return cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &base).width;
}

int widest(const std::vector<std::string>& labels, double scale) {
  int w = 0;
  for (const auto& l : labels) w = std::max(w, text_width(l, scale, 1));
  return w;
}

// Wide enough for its name, kind and summary (up to 360 px: longer summaries end in an
// ellipsis) between the port names on either side (written where a block has several).
int block_width(const DiagramPicture::Block& b) {
  const int centre = std::max({text_width(b.name, 0.62, 2), text_width(b.kind, 0.45, 1), std::min(360, text_width(b.summary, 0.4, 1))});
  const int in = b.input_labels.size() > 1 ? widest(b.input_labels, 0.4) + 8 : 0;
  const int out = b.output_labels.size() > 1 ? widest(b.output_labels, 0.4) + 8 : 0;
  return std::max(kBoxW, centre + 2 * std::max(in, out) + 24);
}

// Fit text into a width by shortening it with an ellipsis.
std::string fit(const std::string& text, double scale, int thickness, int width) {
  int base = 0;
  if (cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &base).width <= width) return text;
  std::string t = text;
  while (t.size() > 1 && cv::getTextSize(t + "...", cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &base).width > width)
    t.pop_back();
  return t + "...";
}

void centered(cv::Mat& img, const std::string& text, cv::Point c, double scale, int thickness, cv::Scalar color) {
  int base = 0;
  const cv::Size ts = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &base);
  cv::putText(img, text, {c.x - ts.width / 2, c.y + ts.height / 2}, cv::FONT_HERSHEY_SIMPLEX, scale, color, thickness,
              cv::LINE_AA);
}

void arrow_head(cv::Mat& img, cv::Point tip, cv::Point dir, cv::Scalar color) {
  const cv::Point2d d(dir.x, dir.y);
  const double n = std::max(1e-9, std::hypot(d.x, d.y));
  const cv::Point2d u = d / n, p(-u.y, u.x);
  std::vector<cv::Point> tri = {tip, tip - cv::Point(cvRound(11 * u.x - 5 * p.x), cvRound(11 * u.y - 5 * p.y)),
                                tip - cv::Point(cvRound(11 * u.x + 5 * p.x), cvRound(11 * u.y + 5 * p.y))};
  cv::fillConvexPoly(img, tri, color, cv::LINE_AA);
}

}  // namespace

DiagramLayout layout_diagram(const DiagramPicture& d) {
  DiagramLayout L;
  const int ni = static_cast<int>(d.inputs.size()), nb = static_cast<int>(d.blocks.size()),
            no = static_cast<int>(d.outputs.size());
  if (d.drivers.size() != d.blocks.size() || d.output_drivers.size() != d.outputs.size())
    throw std::invalid_argument("viz::layout_diagram: one driver list per block and one driver per output expected");
  for (int i = 0; i < ni; ++i) L.nodes.push_back({d.inputs[static_cast<size_t>(i)], 0, i, 0, 0, {}});
  for (int i = 0; i < nb; ++i) L.nodes.push_back({d.blocks[static_cast<size_t>(i)].name, 1, i, 0, 0, {}});
  for (int i = 0; i < no; ++i) L.nodes.push_back({d.outputs[static_cast<size_t>(i)], 2, i, 0, 0, {}});
  auto node_of = [&](const DiagramPicture::Source& s) { return s.block < 0 ? s.port : ni + s.block; };
  for (int bi = 0; bi < nb; ++bi) {
    const auto& drv = d.drivers[static_cast<size_t>(bi)];
    for (size_t k = 0; k < drv.size(); ++k)
      L.edges.push_back({node_of(drv[k]), ni + bi, drv[k].block < 0 ? 0 : drv[k].port, static_cast<int>(k), false, {}});
  }
  for (int j = 0; j < no; ++j) {
    const auto& src = d.output_drivers[static_cast<size_t>(j)];
    L.edges.push_back({node_of(src), ni + nb + j, src.block < 0 ? 0 : src.port, 0, false, {}});
  }
  const int n = static_cast<int>(L.nodes.size());

  // Feedback edges: back edges of a depth-first search from the inputs (then from any
  // node not reached), visiting successors in connection order.
  std::vector<std::vector<int>> out(static_cast<size_t>(n));
  for (size_t e = 0; e < L.edges.size(); ++e) out[static_cast<size_t>(L.edges[e].from)].push_back(static_cast<int>(e));
  std::vector<int> state(static_cast<size_t>(n), 0);
  std::function<void(int)> dfs = [&](int v) {
    state[static_cast<size_t>(v)] = 1;
    for (int e : out[static_cast<size_t>(v)]) {
      const int w = L.edges[static_cast<size_t>(e)].to;
      if (state[static_cast<size_t>(w)] == 1) {
        L.edges[static_cast<size_t>(e)].feedback = true;
      } else if (state[static_cast<size_t>(w)] == 0) {
        dfs(w);
      }
    }
    state[static_cast<size_t>(v)] = 2;
  };
  for (int v = 0; v < ni; ++v)
    if (!state[static_cast<size_t>(v)]) dfs(v);
  for (int v = 0; v < n; ++v)
    if (!state[static_cast<size_t>(v)]) dfs(v);

  // Layers: longest path over forward edges; outputs in the last layer.
  bool changed = true;
  for (int it = 0; changed && it < n + 1; ++it) {
    changed = false;
    for (const auto& e : L.edges) {
      if (e.feedback) continue;
      auto& a = L.nodes[static_cast<size_t>(e.from)];
      auto& b = L.nodes[static_cast<size_t>(e.to)];
      if (b.layer < a.layer + 1) b.layer = a.layer + 1, changed = true;
    }
  }
  int last = 0;
  for (const auto& nd : L.nodes)
    if (nd.kind != 2) last = std::max(last, nd.layer);
  for (auto& nd : L.nodes)
    if (nd.kind == 2) nd.layer = last + 1;
  L.layers = last + 2;

  // Long forward connections get a bend point in every layer they cross, so that they
  // take their own row there instead of running through other blocks.
  std::vector<std::pair<int, int>> segments;
  for (auto& e : L.edges) {
    if (e.feedback) continue;
    int prev = e.from;
    for (int l = L.nodes[static_cast<size_t>(e.from)].layer + 1; l < L.nodes[static_cast<size_t>(e.to)].layer; ++l) {
      L.nodes.push_back({"", 3, 0, l, 0, {}});
      const int dn = static_cast<int>(L.nodes.size()) - 1;
      e.via.push_back(dn);
      segments.push_back({prev, dn});
      prev = dn;
    }
    segments.push_back({prev, e.to});
  }
  const int n_all = static_cast<int>(L.nodes.size());

  // Order within layers: barycentre sweeps.
  std::vector<std::vector<int>> layer(static_cast<size_t>(L.layers));
  for (int v = 0; v < n_all; ++v) layer[static_cast<size_t>(L.nodes[static_cast<size_t>(v)].layer)].push_back(v);
  auto renumber = [&] {
    for (auto& l : layer)
      for (size_t k = 0; k < l.size(); ++k) L.nodes[static_cast<size_t>(l[k])].order = static_cast<int>(k);
  };
  renumber();
  for (int sweep = 0; sweep < 8; ++sweep) {
    for (auto& l : layer) {
      std::vector<std::pair<double, int>> key;
      for (int v : l) {
        double sum = 0;
        int cnt = 0;
        for (const auto& [from, to] : segments) {
          if (to == v) sum += L.nodes[static_cast<size_t>(from)].order, ++cnt;
          if (sweep % 2 && from == v) sum += L.nodes[static_cast<size_t>(to)].order, ++cnt;
        }
        key.push_back({cnt ? sum / cnt : L.nodes[static_cast<size_t>(v)].order, v});
      }
      std::stable_sort(key.begin(), key.end());
      for (size_t k = 0; k < l.size(); ++k) l[k] = key[k].second;
      renumber();
    }
  }

  // Coordinates: each layer a column as wide as its widest node, its nodes stacked with
  // their own heights (a block grows with its number of ports), columns centred
  // vertically; the gap before a column widens with the wires that turn in it.
  auto width_of = [&](const DiagramLayout::Node& nd) {
    if (nd.kind == 3) return 2;
    if (nd.kind != 1) return std::max(kIoW, text_width(nd.kind == 0 ? d.inputs[static_cast<size_t>(nd.index)] : d.outputs[static_cast<size_t>(nd.index)], 0.55, 1) + 24);
    return block_width(d.blocks[static_cast<size_t>(nd.index)]);
  };
  auto height_of = [&](const DiagramLayout::Node& nd) {
    if (nd.kind == 3) return 2;
    if (nd.kind != 1) return kIoH;
    const auto& b = d.blocks[static_cast<size_t>(nd.index)];
    const int ports = static_cast<int>(std::max(b.input_labels.size(), b.output_labels.size()));
    return std::max(kBoxH, 24 * ports + 12);
  };
  std::vector<int> column(static_cast<size_t>(L.layers), 0);
  for (size_t l = 0; l < layer.size(); ++l)
    for (int v : layer[l]) column[l] += height_of(L.nodes[static_cast<size_t>(v)]) + kRowGap;
  const int body = *std::max_element(column.begin(), column.end());
  int nfb = 0;
  for (const auto& e : L.edges) nfb += e.feedback ? 1 : 0;
  std::vector<int> turns(static_cast<size_t>(L.layers), 0);  // forward wires arriving in each column
  for (const auto& [from, to] : segments) ++turns[static_cast<size_t>(L.nodes[static_cast<size_t>(to)].layer)];
  L.column_x.assign(static_cast<size_t>(L.layers), 0);
  L.column_w.assign(static_cast<size_t>(L.layers), kIoW);
  for (size_t l = 0; l < layer.size(); ++l)
    for (int v : layer[l]) L.column_w[l] = std::max(L.column_w[l], width_of(L.nodes[static_cast<size_t>(v)]));
  int x = kMargin;
  for (size_t l = 0; l < layer.size(); ++l) {
    if (l > 0) x += std::max(kLayerGap, 12 * (turns[l] + 1));
    L.column_x[l] = x;
    x += L.column_w[l];
  }
  L.size = cv::Size(x + kMargin, 2 * kMargin + 20 + body + nfb * kLane + 30);
  for (size_t l = 0; l < layer.size(); ++l) {
    int y = kMargin + 20 + (body - column[l]) / 2;
    for (int v : layer[l]) {
      auto& nd = L.nodes[static_cast<size_t>(v)];
      const int cx = L.column_x[l] + L.column_w[l] / 2;
      const int w = nd.kind == 3 ? L.column_w[l] : width_of(nd), h = height_of(nd);
      const int slot = h + kRowGap;
      nd.box = cv::Rect(cx - w / 2, y + (slot - h) / 2, w, h);
      y += slot;
    }
  }
  return L;
}

cv::Mat draw_diagram(const DiagramPicture& d) {
  const DiagramLayout L = layout_diagram(d);
  if (L.size.width > kMaxDrawingSide || L.size.height > kMaxDrawingSide)
    throw InputError("a drawing of diagram '" + d.title + "' (" + std::to_string(d.blocks.size()) + " blocks in " +
                     std::to_string(L.layers) + " columns) would be " + std::to_string(L.size.width) + " x " +
                     std::to_string(L.size.height) + " pixels, more than " + std::to_string(kMaxDrawingSide) +
                     " a side: group blocks into subsystems and draw those");
  cv::Mat img(L.size, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::string& title = d.title;
  cv::putText(img, fit(title, 0.7, 2, L.size.width - 2 * kMargin), {kMargin, 38}, cv::FONT_HERSHEY_SIMPLEX, 0.7, kInk,
              2, cv::LINE_AA);

  auto port_point = [&](int node, int port, bool output) {
    const auto& nd = L.nodes[static_cast<size_t>(node)];
    int count = 1;
    if (nd.kind == 1) {
      const auto& b = d.blocks[static_cast<size_t>(nd.index)];
      count = static_cast<int>(output ? b.output_labels.size() : b.input_labels.size());
    }
    const int y = nd.box.y + nd.box.height * (2 * port + 1) / (2 * std::max(1, count));
    return cv::Point(output ? nd.box.x + nd.box.width : nd.box.x, y);
  };

  // Forward connections: through their bend points, each turning on its own vertical
  // lane in the gap before the column it enters (lanes ordered by where they arrive, so
  // wires do not share a segment); feedback connections in lanes below.
  struct Hop {
    std::size_t edge;
    cv::Point leave, arrive;
    int layer, x = 0;
  };
  std::vector<Hop> hops;
  for (std::size_t i = 0; i < L.edges.size(); ++i) {
    const auto& e = L.edges[i];
    const cv::Point a = port_point(e.from, e.from_port, true), b = port_point(e.to, e.to_port, false);
    if (e.feedback || b.x <= a.x) continue;
    cv::Point leave = a;
    for (int v : e.via) {
      const auto& nd = L.nodes[static_cast<size_t>(v)];
      hops.push_back({i, leave, {nd.box.x, nd.box.y}, nd.layer});
      leave = {nd.box.x + nd.box.width, nd.box.y};
    }
    hops.push_back({i, leave, b, L.nodes[static_cast<size_t>(e.to)].layer});
  }
  for (int l = 1; l < L.layers; ++l) {
    std::vector<Hop*> in;
    for (auto& h : hops)
      if (h.layer == l) in.push_back(&h);
    std::stable_sort(in.begin(), in.end(), [](const Hop* p, const Hop* q) {
      return p->arrive.y != q->arrive.y ? p->arrive.y < q->arrive.y : p->leave.y < q->leave.y;
    });
    const int x0 = L.column_x[static_cast<size_t>(l - 1)] + L.column_w[static_cast<size_t>(l - 1)], x1 = L.column_x[static_cast<size_t>(l)];
    for (std::size_t k = 0; k < in.size(); ++k)
      in[k]->x = x0 + static_cast<int>((static_cast<double>(k) + 1) * (x1 - x0) / (static_cast<double>(in.size()) + 1));
  }
  int lane = 0;
  const int bottom = L.size.height - kMargin;
  for (std::size_t i = 0; i < L.edges.size(); ++i) {
    const auto& e = L.edges[i];
    const cv::Point a = port_point(e.from, e.from_port, true), b = port_point(e.to, e.to_port, false);
    std::vector<cv::Point> path{a};
    bool routed = false;
    for (const auto& h : hops) {
      if (h.edge != i) continue;
      routed = true;
      path.push_back({h.x, h.leave.y});
      path.push_back({h.x, h.arrive.y});
      path.push_back(h.arrive);
    }
    if (!routed) {
      const int y = bottom - lane * kLane;
      ++lane;
      path = {a, {a.x + 20 + 6 * lane, a.y}, {a.x + 20 + 6 * lane, y}, {b.x - 24 - 6 * lane, y}, {b.x - 24 - 6 * lane, b.y}, b};
    }
    const cv::Scalar color = e.feedback ? kBlue : kInk;
    cv::polylines(img, path, false, color, 2, cv::LINE_AA);
    arrow_head(img, b, b - path[path.size() - 2], color);
  }

  // Nodes.
  for (const auto& nd : L.nodes) {
    if (nd.kind == 3) continue;
    if (nd.kind == 1) {
      const auto& b = d.blocks[static_cast<size_t>(nd.index)];
      cv::rectangle(img, nd.box, kFill, cv::FILLED);
      cv::rectangle(img, nd.box, kInk, 2, cv::LINE_AA);
      const cv::Point c(nd.box.x + nd.box.width / 2, nd.box.y + nd.box.height / 2);
      centered(img, fit(b.name, 0.62, 2, nd.box.width - 12), {c.x, c.y - 18}, 0.62, 2, kInk);
      centered(img, b.kind, {c.x, c.y + 4}, 0.45, 1, kGrey);
      centered(img, fit(b.summary, 0.4, 1, nd.box.width - 12), {c.x, c.y + 24}, 0.4, 1, kInk);
      // Port names where a block has several.
      for (size_t k = 0; b.input_labels.size() > 1 && k < b.input_labels.size(); ++k) {
        const cv::Point p = port_point(static_cast<int>(&nd - &L.nodes[0]), static_cast<int>(k), false);
        cv::putText(img, b.input_labels[k], {p.x + 4, p.y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.4, kBlue, 1, cv::LINE_AA);
      }
      for (size_t k = 0; b.output_labels.size() > 1 && k < b.output_labels.size(); ++k) {
        const cv::Point p = port_point(static_cast<int>(&nd - &L.nodes[0]), static_cast<int>(k), true);
        int base = 0;
        const int w = cv::getTextSize(b.output_labels[k], cv::FONT_HERSHEY_SIMPLEX, 0.4, 1, &base).width;
        cv::putText(img, b.output_labels[k], {p.x - w - 4, p.y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.4, kBlue, 1, cv::LINE_AA);
      }
    } else {
      const std::string& label = nd.kind == 0 ? d.inputs[static_cast<size_t>(nd.index)] : d.outputs[static_cast<size_t>(nd.index)];
      cv::rectangle(img, nd.box, kIoFill, cv::FILLED);
      cv::rectangle(img, nd.box, kGrey, 1, cv::LINE_AA);
      centered(img, fit(label, 0.55, 1, nd.box.width - 8), {nd.box.x + nd.box.width / 2, nd.box.y + nd.box.height / 2}, 0.55, 1,
               kInk);
    }
  }
  return img;
}

void save_diagram_png(const DiagramPicture& d, const std::string& path) {
  dmbd::write_file_atomic(path, encode_png(draw_diagram(d)));
}

}  // namespace dmbd::viz
