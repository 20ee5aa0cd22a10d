// A figure of merit against a swept parameter (docs/scenario-format.md, "sweep_plots"):
// the runs grouped into lines by their other matrix axes, each line's points ordered by
// the swept axis's `value`, and the sampled values where every curve's condition holds.
// The verdict is about the sampled values only: between a value where it holds and one
// where it fails the boundary is not located, and the figure and the metrics say so.
#include "sweep_plots.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/base/strings.hpp"
#include "dmbd/experiments/sampled_interval.hpp"

namespace dmbd::scenario::detail {

namespace {

// One line of runs: those whose other axes have the same values, ordered by x.
struct Line {
  std::string name;                        // the other axes' value names joined with "/" ("" when the sweep axis is the only one)
  std::vector<std::pair<double, std::string>> points;  // (x, run name)
};

std::vector<Line> lines_of(const Scenario& s, const std::string& axis) {
  std::vector<Line> lines;
  for (const VariantSetup& v : s.variants) {
    std::string other;
    for (const auto& [a, value] : v.axes)
      if (a != axis) other += (other.empty() ? "" : "/") + value;
    const auto x = std::find_if(v.axis_values.begin(), v.axis_values.end(), [&](const auto& av) { return av.first == axis; });
    if (x == v.axis_values.end()) continue;  // load_scenario refuses this
    auto it = std::find_if(lines.begin(), lines.end(), [&](const Line& l) { return l.name == other; });
    if (it == lines.end()) it = lines.insert(lines.end(), Line{other, {}});
    it->points.emplace_back(x->second, v.name);
  }
  for (Line& l : lines) std::stable_sort(l.points.begin(), l.points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return lines;
}

// The run's name inside a JSON pointer: '~' and '/' escaped (RFC 6901).
std::string pointer_token(const std::string& name) {
  std::string out;
  for (char c : name) out += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return out;
}

// The curve's value for a run (scaled); NaN when the pointer finds nothing (`missing` set:
// the run did not get that far, or the pointer is misspelt: add_sweep_plots tells which).
double value_of(const Scenario& s, const SweepPlotSetup& p, const SweepCurve& c, const std::string& run, const nlohmann::json& metrics,
                bool& missing) {
  std::string ptr = c.metric;
  for (std::size_t at; (at = ptr.find("{run}")) != std::string::npos;) ptr.replace(at, 5, pointer_token(run));
  const std::string where = fmt::format("{}: sweep_plot '{}' ({}): metric {} of run '{}'", s.file, p.file, p.where, ptr, run);
  nlohmann::json::json_pointer jp;
  try {
    jp = nlohmann::json::json_pointer(ptr);
  } catch (const nlohmann::json::exception&) {
    throw InputError(where + ": not a valid JSON pointer");
  }
  missing = !metrics.contains(jp);
  if (missing) return NAN;
  const nlohmann::json& v = metrics.at(jp);
  if (v.is_null()) return NAN;  // a figure the experiment could not compute
  if (!v.is_number()) throw InputError(where + ": expected a number, got " + v.dump());
  return v.get<double>() * c.scale;
}

bool meets(const SweepCurve& c, double y) {
  if (std::isnan(y)) return !c.at_most && !c.at_least;
  return (!c.at_most || y <= *c.at_most) && (!c.at_least || y >= *c.at_least);
}

// The sampled range with a margin (a log axis's automatic whole decades would leave most
// of a 0.05..1 sweep's width empty).
std::optional<std::pair<double, double>> x_limits(const std::vector<Line>& lines, bool log_x) {
  double lo = INFINITY, hi = -INFINITY;
  for (const Line& l : lines)
    for (const auto& pt : l.points)
      if (std::isfinite(pt.first) && (!log_x || pt.first > 0)) lo = std::min(lo, pt.first), hi = std::max(hi, pt.first);
  if (!(lo < hi)) return std::nullopt;
  if (log_x) return std::pair{lo / std::pow(hi / lo, 0.04), hi * std::pow(hi / lo, 0.04)};
  return std::pair{lo - 0.04 * (hi - lo), hi + 0.04 * (hi - lo)};
}

// One axes per curve, one series per line, the condition as a dashed line.
plot::Figure figure_of(const SweepPlotSetup& p, const std::vector<Line>& lines, const std::vector<std::vector<std::vector<double>>>& y) {
  plot::Figure fig(1000, static_cast<int>(120 + 260 * p.curves.size()));
  fig.title = p.title;
  for (std::size_t c = 0; c < p.curves.size(); ++c) {
    plot::Axes& a = fig.add_axes();
    a.title = p.curves[c].label;
    a.y_label = p.y_label;
    a.x_label = c + 1 == p.curves.size() ? p.x_label : "";
    a.x_tick_labels = c + 1 == p.curves.size();
    if (p.log_x) a.x_scale = plot::Scale::Log;
    a.x_limits = x_limits(lines, p.log_x);
    for (std::size_t l = 0; l < lines.size(); ++l) {
      plot::Series s{lines[l].name, {}, y[l][c], plot::palette_color(l)};
      for (const auto& pt : lines[l].points) s.x.push_back(pt.first);
      s.markers = true;
      a.series.push_back(s);
    }
    for (const auto& [bound, word] : {std::pair{p.curves[c].at_most, "at most"}, std::pair{p.curves[c].at_least, "at least"}})
      if (bound) {
        a.h_lines.push_back(*bound);
        a.h_line_labels.push_back(fmt::format("{} {:g}", word, *bound));
      }
    a.legend = lines.size() > 1;
  }
  return fig;
}

}  // namespace

void add_sweep_plots(const Scenario& s, experiments::ExperimentResult& res) {
  for (const SweepPlotSetup& p : s.sweep_plots) {
    const std::vector<Line> lines = lines_of(s, p.axis);
    std::vector<std::vector<std::vector<double>>> y(lines.size());  // [line][curve][point]
    std::map<std::string, std::vector<std::string>> missing_in;      // curve's pointer -> runs without a value
    std::map<std::string, std::size_t> asked;
    nlohmann::json entry = {{"axis", p.axis}, {"lines", nlohmann::json::object()}};
    for (std::size_t l = 0; l < lines.size(); ++l) {
      std::vector<double> x;
      std::vector<std::string> runs;
      for (const auto& [xv, run] : lines[l].points) x.push_back(xv), runs.push_back(run);
      std::vector<bool> holds(x.size(), true);
      nlohmann::json curves = nlohmann::json::object();
      for (const SweepCurve& c : p.curves) {
        std::vector<double> ys;
        for (std::size_t k = 0; k < runs.size(); ++k) {
          bool missing = false;
          ys.push_back(value_of(s, p, c, runs[k], res.metrics, missing));
          holds[k] = holds[k] && meets(c, ys.back());
          if (missing) missing_in[c.metric].push_back(runs[k]);
          ++asked[c.metric];
        }
        curves[c.label] = ys;
        y[l].push_back(ys);
      }
      nlohmann::json line = {{p.axis, x}, {"runs", runs}, {"curves", curves}, {"holds", holds}};
      line.update(experiments::sampled_interval(x, holds));
      const std::string name = lines[l].name.empty() ? "all" : lines[l].name;
      res.notes.push_back(fmt::format("Sweep {} ({}): {} over {}: {}.", p.file, name, p.title.empty() ? "the conditions" : p.title, p.axis,
                                      line["verdict"].get<std::string>()));
      entry["lines"][name] = line;
    }
    // A pointer that finds nothing in any run is a mistake; in some runs, those runs did
    // not get there (a robot that fell has no replay): their points fail, and say so.
    for (const auto& [metric, runs] : missing_in) {
      if (runs.size() == asked[metric])
        throw InputError(fmt::format("{}: sweep_plot '{}' ({}): metric {}: metrics.json has no such value for any run", s.file, p.file, p.where,
                                     metric));
      res.warnings.push_back(fmt::format("sweep_plot '{}': metric {} has no value for run(s) {}: taken as not meeting its condition", p.file,
                                         metric, join(runs)));
    }
    res.metrics["sweeps"][std::filesystem::path(p.file).stem().string()] = entry;
    res.figures.emplace_back(p.file, figure_of(p, lines, y));
  }
}

}  // namespace dmbd::scenario::detail
