#pragma once
// A self-contained HTML report of a run: title, description, summary, a metrics
// table, plots, a strip of frames, the video and notes.
//
//   dmbd::viz::Report report;
//   report.title = "Squat, 100 kg payload";
//   report.summary = {{"Scenario", "squat.yaml"}, {"Control rate", "1 kHz"}};
//   report.metrics = {{"rms_error_N", {{"with_dob", {{"100 kg", 1.23}}}}}};
//   report.plots.push_back({"plots/knee.png", "Knee torque tracking"});
//   report.frames.push_back({"frames/frame_0000.png", 0.0});
//   report.video = "video.mp4";
//   dmbd::viz::write_report(report, "out/report.html");
//
// One HTML page with inline CSS and no external URL: plots, frames and the video are
// linked by paths relative to the page's directory (the caller writes those files
// there). All text is HTML-escaped. Every section with nothing in it is left out. The
// page has no JavaScript unless it has a 3-D replay (ReportReplay: the player is inline,
// three.js and the data are scripts beside the page, replay.hpp).
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmbd/viz/renderer.hpp"  // Camera

namespace dmbd::viz {

struct ReportFigure {
  std::string path;     // relative to the report's directory, e.g. "plots/knee.png"
  std::string caption;  // may be empty
};

struct ReportFrame {
  std::string path;              // relative, e.g. "frames/frame_0042.png"
  std::optional<double> time_s;  // shown as "t = 1.25 s" when given
};

// A 3-D replay of the run: WebGL (three.js) with play, pause, a time slider, a variant
// selector and an orbiting camera that starts where `camera` is (position, look-at, field
// of view; the view keeps its aspect). The page also takes URL parameters: t=SECONDS,
// variant=NAME, speed=FACTOR, ground=0, overlays=0, and view=replay, which shows the view
// alone at the camera's size (for a picture of one moment). Its state is the replay
// section's data-state attribute: "loading", "ready" (with data-time, the time shown) or
// "error" (the reason shown on the page and given to console.error).
struct ReportReplayVariant {
  std::string name;
  std::string track, scene;  // relative paths of its scripts (replay_track_script, replay_scene_script)
};
struct ReportReplay {
  std::vector<ReportReplayVariant> variants;  // empty: no replay section
  std::size_t initial = 0;                    // the variant shown first
  std::vector<std::string> scripts;           // relative paths: three.min.js, then OrbitControls.js
  std::string licence;                        // relative path of three.js's licence, linked under the view; may be empty
  Camera camera;
  std::string title;    // the view's first line (the frames' title)
  std::string caption;  // under the view; may be empty
  double force_scale_m_per_N = 0.001;  // arrow length per newton, as the frames' Overlays
};

struct Report {
  std::string title;        // page title and heading ("Report" when empty)
  std::string description;  // paragraph under the title; blank lines separate paragraphs
  // Key facts in order (scenario, robot, duration, rates, ...).
  std::vector<std::pair<std::string, std::string>> summary;
  // Rendered as a two-column table, nested objects flattened into rows
  // ("rms_error_N / with_dob / 100 kg"), grouped under their top-level key; see
  // flatten_metrics(). null or an empty object: no metrics section.
  nlohmann::json metrics = nlohmann::json::object();
  std::vector<ReportFigure> plots;  // one full-width figure each, in order
  // Frames in time order; at most max_frames of them, evenly chosen (first and last
  // included), are shown in a grid, each linking to its full-size image.
  std::vector<ReportFrame> frames;
  std::size_t max_frames = 8;
  std::string video;          // relative path of an MP4; empty: no video section
  std::string video_caption;  // may be empty
  std::string video_poster;   // relative path of an image shown before playing; may be empty
  std::vector<std::string> notes;  // free-text paragraphs; line breaks are kept
  ReportReplay replay;             // no variants: no replay section
};

// The page as a string. Throws std::invalid_argument naming the field when a path
// is empty, absolute, a URL (has a scheme such as "http:" or "file:"), contains a
// ".." component, a backslash or a control character. Paths are percent-encoded in
// the page (a space becomes %20).
std::string render_report_html(const Report& report);

// render_report_html() written atomically ("<path>.tmp", then a rename). Throws
// std::invalid_argument as above, std::runtime_error naming the path when writing
// fails (nothing is left behind).
void write_report(const Report& report, const std::string& path);

// Additions used by the page and useful on their own.

// & < > " ' as entities; everything else (UTF-8 included) unchanged.
std::string html_escape(std::string_view text);

// One row of the metrics table: the keys from the top level down to the leaf (array
// elements as "[i]") and the formatted value.
struct MetricRow {
  std::vector<std::string> path;
  std::string value;
};
// Depth-first in the object's key order (nlohmann::json sorts keys). Leaves:
// numbers via format_metric(), booleans "true"/"false", null "null", strings as
// they are; an array of at most 8 scalars is one row "[1.5, 2, 3]", other arrays
// one row per element; an empty object or array is one row "{}" / "[]". A scalar
// at the top level is one row with path {"value"}.
std::vector<MetricRow> flatten_metrics(const nlohmann::json& metrics);

// About 4 significant digits, compact: integers exactly ("100", "-3"); 1e-3 <=
// |v| < 1e4 with %.4g ("0.1235", "12.35", "1235"); 1e4 <= |v| < 1e6 rounded to an
// integer ("12346"); otherwise mantissa and exponent ("1.235e7", "2.5e-6"); "0",
// "NaN", "inf", "-inf".
std::string format_metric(double value);
std::string format_metric(const nlohmann::json& number);

// min(count, max_count) indices into [0, count), strictly increasing and evenly
// spread, the first and the last included (max_count 1: {0}; max_count 0: {}).
std::vector<std::size_t> evenly_spaced_indices(std::size_t count, std::size_t max_count);

}  // namespace dmbd::viz
