// run_scenario: runs the variants and writes log.csv, metrics.json, plots, frames,
// video and report.html.
#include "dmbd/sim/outputs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "dmbd/blocks/error.hpp"
#include "dmbd/viz/plot.hpp"
#include "dmbd/viz/renderer.hpp"
#include "dmbd/viz/report.hpp"
#include "dmbd/viz/robot_scene.hpp"
#include "dmbd/viz/video.hpp"

namespace dmbd::sim {

namespace fs = std::filesystem;

namespace {

void write_text(const fs::path& p, const std::string& s) { viz::write_file_atomic(p.string(), std::vector<unsigned char>(s.begin(), s.end())); }

std::string num(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : (std::isnan(v) ? "NaN" : (v > 0 ? "inf" : "-inf")); }

// JSON cannot hold inf/NaN: they become strings.
nlohmann::json finite_json(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::json o = nlohmann::json::object();
    for (auto it = j.begin(); it != j.end(); ++it) o[it.key()] = finite_json(it.value());
    return o;
  }
  if (j.is_array()) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& e : j) a.push_back(finite_json(e));
    return a;
  }
  if (j.is_number_float() && !std::isfinite(j.get<double>())) return num(j.get<double>());
  return j;
}

// Renders the frame variant: one PNG per frame into frames/, the same images into
// video.mp4.
struct FrameSink {
  FrameSink(const Scenario& scenario, fs::path out) : s(scenario), dir(std::move(out)) {}
  const Scenario& s;
  fs::path dir;
  bool enabled = false;
  std::optional<viz::Renderer> renderer;
  viz::Camera camera;
  std::optional<viz::VideoWriter> video;
  std::vector<viz::ReportFrame> frames;
  double render_s = 0;
  std::string variant;

  void frame(double t, const model::Plant& plant) {
    const auto X = plant.link_poses();
    if (!renderer) {
      renderer.emplace(s.frames.width_px, s.frames.height_px);
      const viz::Scene scene = viz::scene_from_robot(plant.description());
      renderer->set_scene(scene);
      camera.width_px = s.frames.width_px;
      camera.height_px = s.frames.height_px;
      if (s.frames.camera_position && s.frames.camera_look_at) {
        camera.position = *s.frames.camera_position;
        camera.look_at = *s.frames.camera_look_at;
      } else {
        // A three-quarter view from the front left that frames the robot's bounds.
        const Eigen::AlignedBox3d b = viz::scene_bounds(scene, X);
        const double size = std::max(b.diagonal().norm(), 0.6);
        camera.look_at = b.center();
        camera.position = b.center() + 1.5 * size * Eigen::Vector3d(0.62, -0.70, 0.35).normalized();
      }
      fs::create_directories(dir / "frames");
      video.emplace((dir / "video.mp4").string(), s.frames.fps);
    }
    viz::Overlays o;
    o.text_lines = {s.name + "  |  " + variant, fmt::format("t = {:.3f} s", t)};
    o.com_W = plant.com_position();
    for (const auto& c : plant.contacts())
      if (c.force_W.norm() > 1e-3) o.forces.push_back({c.p_W, c.force_W, viz::Color{230, 50, 40}});
    const auto t0 = std::chrono::steady_clock::now();
    const cv::Mat& img = renderer->render(X, camera, o);
    render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string name = fmt::format("frames/frame_{:05d}.png", frames.size());
    viz::write_file_atomic((dir / name).string(), viz::encode_png(img));
    video->write(img);
    frames.push_back({name, t});
  }
};

}  // namespace

std::string combined_csv(const std::vector<VariantResult>& runs) {
  if (runs.size() == 1) return runs.front().log.to_csv();
  // The time base: every instant any run logged, in order. Log times are whole
  // nanoseconds times 1e-9, so runs that logged the same instant hold the same double.
  std::vector<double> t;
  for (const auto& r : runs) t.insert(t.end(), r.log.time().begin(), r.log.time().end());
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  std::string out = "t [s]";
  for (const auto& r : runs)
    for (std::size_t c = 1; c < r.log.columns(); ++c)
      out += fmt::format(",{}/{} [{}]", r.name, r.log.name(static_cast<int>(c)), r.log.unit(static_cast<int>(c)));
  out += '\n';
  std::vector<std::size_t> next(runs.size(), 0);  // each run's first row not yet written
  for (double ts : t) {
    out += fmt::format("{:.17g}", ts);
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const Log& log = runs[k].log;
      const bool has = next[k] < log.rows() && log.time()[next[k]] == ts;
      for (std::size_t c = 1; c < log.columns(); ++c) {
        out += ',';
        if (has) out += fmt::format("{:.17g}", log.column(static_cast<int>(c))[next[k]]);  // empty: no sample at ts
      }
      if (has) ++next[k];
    }
    out += '\n';
  }
  return out;
}

