#include "report_cmd.hpp"

#include <cstdio>
#include <iostream>

#include "dmbd/base/error.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "simulate_cmd.hpp"

namespace dmbd::apps {

namespace {

// "1280x720" -> width, height.
std::pair<int, int> parse_size(const std::string& s) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 64 || h < 64 || w > 8192 || h > 8192)
    throw InputError("--size '" + s + "': expected WIDTHxHEIGHT in pixels, each 64 to 8192 (e.g. 1280x720)");
  return {w, h};
}

// "X,Y,Z:X,Y,Z" -> camera position, look-at point (m, world).
std::pair<Eigen::Vector3d, Eigen::Vector3d> parse_camera(const std::string& s) {
  double v[6];
  char extra = 0;
  if (std::sscanf(s.c_str(), "%lf,%lf,%lf:%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &extra) != 6)
    throw InputError("--camera '" + s + "': expected POSITION:LOOK_AT as X,Y,Z:X,Y,Z in metres (e.g. 2,-2,1.2:0,0,0.7)");
  const Eigen::Vector3d p(v[0], v[1], v[2]), l(v[3], v[4], v[5]);
  if (!p.allFinite() || !l.allFinite() || (p - l).norm() < 1e-6) throw InputError("--camera '" + s + "': the position must differ from the look-at point");
  return {p, l};
}

}  // namespace

ReportCommand::ReportCommand(CLI::App& app)
    : Command(app, "report", "Redraw a run directory's plots, frames, video and report.html from its log, without simulating") {
  cmd_->add_option("run_dir", dir_, "A folder written by dmbd simulate (log.csv, metrics.json)")->required();
  cmd_->add_flag("--no-frames", no_frames_, "Do not render frames or the video");
  cmd_->add_option("--size", size_, "Frame size WIDTHxHEIGHT in pixels, instead of the scenario's");
  cmd_->add_option("--camera", camera_, "Camera POSITION:LOOK_AT as X,Y,Z:X,Y,Z (m), instead of the scenario's");
}

int ReportCommand::run() {
  report::ReportOptions o;
  o.frames = !no_frames_;
  if (!size_.empty()) std::tie(o.width_px, o.height_px) = parse_size(size_);
  if (!camera_.empty()) {
    const auto [p, l] = parse_camera(camera_);
    o.camera_position = p;
    o.camera_look_at = l;
  }
  print_report(report::write_report(scenario::read_run(dir_), dir_, o), dir_);
  return 0;
}

}  // namespace dmbd::apps
