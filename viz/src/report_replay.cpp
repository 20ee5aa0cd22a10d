// The report page's 3-D replay section: the controls, the view, the setup the player
// reads (the camera, the variants' scripts) and the scripts at the end of the page.
#include "report_replay.hpp"

#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace dmbd::viz::detail {

const char* const kReplayCss = R"css(
.replay-bar { display: flex; flex-wrap: wrap; align-items: center; gap: 6px 14px; margin: 0 0 8px; font-size: 0.95em; }
.replay-bar input[type=range] { flex: 1 1 240px; }
.replay-bar #replay-clock { font-variant-numeric: tabular-nums; min-width: 8.5em; }
.replay-view {
  position: relative; width: 100%; overflow: hidden; border: 1px solid #d0d7de; border-radius: 4px;
  background: linear-gradient(to bottom, rgb(92, 124, 168), rgb(214, 222, 230));
}
.replay-view canvas { display: block; touch-action: none; }
#replay-hud { position: absolute; inset: 0; pointer-events: none; color: #ffffff; font-size: 13px; line-height: 1.35;
  font-family: ui-monospace, "DejaVu Sans Mono", Menlo, Consolas, monospace; }
#replay-hud .lines { position: absolute; left: 8px; top: 8px; padding: 4px 8px; background: rgba(20, 24, 30, 0.6); border-radius: 3px; }
#replay-hud .legend { position: absolute; right: 8px; top: 8px; padding: 4px 8px; background: rgba(20, 24, 30, 0.6); border-radius: 3px; }
#replay-hud .swatch { display: inline-block; width: 22px; margin: 0 6px 3px 0; border-top: 3px solid; vertical-align: middle; }
#replay-hud .swatch.dashed { border-top-style: dashed; }
body.replay-only { background: #ffffff; }
body.replay-only main { margin: 0; padding: 0; border: 0; max-width: none; }
body.replay-only main > *:not(#replay), body.replay-only #replay > *:not(#replay-view) { display: none; }
body.replay-only .replay-view { border: 0; border-radius: 0; width: auto; display: inline-block; }
)css";

namespace {

// The setup the player reads: JSON inside a <script type="application/json"> element, so
// '<' is escaped ("</script>" in a title cannot end the element).
std::string setup_json(const ReportReplay& r) {
  const Camera& c = r.camera;
  const auto v3 = [](const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
  nlohmann::json j = {{"camera",
                       {{"position", v3(c.position)}, {"look_at", v3(c.look_at)}, {"up", v3(c.up)}, {"fov_y_deg", c.fov_y_deg},
                        {"width", c.width_px}, {"height", c.height_px}, {"near_m", c.near_m}}},
                      {"light_from", v3(RenderStyle{}.light_from_W)},
                      {"initial", r.initial},
                      {"title", r.title},
                      {"scripts", r.scripts},
                      {"force_scale_m_per_N", r.force_scale_m_per_N}};
  std::string text;
  for (const char ch : j.dump()) text += ch == '<' ? std::string("\\u003c") : std::string(1, ch);
  return text;
}

std::string variant_options(const ReportReplay& r) {
  std::string out;
  for (std::size_t i = 0; i < r.variants.size(); ++i) {
    const ReportReplayVariant& v = r.variants[i];
    out += fmt::format("<option value=\"{}\" data-track=\"{}\" data-scene=\"{}\"{}>{}</option>\n", i,
                       report_url(v.track, fmt::format("replay.variants[{}].track", i)),
                       report_url(v.scene, fmt::format("replay.variants[{}].scene", i)), i == r.initial ? " selected" : "",
                       html_escape(v.name));
  }
  return out;
}

}  // namespace

void replay_section(const ReportReplay& r, std::string& out) {
  if (r.variants.empty()) return;
  if (r.initial >= r.variants.size())
    throw std::invalid_argument(fmt::format("viz: report replay.initial {} of {} variants", r.initial, r.variants.size()));
  if (r.scripts.size() != 2) throw std::invalid_argument("viz: report replay.scripts: expected three.min.js and OrbitControls.js");
  validate(r.camera);
  out += "<section id=\"replay\" data-state=\"loading\">\n<h2>3-D replay</h2>\n<div class=\"replay-bar\">\n";
  out += "<button type=\"button\" id=\"replay-play\">Play</button>\n";
  out += "<input type=\"range\" id=\"replay-time\" min=\"0\" max=\"1\" step=\"any\" value=\"0\" aria-label=\"time\">\n";
  out += "<span id=\"replay-clock\">t = 0.000 s</span>\n<label>speed <select id=\"replay-speed\">";
  for (const char* s : {"0.1", "0.25", "0.5", "1", "2", "4"})
    out += fmt::format("<option value=\"{0}\"{1}>{0}&#215;</option>", s, std::string(s) == "1" ? " selected" : "");
  out += "</select></label>\n";
  out += fmt::format("<label>variant <select id=\"replay-variant\"{}>\n{}</select></label>\n", r.variants.size() < 2 ? " disabled" : "",
                     variant_options(r));
  out += "<label><input type=\"checkbox\" id=\"replay-ground\" checked> ground</label>\n";
  out += "<label><input type=\"checkbox\" id=\"replay-overlays\" checked> overlays</label>\n";
  out += "<button type=\"button\" id=\"replay-reset\">Reset view</button>\n</div>\n";
  out += fmt::format("<div class=\"replay-view\" id=\"replay-view\" style=\"aspect-ratio: {} / {}\">\n<canvas id=\"replay-canvas\" "
                     "width=\"{}\" height=\"{}\"></canvas>\n<div id=\"replay-hud\"></div>\n</div>\n",
                     r.camera.width_px, r.camera.height_px, r.camera.width_px, r.camera.height_px);
  out += "<p id=\"replay-message\" class=\"muted\"></p>\n";
  const std::string how = "Drag to orbit, right-drag to pan, scroll to zoom.";
  out += fmt::format("<p class=\"muted\">{}", html_escape(r.caption.empty() ? how : r.caption + " " + how));
  if (!r.licence.empty()) out += fmt::format(" <a href=\"{}\">three.js licence</a>", report_url(r.licence, "replay.licence"));
  out += "</p>\n";
  out += "<script type=\"application/json\" id=\"replay-setup\">" + setup_json(r) + "</script>\n</section>\n";
}

void replay_scripts(const ReportReplay& r, std::string& out) {
  if (r.variants.empty()) return;
  for (std::size_t i = 0; i < r.scripts.size(); ++i)
    out += fmt::format("<script src=\"{}\"></script>\n", report_url(r.scripts[i], fmt::format("replay.scripts[{}]", i)));
  out += std::string("<script>") + kReplayPlayerJs + "</script>\n";
}

}  // namespace dmbd::viz::detail