ScenarioRunResult run_scenario(const Scenario& s, const std::string& out_dir, const ScenarioRunOptions& options) {
  ScenarioRunResult res;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec || !fs::is_directory(out_dir)) throw InputError("--out '" + out_dir + "': cannot create the folder: " + ec.message());
  const fs::path dir(out_dir);

  FrameSink sink(s, dir);
  sink.enabled = options.frames && s.frames.enabled;
  sink.variant = s.frames.variant.empty() ? s.variants.front().name : s.frames.variant;
  // Old frames of an earlier run would be mixed with the new ones in the strip.
  if (sink.enabled) fs::remove_all(dir / "frames", ec);

  double total = 0;
  for (const auto& v : s.variants) total += options.duration_s.value_or(v.duration_s);
  double done = 0;
  for (const auto& v : s.variants) {
    RunOptions ro;
    ro.duration_s = options.duration_s;
    const double d = options.duration_s.value_or(v.duration_s);
    if (options.on_progress) ro.on_progress = [&](double f) { options.on_progress((done + f * d) / total, v.name); };
    const bool render = sink.enabled && v.name == sink.variant;
    // Long runs are rendered as a time-lapse of at most max_frames frames.
    const double frame_rate = render ? std::min(s.frames.fps, s.frames.max_frames / d) : 0.0;
    // A whole number of nanoseconds per frame.
    const double frame_rate_ns = frame_rate > 0 ? 1e9 / std::ceil(1e9 / frame_rate / 1e6) / 1e6 : 0.0;
    try {
      res.runs.push_back(run_variant(s, v, ro, frame_rate_ns,
                                     render ? std::function<void(double, const model::Plant&)>(
                                                  [&](double t, const model::Plant& p) { sink.frame(t, p); })
                                            : std::function<void(double, const model::Plant&)>()));
    } catch (const DivergenceError& e) {
      throw InputError(s.file + ": variant '" + v.name + "': " + e.what());
    }
    done += d;
  }
  if (sink.video) {
    sink.video->finish();
    res.files.push_back("video.mp4");
    for (const auto& f : sink.frames) res.files.push_back(f.path);
    res.frames = static_cast<int>(sink.frames.size());
    res.render_fps = sink.render_s > 0 ? static_cast<double>(sink.frames.size()) / sink.render_s : 0.0;
  }
  // The log first: it is there to look at even when the experiment's analysis fails.
  write_text(dir / "log.csv", combined_csv(res.runs));
  res.files.push_back("log.csv");
  res.experiment = evaluate_experiment(s, res.runs);

  nlohmann::json metrics = res.experiment.metrics;
  metrics["scenario"] = s.name;
  for (const auto& r : res.runs) {
    nlohmann::json& j = metrics["runs"][r.name];
    j["duration_s"] = r.log.time().empty() ? 0.0 : r.log.time().back();
    j["wall_s"] = r.wall_s;
    j["real_time_factor"] = r.real_time_factor;
    j["integrator_steps"] = r.integrator_steps;
    j["controller_steps"] = r.controller_steps;
    j["controller_clamp_events"] = r.clamp_events;
  }
  write_text(dir / "metrics.json", finite_json(metrics).dump(2) + "\n");
  res.files.push_back("metrics.json");
  fs::create_directories(dir / "plots");
  for (const auto& [file, fig] : res.experiment.figures) {
    fig.save_png((dir / "plots" / file).string());
    res.files.push_back("plots/" + file);
  }

  // The report.
  viz::Report rep;
  rep.title = s.name;
  rep.description = s.description;
  const VariantSetup& v0 = s.variants.front();
  rep.summary.emplace_back("scenario file", fs::path(s.file).filename().string());
  rep.summary.emplace_back("robot", v0.robot.urdf == "draco" ? "DRACO (model/draco/draco.urdf)" : v0.robot.urdf);
  rep.summary.emplace_back("base", v0.robot.base == model::BaseMode::Fixed ? "fixed to the table" : "floating, on the ground");
  std::string names;
  for (const auto& r : res.runs) names += (names.empty() ? "" : ", ") + r.name;
  rep.summary.emplace_back("variants", names);
  for (const auto& r : res.runs)
    rep.summary.emplace_back("run " + r.name, fmt::format("{:.3g} s simulated, real-time factor {:.3g}, {} integrator steps",
                                                          r.log.time().empty() ? 0.0 : r.log.time().back(), r.real_time_factor,
                                                          r.integrator_steps));
  for (const auto& c : v0.controllers)
    rep.summary.emplace_back("controller " + c.name, fmt::format("{} at {} Hz, delay {} s", fs::path(c.diagram).filename().string(), c.rate_hz, c.delay_s));
  rep.metrics = finite_json(res.experiment.metrics);
  for (const auto& [file, fig] : res.experiment.figures) rep.plots.push_back({"plots/" + file, fig.title});
  rep.frames = sink.frames;
  if (sink.video) {
    rep.video = "video.mp4";
    rep.video_caption = fmt::format("Variant {}: {} frames at {} frames/s", sink.variant, sink.frames.size(), s.frames.fps);
    if (!sink.frames.empty()) rep.video_poster = sink.frames.front().path;
  }
  rep.notes = res.experiment.notes;
  rep.notes.push_back("Files: log.csv (every signal of every variant, with units), metrics.json, plots/, frames/, video.mp4.");
  res.report = (dir / "report.html").string();
  viz::write_report(rep, res.report);
  res.files.push_back("report.html");
  return res;
}

}  // namespace dmbd::sim
