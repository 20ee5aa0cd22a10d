// write_report: plots, frames, video, the 3-D replay and report.html from a run.
#include "dmbd/report/report.hpp"

#include <chrono>
#include <filesystem>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/viz/plot.hpp"
#include "dmbd/viz/report.hpp"
#include "frames.hpp"
#include "replay.hpp"

namespace dmbd::report {

namespace fs = std::filesystem;

namespace {

void make_dir(const fs::path& d) {
  std::error_code ec;
  fs::create_directories(d, ec);
  if (ec || !fs::is_directory(d)) throw OutputError("cannot create the folder '" + d.string() + "': " + (ec ? ec.message() : "a file is in the way"));
}

// The robot as the report names it: its folder's name for it and the URDF's path, or the
// URDF's own robot name and path.
std::string robot_name(const scenario::RobotSetup& r) {
  if (r.folder) return r.folder->display_name + " (" + r.folder->name + ": " + r.urdf + ")";
  model::UrdfOptions quick;
  quick.load_meshes = false;
  return model::load_urdf(r.urdf, quick).name + " (" + r.urdf + ")";
}

std::vector<std::pair<std::string, std::string>> summary(const scenario::ScenarioRun& run) {
  const scenario::Scenario& s = run.scenario;
  const scenario::VariantSetup& v0 = s.variants.front();
  std::vector<std::pair<std::string, std::string>> out;
  out.emplace_back("scenario file", fs::path(s.file).filename().string());
  out.emplace_back("robot", robot_name(v0.robot));
  out.emplace_back("base", v0.robot.base == model::BaseMode::Floating ? "floating, on the ground"
                           : v0.robot.contact                        ? "fixed to the world, standing on the ground"
                                                                     : "fixed to the table");
  std::string names;
  for (const auto& r : run.runs) names += (names.empty() ? "" : ", ") + r.name;
  out.emplace_back("variants", names);
  for (const auto& r : run.runs)
    out.emplace_back("run " + r.name, fmt::format("{:.3g} s simulated, real-time factor {:.3g}, {} integrator steps",
                                                  r.log.time().empty() ? 0.0 : r.log.time().back(), r.real_time_factor,
                                                  r.integrator_steps));
  for (const auto& c : v0.controllers)
    out.emplace_back("controller " + c.name,
                     fmt::format("{} at {} Hz, delay {} s", fs::path(c.diagram).filename().string(), c.rate_hz, c.delay_s));
  return out;
}

void add_video(viz::Report& rep, const detail::Frames& f, std::vector<std::string>& files) {
  rep.frames = f.frames;
  if (f.frames.empty()) return;
  rep.video = "video.mp4";
  rep.video_caption = f.speedup > 1.01
                          ? fmt::format("Variant {}: {} frames, a time-lapse at {:.3g} times real time", f.variant, f.frames.size(), f.speedup)
                          : fmt::format("Variant {}: {} frames at {:.4g} frames/s (real time)", f.variant, f.frames.size(), f.video_fps);
  rep.video_poster = f.frames.front().path;
  files.push_back("video.mp4");
  for (const auto& fr : f.frames) files.push_back(fr.path);
}

}  // namespace

ReportResult write_report(const scenario::ScenarioRun& run, const std::string& dir, const ReportOptions& options) {
  const fs::path d(dir);
  make_dir(d / "plots");
  scenario::forget_earlier_report(dir);  // the page first: it links the frames and video removed below
  std::error_code ec;
  ReportResult res;
  viz::Report rep;
  rep.title = run.scenario.name;
  rep.description = run.scenario.description;
  rep.summary = summary(run);
  rep.metrics = scenario::finite_json(run.experiment.metrics);
  for (const auto& [file, fig] : run.experiment.figures) {
    viz::Figure(fig).save_png((d / "plots" / file).string());
    res.files.push_back("plots/" + file);
    rep.plots.push_back({"plots/" + file, fig.title});
  }
  // Frames of an earlier report would be listed with the new ones.
  fs::remove_all(d / "frames", ec);
  fs::remove(d / "video.mp4", ec);
  for (const auto& r : run.runs) res.warnings.insert(res.warnings.end(), r.warnings.begin(), r.warnings.end());
  res.warnings.insert(res.warnings.end(), run.experiment.warnings.begin(), run.experiment.warnings.end());
  if (options.frames && run.scenario.frames.enabled) {
    const detail::Frames f = detail::write_frames(run, dir, options);
    add_video(rep, f, res.files);
    res.frames = static_cast<int>(f.frames.size());
    res.render_fps = f.render_s > 0 ? static_cast<double>(f.frames.size()) / f.render_s : 0.0;
    res.warnings.insert(res.warnings.end(), f.warnings.begin(), f.warnings.end());
  }
  const auto t0 = std::chrono::steady_clock::now();
  detail::Replay replay = detail::write_replay(run, dir, options);
  res.replay_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  res.replay_variants = static_cast<int>(replay.page.variants.size());
  rep.replay = std::move(replay.page);
  res.files.insert(res.files.end(), replay.files.begin(), replay.files.end());
  res.warnings.insert(res.warnings.end(), replay.warnings.begin(), replay.warnings.end());
  for (const auto& w : res.warnings) rep.notes.push_back("Warning: " + w);
  for (const auto& r : run.runs)
    for (const auto& f : r.fixed_point)
      rep.notes.push_back(fmt::format("Run {}: controller '{}' in {}-bit fixed point: predicted error bound on '{}' over the run {:.4g} {} "
                                      "(range +-{:.4g} {}; it holds while no saturation engages).",
                                      r.name, f.controller, f.word_bits, f.output, f.bound, f.unit, f.range, f.unit));
  rep.notes.insert(rep.notes.end(), run.experiment.notes.begin(), run.experiment.notes.end());
  rep.notes.push_back(std::string("Files: log.csv (every signal of every variant, with units), metrics.json, plots/") +
                      (res.frames > 0 ? ", frames/, video.mp4" : "") + (res.replay_variants > 0 ? ", replay/." : "."));
  res.page = (d / "report.html").string();
  viz::write_report(rep, res.page);
  res.files.push_back("report.html");
  return res;
}

}  // namespace dmbd::report
