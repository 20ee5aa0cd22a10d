// The HTML report: one self-contained page (inline CSS, no external URL; a script only
// for the 3-D replay, report_replay.cpp).
#include "dmbd/viz/report.hpp"
#include "dmbd/base/file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "dmbd/viz/plot.hpp"
#include "report_replay.hpp"

namespace dmbd::viz {
namespace {

using nlohmann::json;

// Arrays of at most this many scalars are shown on one row.
constexpr std::size_t kInlineArrayMax = 8;

// Engineering-report look: system fonts, one column, zebra table, captioned figures.
constexpr std::string_view kStyle = R"css(
:root { color-scheme: light; }
* { box-sizing: border-box; }
body {
  margin: 0; background: #f3f4f6; color: #1f2328;
  font-family: system-ui, -apple-system, "Segoe UI", Roboto, "Noto Sans", "Liberation Sans", "DejaVu Sans", Arial, sans-serif;
  font-size: 16px; line-height: 1.5;
}
main {
  max-width: 980px; margin: 24px auto; padding: 32px 40px 24px;
  background: #ffffff; border: 1px solid #d0d7de; border-radius: 6px;
}
header { border-bottom: 2px solid #1f2328; margin-bottom: 8px; padding-bottom: 12px; }
h1 { font-size: 1.9em; line-height: 1.2; margin: 0 0 8px; }
h2 {
  font-size: 1.25em; margin: 32px 0 12px; padding-bottom: 4px;
  border-bottom: 1px solid #d0d7de;
}
p { margin: 0 0 10px; }
.description { color: #3d444d; }
.muted { color: #59636e; }
dl.summary {
  display: grid; grid-template-columns: max-content 1fr; gap: 4px 24px; margin: 0;
}
dl.summary dt { font-weight: 600; color: #3d444d; }
dl.summary dd { margin: 0; font-variant-numeric: tabular-nums; }
table.metrics { border-collapse: collapse; width: 100%; font-size: 0.95em; }
table.metrics th, table.metrics td { padding: 5px 10px; border-bottom: 1px solid #e3e6ea; text-align: left; }
table.metrics thead th { background: #eaeef2; border-bottom: 2px solid #afb8c1; }
table.metrics tr.alt { background: #f6f8fa; }
table.metrics tr.group th {
  background: #ffffff; padding-top: 14px; border-bottom: 1px solid #afb8c1; font-weight: 600;
}
table.metrics td.key .prefix { color: #59636e; }
table.metrics td.value {
  text-align: right; white-space: nowrap;
  font-family: ui-monospace, "SFMono-Regular", "DejaVu Sans Mono", Menlo, Consolas, monospace;
  font-variant-numeric: tabular-nums;
}
figure { margin: 0 0 20px; padding: 10px; border: 1px solid #d0d7de; border-radius: 4px; background: #ffffff; }
figure img, figure video { display: block; max-width: 100%; height: auto; margin: 0 auto; }
figure video { max-height: 80vh; background: #000000; }
figcaption { margin-top: 8px; font-size: 0.9em; color: #3d444d; text-align: center; }
.frames { display: grid; grid-template-columns: repeat(4, 1fr); gap: 10px; }
.frames figure { margin: 0; padding: 6px; }
.frames figcaption { margin-top: 4px; font-variant-numeric: tabular-nums; }
.notes p { white-space: pre-wrap; }
footer { margin-top: 32px; padding-top: 8px; border-top: 1px solid #d0d7de; font-size: 0.8em; color: #59636e; }
)css";

bool is_scalar(const json& j) { return !j.is_object() && !j.is_array(); }

std::string leaf_text(const json& j) {
  if (j.is_number()) return format_metric(j);
  if (j.is_boolean()) return j.get<bool>() ? "true" : "false";
  if (j.is_null()) return "null";
  if (j.is_string()) return j.get<std::string>();
  return j.dump();  // binary values
}

void flatten(const json& j, std::vector<std::string>& path, std::vector<MetricRow>& rows) {
  if (j.is_object()) {
    if (j.empty()) {
      rows.push_back({path, "{}"});
      return;
    }
    for (auto it = j.begin(); it != j.end(); ++it) {
      path.push_back(it.key());
      flatten(it.value(), path, rows);
      path.pop_back();
    }
  } else if (j.is_array()) {
    bool all_scalar = true;
    for (const json& e : j) all_scalar = all_scalar && is_scalar(e);
    if (j.empty() || (all_scalar && j.size() <= kInlineArrayMax)) {
      std::string text = "[";
      for (std::size_t i = 0; i < j.size(); ++i) text += (i ? ", " : "") + leaf_text(j[i]);
      rows.push_back({path, text + "]"});
      return;
    }
    for (std::size_t i = 0; i < j.size(); ++i) {
      path.push_back(fmt::format("[{}]", i));
      flatten(j[i], path, rows);
      path.pop_back();
    }
  } else {
    rows.push_back({path, leaf_text(j)});
  }
}

// Throws unless path is a relative path inside the report's directory; returns it
// percent-encoded for an href/src attribute.
std::string checked_url(const std::string& path, std::string_view field) {
  auto fail = [&](std::string_view why) {
    throw std::invalid_argument(fmt::format("viz: report {} '{}' {}; give a path relative to the report's directory",
                                            field, path, why));
  };
  if (path.empty()) fail("is empty");
  if (path.front() == '/') fail("is absolute");
  for (unsigned char c : path) {
    if (c < 0x20 || c == 0x7f) fail("contains a control character");
    if (c == '\\') fail("contains a backslash");
  }
  // A scheme ("http:", "file:", "data:", "C:") is letters, digits, + - . before the first ':'.
  if (const auto colon = path.find(':'); colon != std::string::npos && path.find('/') > colon) fail("is a URL");
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    if (path.compare(start, end - start, "..") == 0) fail("leaves the report's directory (\"..\")");
    start = end + 1;
  }
  std::string url;
  for (unsigned char c : path) {
    const bool keep = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' ||
                      c == '.' || c == '_' || c == '~' || c == '/';
    url += keep ? std::string(1, static_cast<char>(c)) : fmt::format("%{:02X}", c);
  }
  return url;
}

// Paragraphs separated by blank lines, each escaped.
std::string paragraphs(const std::string& text, std::string_view css_class) {
  std::string out;
  std::string current;
  auto flush = [&] {
    const auto first = current.find_first_not_of(" \t\r\n");
    if (first != std::string::npos) {
      const auto last = current.find_last_not_of(" \t\r\n");
      out += fmt::format("<p class=\"{}\">{}</p>\n", css_class, html_escape(current.substr(first, last - first + 1)));
    }
    current.clear();
  };
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    if (line.find_first_not_of(" \t\r") == std::string::npos) {
      flush();
    } else {
      if (!current.empty()) current += '\n';
      current += line;
    }
    start = end + 1;
  }
  flush();
  return out;
}

// "1.25" for a time in seconds: 3 decimals, trailing zeros dropped.
std::string format_time(double t_s) {
  std::string s = fmt::format("{:.3f}", t_s);
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

void metrics_section(const json& metrics, std::string& out) {
  if (metrics.is_null() || (metrics.is_object() && metrics.empty())) return;
  const std::vector<MetricRow> rows = flatten_metrics(metrics);
  out += "<section id=\"metrics\">\n<h2>Metrics</h2>\n<table class=\"metrics\">\n";
  out += "<thead><tr><th scope=\"col\">Metric</th><th scope=\"col\" style=\"text-align:right\">Value</th></tr>"
         "</thead>\n";
  // Rows sharing a top-level key go in one <tbody> under a heading row with that key;
  // top-level leaves between groups get a <tbody> of their own. Zebra stripes restart
  // in every <tbody>.
  std::string group;
  bool open = false;
  int stripe = 0;
  auto open_body = [&] {
    if (open) out += "</tbody>\n";
    out += "<tbody>\n";
    open = true;
    stripe = 0;
  };
  for (const MetricRow& row : rows) {
    std::size_t skip = 0;
    if (row.path.size() > 1) {
      if (!open || row.path.front() != group) {
        group = row.path.front();
        open_body();
        out += fmt::format("<tr class=\"group\"><th colspan=\"2\" scope=\"rowgroup\">{}</th></tr>\n",
                           html_escape(group));
      }
      skip = 1;
    } else if (!open || !group.empty()) {
      group.clear();
      open_body();
    }
    std::string key;
    for (std::size_t i = skip; i + 1 < row.path.size(); ++i)
      key += "<span class=\"prefix\">" + html_escape(row.path[i]) + " / </span>";
    if (!row.path.empty()) key += html_escape(row.path.back());
    out += fmt::format("<tr{}><td class=\"key\">{}</td><td class=\"value\">{}</td></tr>\n",
                       stripe++ % 2 ? " class=\"alt\"" : "", key, html_escape(row.value));
  }
  if (open) out += "</tbody>\n";
  out += "</table>\n</section>\n";
}

}  // namespace

std::string detail::report_url(const std::string& path, std::string_view field) { return checked_url(path, field); }

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string format_metric(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == 0.0) return "0";
  const double a = std::fabs(value);
  if (a >= 1e-3 && a < 1e4) return fmt::format("{:.4g}", value);
  if (a >= 1e4 && a < 1e6) return fmt::format("{:.0f}", value);
  // Mantissa with 4 significant digits, trailing zeros dropped, bare exponent.
  std::string s = fmt::format("{:.3e}", value);
  const auto e = s.find('e');
  std::string mantissa = s.substr(0, e);
  if (mantissa.find('.') != std::string::npos) {
    while (mantissa.back() == '0') mantissa.pop_back();
    if (mantissa.back() == '.') mantissa.pop_back();
  }
  int exponent = std::stoi(s.substr(e + 1));
  return fmt::format("{}e{}", mantissa, exponent);
}

std::string format_metric(const json& number) {
  if (number.is_number_unsigned()) return std::to_string(number.get<std::uint64_t>());
  if (number.is_number_integer()) return std::to_string(number.get<std::int64_t>());
  if (number.is_number_float()) return format_metric(number.get<double>());
  throw std::invalid_argument(fmt::format("viz: format_metric: {} is not a number", number.dump()));
}

std::vector<MetricRow> flatten_metrics(const json& metrics) {
  std::vector<MetricRow> rows;
  std::vector<std::string> path;
  if (is_scalar(metrics)) {
    rows.push_back({{"value"}, leaf_text(metrics)});
    return rows;
  }
  flatten(metrics, path, rows);
  return rows;
}

std::vector<std::size_t> evenly_spaced_indices(std::size_t count, std::size_t max_count) {
  std::vector<std::size_t> out;
  const std::size_t n = std::min(count, max_count);
  if (n == 0) return out;
  if (n == 1) return {0};
  out.reserve(n);
  // Round i * (count - 1) / (n - 1) to the nearest index; with n <= count the steps
  // are at least 1, so the result is strictly increasing.
  for (std::size_t i = 0; i < n; ++i) out.push_back((2 * i * (count - 1) + (n - 1)) / (2 * (n - 1)));
  return out;
}

std::string render_report_html(const Report& report) {
  const std::string title = report.title.empty() ? "Report" : report.title;
  std::string out;
  out += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += "<meta name=\"generator\" content=\"draco-mbd\">\n";
  out += fmt::format("<title>{}</title>\n<style>{}{}</style>\n</head>\n<body>\n<main>\n", html_escape(title), kStyle,
                     report.replay.variants.empty() ? "" : detail::kReplayCss);

  out += fmt::format("<header>\n<h1>{}</h1>\n", html_escape(title));
  out += paragraphs(report.description, "description");
  out += "</header>\n";

  if (!report.summary.empty()) {
    out += "<section id=\"summary\">\n<h2>Summary</h2>\n<dl class=\"summary\">\n";
    for (const auto& [key, value] : report.summary)
      out += fmt::format("<dt>{}</dt><dd>{}</dd>\n", html_escape(key), html_escape(value));
    out += "</dl>\n</section>\n";
  }

  metrics_section(report.metrics, out);

  if (!report.plots.empty()) {
    out += "<section id=\"plots\">\n<h2>Plots</h2>\n";
    for (std::size_t i = 0; i < report.plots.size(); ++i) {
      const ReportFigure& plot = report.plots[i];
      const std::string url = checked_url(plot.path, fmt::format("plots[{}].path", i));
      const std::string alt = plot.caption.empty() ? plot.path : plot.caption;
      out += fmt::format("<figure>\n<a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a>\n", url, html_escape(alt));
      if (!plot.caption.empty())
        out += fmt::format("<figcaption>Figure {}. {}</figcaption>\n", i + 1, html_escape(plot.caption));
      out += "</figure>\n";
    }
    out += "</section>\n";
  }

  detail::replay_section(report.replay, out);

  if (!report.frames.empty() && report.max_frames > 0) {
    const auto shown = evenly_spaced_indices(report.frames.size(), report.max_frames);
    out += "<section id=\"frames\">\n<h2>Frames</h2>\n";
    if (shown.size() < report.frames.size())
      out += fmt::format("<p class=\"muted\">{} of {} frames, evenly spaced.</p>\n", shown.size(),
                         report.frames.size());
    out += "<div class=\"frames\">\n";
    for (std::size_t i : shown) {
      const ReportFrame& frame = report.frames[i];
      const std::string url = checked_url(frame.path, fmt::format("frames[{}].path", i));
      const std::string label =
          frame.time_s ? fmt::format("t = {} s", format_time(*frame.time_s)) : fmt::format("frame {}", i);
      out += fmt::format("<figure>\n<a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a>\n<figcaption>{1}</figcaption>\n"
                         "</figure>\n",
                         url, html_escape(label));
    }
    out += "</div>\n</section>\n";
  }

  if (!report.video.empty()) {
    const std::string url = checked_url(report.video, "video");
    std::string poster;
    if (!report.video_poster.empty())
      poster = fmt::format(" poster=\"{}\"", checked_url(report.video_poster, "video_poster"));
    out += "<section id=\"video\">\n<h2>Video</h2>\n<figure>\n";
    out += fmt::format("<video controls preload=\"metadata\" playsinline{}>\n<source src=\"{}\" type=\"video/mp4\">\n"
                       "<a href=\"{}\">Download the video</a>\n</video>\n",
                       poster, url, url);
    if (!report.video_caption.empty())
      out += fmt::format("<figcaption>{}</figcaption>\n", html_escape(report.video_caption));
    out += "</figure>\n</section>\n";
  }

  bool any_note = false;
  for (const std::string& note : report.notes) any_note = any_note || !note.empty();
  if (any_note) {
    out += "<section id=\"notes\" class=\"notes\">\n<h2>Notes</h2>\n";
    for (const std::string& note : report.notes)
      if (!note.empty()) out += fmt::format("<p>{}</p>\n", html_escape(note));
    out += "</section>\n";
  }

  out += "<footer>Generated by draco-mbd.</footer>\n</main>\n";
  detail::replay_scripts(report.replay, out);
  out += "</body>\n</html>\n";
  return out;
}

void write_report(const Report& report, const std::string& path) {
  const std::string html = render_report_html(report);
  dmbd::write_file_atomic(path, html);
}

}  // namespace dmbd::viz
