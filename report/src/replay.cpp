// The 3-D replay of a run: DIR/replay/ with three.js, the robots' meshes and each
// replayed variant's track, and what the page needs to show them.
#include "replay.hpp"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/report/robot_scene.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/viz/replay.hpp"
#include "frame_view.hpp"
#include "replay_track.hpp"

namespace dmbd::report::detail {

namespace fs = std::filesystem;

namespace {

// A variant ready to be sampled: its robot, where its log holds the pose, its scene.
struct Prepared {
  const sim::VariantResult* run = nullptr;
  model::RobotDescription robot;
  PoseColumns cols;
  viz::Scene robot_scene;  // the links (the camera frames these)
  std::optional<Table> table;
  std::size_t floats = 0;  // per sample
};

// The runs replayed, in the scenario's order: the frames' variant and the first others,
// at most kReplayMaxVariants.
std::vector<const sim::VariantResult*> chosen(const scenario::ScenarioRun& run, const std::string& frames_variant) {
  std::vector<const sim::VariantResult*> out;
  const auto frames = std::find_if(run.runs.begin(), run.runs.end(), [&](const auto& r) { return r.name == frames_variant; });
  const std::size_t others = kReplayMaxVariants - (frames == run.runs.end() ? 0 : 1);
  std::size_t taken = 0;
  for (auto it = run.runs.begin(); it != run.runs.end(); ++it) {
    const bool take = it == frames || taken < others;
    if (take && it != frames) ++taken;
    if (take && it->log.rows() > 0) out.push_back(&*it);
  }
  return out;
}

// The variant's robot and log columns, or why it cannot be drawn (in `failures`) and nothing.
std::optional<Prepared> prepare(const scenario::Scenario& s, const sim::VariantResult& r, std::vector<std::string>& failures) {
  const auto v = std::find_if(s.variants.begin(), s.variants.end(), [&](const auto& x) { return x.name == r.name; });
  if (v == s.variants.end()) return std::nullopt;
  try {
    Prepared p;
    p.run = &r;
    p.robot = scenario::variant_plant(s, *v).robot;
    p.cols = pose_columns(p.robot, r, *v, scenario::variant_overlays(s, *v), s.file);
    p.robot_scene = scene_from_robot(p.robot);
    if (v->robot.base == model::BaseMode::Fixed && !v->robot.contact && !p.robot_scene.bodies.empty())
      p.table = table_under(p.robot_scene, link_poses(p.robot, r.log, p.cols, 0), p.cols.X_WB);
    p.floats = floats_per_sample(p.robot, p.cols, p.table.has_value());
    return p;
  } catch (const OutputError&) {
    throw;
  } catch (const InputError& e) {
    failures.push_back(std::string("no 3-D replay: ") + e.what());
  } catch (const std::invalid_argument& e) {
    failures.push_back(fmt::format("no 3-D replay of variant '{}': {}", r.name, e.what()));
  }
  return std::nullopt;
}

// One warning per variant without a replay, or the first and a count for more than two.
void warn(const std::vector<std::string>& failures, std::vector<std::string>& warnings) {
  if (failures.size() <= 2) {
    warnings.insert(warnings.end(), failures.begin(), failures.end());
    return;
  }
  warnings.push_back(fmt::format("{} ({} more variants have no replay either)", failures.front(), failures.size() - 1));
}

// The one rate for every replayed variant: kReplayRateHz, or lower to keep within kReplayMaxFloats.
double sampling_rate(const std::vector<Prepared>& prepared) {
  double per_hz = 0;  // floats per hertz of sampling rate
  for (const Prepared& p : prepared) {
    const auto& t = p.run->log.time();
    per_hz += static_cast<double>(p.floats) * (t.back() - t.front());
  }
  return per_hz > 0 ? std::min(kReplayRateHz, kReplayMaxFloats / per_hz) : kReplayRateHz;
}

// The rate, after leaving out variants (the last first, never the frames' variant) while
// it would be below kReplayMinRateHz.
double fit(std::vector<Prepared>& prepared, const std::string& frames_variant) {
  for (;;) {
    const double rate = sampling_rate(prepared);
    const auto last = std::find_if(prepared.rbegin(), prepared.rend(), [&](const Prepared& p) { return p.run->name != frames_variant; });
    if (rate >= kReplayMinRateHz || prepared.size() == 1 || last == prepared.rend()) return rate;
    prepared.erase(std::next(last).base());
  }
}

bool same_mesh(const viz::SceneMesh& a, const viz::SceneMesh& b) {
  return a.vertices == b.vertices && a.normals == b.normals && a.triangles == b.triangles && a.rgba == b.rgba;
}

bool same_scene(const viz::Scene& a, const viz::Scene& b) {
  if (a.bodies.size() != b.bodies.size()) return false;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const auto& x = a.bodies[i].meshes;
    const auto& y = b.bodies[i].meshes;
    if (a.bodies[i].name != b.bodies[i].name || x.size() != y.size() || !std::equal(x.begin(), x.end(), y.begin(), same_mesh))
      return false;
  }
  return true;
}

viz::Scene drawn_scene(const Prepared& p) {
  viz::Scene s = p.robot_scene;
  if (p.table) s.bodies.push_back(p.table->body);
  return s;
}

std::string caption(const Replay& out, std::size_t variants) {
  std::string c = fmt::format("The run as logged, drawn with three.js: the links' poses sampled at {:.3g} Hz (every logged row where "
                              "the log is slower) and played between the samples",
                              out.rate_hz);
  if (variants < out.variants_in_run) c += fmt::format("; {} of the run's {} variants", variants, out.variants_in_run);
  return c + ".";
}

}  // namespace

