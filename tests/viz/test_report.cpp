// Tests for the dmbd::viz HTML report: escaping, relative-only references, the
// metrics table, the frame strip, atomic output, and a screenshot of the page in
// headless Chromium showing the plot and the frames.
#include "dmbd/viz/report.hpp"

#include <stdlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "viz_test_support.hpp"
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dmbd/viz/plot.hpp"
#include "dmbd/viz/video.hpp"

namespace dmbd::viz {
namespace {

namespace fs = std::filesystem;
using test::find_chromium;
// Temp folders named after this test file.
struct TempDir : test::TempDir {
  TempDir() : test::TempDir("dmbd_test_report") {}
};
using nlohmann::json;


std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// Values of every src=, href=, poster= attribute (and CSS url()).
std::vector<std::string> references(const std::string& html) {
  std::vector<std::string> refs;
  const std::regex attr(R"re(\b(?:src|href|poster)\s*=\s*"([^"]*)")re", std::regex::icase);
  for (auto it = std::sregex_iterator(html.begin(), html.end(), attr); it != std::sregex_iterator(); ++it)
    refs.push_back((*it)[1]);
  const std::regex css_url(R"re(url\(\s*['"]?([^'")]*))re", std::regex::icase);
  for (auto it = std::sregex_iterator(html.begin(), html.end(), css_url); it != std::sregex_iterator(); ++it)
    refs.push_back((*it)[1]);
  return refs;
}

// A report with every section filled in (paths need not exist for the text tests).
Report full_report() {
  Report r;
  r.title = "Squat with a 100 kg payload";
  r.description = "Knee torque tracking of the RFSEA with and without the disturbance observer.\n\nSecond paragraph.";
  r.summary = {{"Scenario", "examples/scenarios/squat.yaml"}, {"Robot", "DRACO"}, {"Duration", "4 s"},
               {"Control rate", "1 kHz"}};
  r.metrics = {{"rms_error_N", {{"with_dob", {{"100 kg", 1.23456}, {"0 kg", 0.5}}}, {"without_dob", {{"100 kg", 12.5}}}}},
               {"settling_time_s", 0.0421},
               {"saturations", 0},
               {"stable", true},
               {"poles", {-1.5, -2.25}},
               {"phase", "double support"}};
  r.plots = {{"plots/knee torque.png", "Knee torque, reference and measured"}, {"plots/error.png", ""}};
  for (int i = 0; i < 40; ++i)
    r.frames.push_back({"frames/frame_" + std::to_string(1000 + i).substr(1) + ".png", 0.1 * i});
  r.video = "video.mp4";
  r.video_caption = "The whole run at real time.";
  r.video_poster = "frames/frame_000.png";
  r.notes = {"Gains from Table II.\nSecond line."};
  return r;
}

// ---- Text-level tests ------------------------------------------------------------

TEST(Report, HtmlEscape) {
  EXPECT_EQ(html_escape(R"(<a href="x">'&'</a>)"), "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;");
  EXPECT_EQ(html_escape("plain µ° text"), "plain µ° text");
  EXPECT_EQ(html_escape(""), "");
}

TEST(Report, ScriptInTitleBecomesText) {
  Report r;
  r.title = "<script>alert('x')</script>";
  const std::string html = render_report_html(r);
  EXPECT_FALSE(contains(lower(html), "<script")) << html;
  EXPECT_TRUE(contains(html, "<title>&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;</title>"));
  EXPECT_TRUE(contains(html, "<h1>&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;</h1>"));
}

TEST(Report, EveryTextFieldIsEscaped) {
  const std::string evil = "<b onmouseover=\"x\">bold</b>";
  Report r = full_report();
  r.title = r.description = r.video_caption = evil;
  r.summary = {{evil, evil}};
  r.metrics = {{evil, {{evil, evil}}}, {"n" + evil, 1.0}};
  r.plots = {{"plots/a.png", evil}};
  r.frames = {{"frames/f.png", std::nullopt}};
  r.notes = {evil};
  const std::string html = render_report_html(r);
  EXPECT_FALSE(contains(html, "<b ")) << html;
  EXPECT_FALSE(contains(html, "</b>")) << html;
  EXPECT_FALSE(contains(html, "\"x\"")) << html;
  EXPECT_TRUE(contains(html, html_escape(evil)));
}

TEST(Report, OnlyRelativeReferencesAndNoScript) {
  const Report r = full_report();
  const std::string html = render_report_html(r);
  const std::vector<std::string> refs = references(html);
  ASSERT_FALSE(refs.empty());
  for (const std::string& ref : refs) {
    SCOPED_TRACE(ref);
    EXPECT_FALSE(ref.empty());
    EXPECT_NE(ref.front(), '/');
    EXPECT_FALSE(contains(ref, ":")) << "no scheme (http:, file:, data:)";
    EXPECT_FALSE(contains(ref, "..")) << "stays within the output directory";
  }
  // Exactly the given files: both plots, the 8 frames shown, the video and its poster.
  const std::set<std::string> unique(refs.begin(), refs.end());
  std::set<std::string> expected = {"plots/knee%20torque.png", "plots/error.png", "video.mp4", "frames/frame_000.png"};
  for (std::size_t i : evenly_spaced_indices(40, 8)) expected.insert(r.frames[i].path);
  EXPECT_EQ(unique, expected);
  // Self-contained: no external URL anywhere, no script, no stylesheet link, no import.
  EXPECT_FALSE(contains(lower(html), "http")) << html;
  EXPECT_FALSE(contains(lower(html), "<script"));
  EXPECT_FALSE(contains(lower(html), "<link"));
  EXPECT_FALSE(contains(lower(html), "@import"));
  EXPECT_FALSE(contains(lower(html), "<iframe"));
}

TEST(Report, RejectsPathsOutsideTheDirectory) {
  for (const std::string bad : {"", "/tmp/plot.png", "http://example.com/plot.png", "file:///tmp/plot.png",
                                "data:image/png;base64,AAAA", "../plot.png", "plots/../../plot.png", "..",
                                "C:\\plots\\plot.png", "plots\\plot.png", "plot\n.png", "javascript:alert(1)"}) {
    SCOPED_TRACE(bad);
    Report r;
    r.plots = {{bad, "caption"}};
    EXPECT_THROW(render_report_html(r), std::invalid_argument);
    r.plots.clear();
    r.frames = {{bad, 0.0}};
    EXPECT_THROW(render_report_html(r), std::invalid_argument);
    r.frames.clear();
    if (!bad.empty()) {  // an empty video path means "no video"
      r.video = bad;
      EXPECT_THROW(render_report_html(r), std::invalid_argument);
      r.video = "video.mp4";
      r.video_poster = bad;
      EXPECT_THROW(render_report_html(r), std::invalid_argument);
    }
  }
  // Dots inside names and leading "./" are fine.
  Report ok;
  ok.plots = {{"./plots/knee..torque.v2.png", ""}};
  ok.video = "run.1/video.mp4";
  EXPECT_NO_THROW(render_report_html(ok));
  // The error names the field and the path.
  Report r;
  r.plots = {{"plots/a.png", ""}, {"/abs/b.png", ""}};
  try {
    render_report_html(r);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(contains(e.what(), "plots[1]")) << e.what();
    EXPECT_TRUE(contains(e.what(), "/abs/b.png")) << e.what();
  }
}

TEST(Report, PathsArePercentEncoded) {
  Report r;
  r.plots = {{"plots/knee torque #2?.png", "c"}};
  const std::string html = render_report_html(r);
  EXPECT_TRUE(contains(html, "src=\"plots/knee%20torque%20%232%3F.png\"")) << html;
}

TEST(Report, FormatMetric) {
  EXPECT_EQ(format_metric(0.0), "0");
  EXPECT_EQ(format_metric(-0.0), "0");
  EXPECT_EQ(format_metric(1.23456), "1.235");
  EXPECT_EQ(format_metric(0.5), "0.5");
  EXPECT_EQ(format_metric(-12.3456), "-12.35");
  EXPECT_EQ(format_metric(1234.56), "1235");
  EXPECT_EQ(format_metric(0.00123456), "0.001235");
  EXPECT_EQ(format_metric(12345.6), "12346");
  EXPECT_EQ(format_metric(1.23456e7), "1.235e7");
  EXPECT_EQ(format_metric(2.5e-6), "2.5e-6");
  EXPECT_EQ(format_metric(-1e-9), "-1e-9");
  EXPECT_EQ(format_metric(std::numeric_limits<double>::quiet_NaN()), "NaN");
  EXPECT_EQ(format_metric(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(format_metric(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(format_metric(json(100)), "100");
  EXPECT_EQ(format_metric(json(-3)), "-3");
  EXPECT_EQ(format_metric(json(12345678901ULL)), "12345678901");  // integers exactly
  EXPECT_EQ(format_metric(json(2.0)), "2");
  EXPECT_THROW(format_metric(json("x")), std::invalid_argument);
}

TEST(Report, FlattenMetrics) {
  const json m = {{"rms_error_N", {{"with_dob", {{"100 kg", 1.23456}}}}},
                  {"poles", {-1.5, -2.0}},
                  {"runs", json::array({{{"t_s", 1.0}}, {{"t_s", 2.0}}})},
                  {"empty", json::object()},
                  {"flag", false},
                  {"missing", nullptr},
                  {"long", std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8, 9}}};
  const std::vector<MetricRow> rows = flatten_metrics(m);
  auto find = [&](const std::vector<std::string>& path) -> std::string {
    for (const MetricRow& row : rows)
      if (row.path == path) return row.value;
    return "<no row>";
  };
  EXPECT_EQ(find({"rms_error_N", "with_dob", "100 kg"}), "1.235");
  EXPECT_EQ(find({"poles"}), "[-1.5, -2]");
  EXPECT_EQ(find({"runs", "[0]", "t_s"}), "1");
  EXPECT_EQ(find({"runs", "[1]", "t_s"}), "2");
  EXPECT_EQ(find({"empty"}), "{}");
  EXPECT_EQ(find({"flag"}), "false");
  EXPECT_EQ(find({"missing"}), "null");
  EXPECT_EQ(find({"long", "[8]"}), "9");
  EXPECT_EQ(rows.size(), 1u + 1 + 2 + 1 + 1 + 1 + 9);
  EXPECT_EQ(flatten_metrics(json(3.5)).at(0).path, std::vector<std::string>{"value"});
}

TEST(Report, MetricsTableContainsEveryLeaf) {
  const Report r = full_report();
  const std::string html = render_report_html(r);
  const auto table_begin = html.find("<table class=\"metrics\">");
  const auto table_end = html.find("</table>", table_begin);
  ASSERT_NE(table_begin, std::string::npos);
  const std::string table = html.substr(table_begin, table_end - table_begin);
  const std::vector<MetricRow> rows = flatten_metrics(r.metrics);
  ASSERT_EQ(rows.size(), 8u);
  for (const MetricRow& row : rows) {
    SCOPED_TRACE(row.path.back());
    EXPECT_TRUE(contains(table, "<td class=\"value\">" + html_escape(row.value) + "</td>"));
    for (const std::string& key : row.path) EXPECT_TRUE(contains(table, html_escape(key)));
  }
  for (const char* v : {"1.235", "0.5", "12.5", "0.0421", ">0<", "true", "[-1.5, -2.25]", "double support"})
    EXPECT_TRUE(contains(table, v)) << v;
  // Nested rows are grouped under their top-level key, the rest of the path shown.
  EXPECT_TRUE(contains(table, "<th colspan=\"2\" scope=\"rowgroup\">rms_error_N</th>"));
  EXPECT_TRUE(contains(table, "<span class=\"prefix\">with_dob / </span>100 kg"));
}

TEST(Report, EvenlySpacedIndices) {
  EXPECT_EQ(evenly_spaced_indices(0, 8), std::vector<std::size_t>{});
  EXPECT_EQ(evenly_spaced_indices(10, 0), std::vector<std::size_t>{});
  EXPECT_EQ(evenly_spaced_indices(10, 1), std::vector<std::size_t>{0});
  EXPECT_EQ(evenly_spaced_indices(10, 2), (std::vector<std::size_t>{0, 9}));
  EXPECT_EQ(evenly_spaced_indices(5, 8), (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(evenly_spaced_indices(9, 5), (std::vector<std::size_t>{0, 2, 4, 6, 8}));
  for (std::size_t count : {8u, 9u, 17u, 40u, 1001u}) {
    const auto idx = evenly_spaced_indices(count, 8);
    ASSERT_EQ(idx.size(), 8u);
    EXPECT_EQ(idx.front(), 0u);
    EXPECT_EQ(idx.back(), count - 1);
    std::size_t min_step = count, max_step = 0;
    for (std::size_t i = 1; i < idx.size(); ++i) {
      min_step = std::min(min_step, idx[i] - idx[i - 1]);
      max_step = std::max(max_step, idx[i] - idx[i - 1]);
    }
    EXPECT_GE(min_step, 1u);
    EXPECT_LE(max_step - min_step, 1u) << "steps differ by at most one";
  }
}

TEST(Report, FrameStripShowsEvenlyChosenFramesWithTimes) {
  const Report r = full_report();  // 40 frames at 0.1 s
  const std::string html = render_report_html(r);
  const auto begin = html.find("<section id=\"frames\">");
  ASSERT_NE(begin, std::string::npos);
  const std::string strip = html.substr(begin, html.find("</section>", begin) - begin);
  std::size_t images = 0;
  for (auto pos = strip.find("<img"); pos != std::string::npos; pos = strip.find("<img", pos + 1)) ++images;
  EXPECT_EQ(images, 8u);
  EXPECT_TRUE(contains(strip, "8 of 40 frames"));
  EXPECT_TRUE(contains(strip, "t = 0 s"));
  EXPECT_TRUE(contains(strip, "t = 3.9 s"));
  EXPECT_TRUE(contains(strip, "frames/frame_039.png"));
}

TEST(Report, EmptySectionsAreLeftOut) {
  Report r;
  r.title = "Only a title";
  const std::string html = render_report_html(r);
  for (const char* absent : {"<table", "<video", "<img", "id=\"summary\"", "id=\"frames\"", "id=\"notes\"",
                             "id=\"plots\"", "id=\"metrics\""})
    EXPECT_FALSE(contains(html, absent)) << absent;
  r.metrics = nullptr;
  EXPECT_FALSE(contains(render_report_html(r), "<table"));
  EXPECT_TRUE(contains(render_report_html(Report{}), "<h1>Report</h1>"));
}

TEST(Report, DocumentStructure) {
  const std::string html = render_report_html(full_report());
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_TRUE(contains(html, "<meta charset=\"utf-8\">"));
  EXPECT_TRUE(contains(html, "<video controls"));
  EXPECT_TRUE(contains(html, "<source src=\"video.mp4\" type=\"video/mp4\">"));
  EXPECT_TRUE(contains(html, "poster=\"frames/frame_000.png\""));
  EXPECT_TRUE(contains(html, "<figcaption>Figure 1. Knee torque, reference and measured</figcaption>"));
  EXPECT_TRUE(contains(html, "<p class=\"description\">Second paragraph.</p>"));
  EXPECT_TRUE(contains(html, "Gains from Table II.\nSecond line."));
  // Sections in the documented order.
  std::size_t last = 0;
  for (const char* id : {"summary", "metrics", "plots", "frames", "video", "notes"}) {
    const auto pos = html.find(std::string("<section id=\"") + id + "\"");
    ASSERT_NE(pos, std::string::npos) << id;
    EXPECT_GT(pos, last) << id;
    last = pos;
  }
  // Balanced tags for the elements the page opens.
  for (const char* tag : {"section", "figure", "table", "tbody", "tr", "dl", "video", "main", "header"}) {
    std::size_t open = 0, close = 0;
    const std::string o = std::string("<") + tag, c = std::string("</") + tag + ">";
    for (auto p = html.find(o); p != std::string::npos; p = html.find(o, p + 1))
      if (html[p + o.size()] == '>' || html[p + o.size()] == ' ') ++open;
    for (auto p = html.find(c); p != std::string::npos; p = html.find(c, p + 1)) ++close;
    EXPECT_EQ(open, close) << tag;
  }
}

TEST(Report, WriteIsAtomic) {
  TempDir dir;
  const Report r = full_report();
  const std::string path = dir / "report.html";
  write_report(r, path);
  EXPECT_EQ(read_text(path), render_report_html(r));
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path())) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"report.html"}) << "no .tmp left";
  write_report(Report{}, path);  // overwrite in place
  EXPECT_TRUE(contains(read_text(path), "<h1>Report</h1>"));

  const std::string bad = dir / "missing/report.html";
  try {
    write_report(r, bad);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(contains(e.what(), bad)) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "missing"));
  // An invalid path in the report: nothing is written.
  Report invalid;
  invalid.video = "/abs/video.mp4";
  EXPECT_THROW(write_report(invalid, dir / "invalid.html"), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "invalid.html"));
  EXPECT_FALSE(fs::exists(dir / "invalid.html.tmp"));
}

// ---- The page in a real browser ---------------------------------------------------


// Plot series colour: nothing else on the page is this red.
constexpr Color kPlotRed{220, 20, 20};
constexpr double kPi = 3.14159265358979323846;
// Frame content: a blue-green gradient with a yellow disc; no red.
cv::Mat synthetic_frame(int i, int n) {
  cv::Mat frame(240, 320, CV_8UC3);
  for (int y = 0; y < frame.rows; ++y)
    frame.row(y).setTo(cv::Scalar(120 + y / 3, 80 + y / 4, 20));
  const int x = 40 + (240 * i) / std::max(1, n - 1);
  cv::circle(frame, {x, 120}, 30, cv::Scalar(0, 220, 240), cv::FILLED, cv::LINE_AA);
  return frame;
}

// Pixels within +-tol of a BGR colour.
int count_colour(const cv::Mat& img, cv::Scalar bgr, int tol) {
  cv::Mat mask;
  cv::inRange(img, bgr - cv::Scalar::all(tol), bgr + cv::Scalar::all(tol), mask);
  return cv::countNonZero(mask);
}

TEST(Report, ScreenshotInHeadlessChromiumShowsPlotAndFrames) {
  const std::string chromium = find_chromium();
  ASSERT_FALSE(chromium.empty()) << "chromium is not installed (needed for the report screenshot test): run "
                                    "scripts/setup";
  TempDir dir;
  fs::create_directories(dir.path() / "plots");
  fs::create_directories(dir.path() / "frames");

  // A real plot.
  Figure fig(1000, 500);
  Axes& ax = fig.add_axes();
  ax.title = "Knee torque";
  ax.x_label = "Time (s)";
  ax.y_label = "Torque (N m)";
  std::vector<double> t, y;
  for (int i = 0; i <= 400; ++i) {
    t.push_back(i * 0.01);
    y.push_back(std::sin(2 * kPi * 0.75 * t.back()));
  }
  Series s{"measured", t, y, kPlotRed};
  s.width_px = 3.0;
  ax.series.push_back(s);
  fig.save_png(dir / "plots/knee.png");

  // Frames and the video made from them.
  Report r = full_report();
  r.plots = {{"plots/knee.png", "Knee torque against time"}};
  r.frames.clear();
  std::vector<cv::Mat> frames;
  const int n = 24;
  for (int i = 0; i < n; ++i) {
    frames.push_back(synthetic_frame(i, n));
    const std::string rel = "frames/frame_" + std::to_string(100 + i).substr(1) + ".png";
    ASSERT_TRUE(cv::imwrite(dir / rel, frames.back()));
    r.frames.push_back({rel, i / 12.0});
  }
  write_video(frames, dir / "video.mp4", 12.0);
  r.video = "video.mp4";
  r.video_poster = r.frames.front().path;
  const std::string html_path = dir / "report.html";
  write_report(r, html_path);

  const std::string shot = dir / "screenshot.png", log = dir / "chromium.log";
  const std::string cmd = "timeout 60 '" + chromium +
                          "' --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1280,2000 "
                          "--user-data-dir='" + (dir / "profile") + "' --screenshot='" + shot + "' 'file://" +
                          html_path + "' > '" + log + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  std::string log_text;
  {
    std::ifstream in(log);
    log_text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ASSERT_EQ(rc, 0) << cmd << "\n" << log_text;
  const cv::Mat img = cv::imread(shot, cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty()) << "no screenshot: " << log_text;
  if (const char* keep = std::getenv("DMBD_KEEP_SCREENSHOT")) fs::copy_file(shot, keep, fs::copy_options::overwrite_existing);
  EXPECT_EQ(img.size(), cv::Size(1280, 2000));

  // Not blank: pixels that are neither the page grey (#f3f4f6) nor white.
  const int total = static_cast<int>(img.total());
  const int background = count_colour(img, cv::Scalar(0xf6, 0xf4, 0xf3), 2) + count_colour(img, cv::Scalar(255, 255, 255), 2);
  const double content_fraction = 1.0 - static_cast<double>(background) / total;
  EXPECT_GT(content_fraction, 0.05) << "content fraction " << content_fraction;
  cv::Mat grey;
  cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, stddev;
  cv::meanStdDev(grey, mean, stddev);
  EXPECT_GT(stddev[0], 20.0) << "grey-level standard deviation";

  // The plot is there: its red series (scaled with the image, anti-aliased, so count
  // a loose band around the colour). A 3 px line across ~900 px covers thousands.
  const int red = count_colour(img, cv::Scalar(kPlotRed.b, kPlotRed.g, kPlotRed.r), 40);
  EXPECT_GT(red, 1500) << "plot series pixels";
  // The frames are there: their yellow discs (8 shown; each ~200 px wide -> ~250 px of disc).
  const int yellow = count_colour(img, cv::Scalar(0, 220, 240), 30);
  EXPECT_GT(yellow, 8 * 150) << "frame disc pixels";
}

}  // namespace
}  // namespace dmbd::viz