Replay write_replay(const scenario::ScenarioRun& run, const std::string& dir, const ReportOptions& options) {
  const scenario::Scenario& s = run.scenario;
  Replay out;
  out.variants_in_run = run.runs.size();
  const fs::path folder = fs::path(dir) / "replay";
  std::error_code ec;
  fs::remove_all(folder, ec);  // an earlier report's variants
  const std::string frames_variant = s.frames.variant.empty() && !run.runs.empty() ? run.runs.front().name : s.frames.variant;
  std::vector<Prepared> prepared;
  std::vector<std::string> failures;
  for (const sim::VariantResult* r : chosen(run, frames_variant))
    if (auto p = prepare(s, *r, failures)) prepared.push_back(std::move(*p));
  warn(failures, out.warnings);
  if (prepared.empty()) return out;
  fs::create_directories(folder, ec);
  try {
    for (const std::string& f : viz::copy_three_js(folder.string())) out.files.push_back("replay/" + f);
  } catch (const OutputError&) {
    throw;
  } catch (const InputError& e) {
    out.warnings.push_back(std::string("no 3-D replay: ") + e.what());
    fs::remove_all(folder, ec);
    out.files.clear();
    return out;
  }
  out.page.scripts = {out.files[0], out.files[1]};  // three.min.js, OrbitControls.js
  out.page.licence = out.files[2];
  out.rate_hz = fit(prepared, frames_variant);
  // The view starts at the frames' camera: the frames' variant's (else the first replayed).
  const auto framed = std::find_if(prepared.begin(), prepared.end(), [&](const Prepared& p) { return p.run->name == frames_variant; });
  const Prepared& f = framed == prepared.end() ? prepared.front() : *framed;
  out.page.camera = frame_camera(s.frames, options, f.robot, f.run->log, f.cols, row_step(f.run->log, s.frames).n, f.robot_scene);
  out.page.initial = static_cast<std::size_t>(framed == prepared.end() ? 0 : framed - prepared.begin());
  out.page.title = s.name;
  std::vector<viz::Scene> scenes;  // written so far, scene_K.js for scenes[K]
  for (std::size_t k = 0; k < prepared.size(); ++k) {
    const Prepared& p = prepared[k];
    viz::Scene scene = drawn_scene(p);
    auto same = std::find_if(scenes.begin(), scenes.end(), [&](const viz::Scene& x) { return same_scene(x, scene); });
    const std::string scene_file = fmt::format("replay/scene_{}.js", same - scenes.begin());
    if (same == scenes.end()) {
      write_file_atomic((fs::path(dir) / scene_file).string(), viz::replay_scene_script(scene, scene_file));
      out.files.push_back(scene_file);
      scenes.push_back(std::move(scene));
    }
    const std::string track_file = fmt::format("replay/variant_{}.js", k);
    const viz::ReplayTrack track = replay_track(p.robot, *p.run, p.cols, p.table, replay_rows(p.run->log, out.rate_hz));
    write_file_atomic((fs::path(dir) / track_file).string(), viz::replay_track_script(track, track_file));
    out.files.push_back(track_file);
    out.page.variants.push_back({p.run->name, track_file, scene_file});
  }
  out.page.caption = caption(out, prepared.size());
  return out;
}

}  // namespace dmbd::report::detail
