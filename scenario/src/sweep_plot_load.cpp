// Reading `sweep_plots` (docs/scenario-format.md, "sweep_plots"): a figure of merit
// against a numeric matrix axis, each curve a metrics.json value with its condition.
#include "scenario_reader.hpp"

#include "dmbd/base/strings.hpp"

namespace dmbd::scenario::detail {

namespace {

// The axis must be one of the matrix's, every value of it with a `value`.
void check_axis(const Reader& rd, const YAML::Node& at, const std::string& axis, const YAML::Node& matrix) {
  if (!matrix || !matrix.IsMap()) rd.fail(at, "sweep_plot.axis: the scenario has no matrix (a sweep plot's x is a matrix axis)");
  std::vector<std::string> axes;
  for (const auto& kv : matrix) axes.push_back(kv.first.Scalar());
  const YAML::Node values = matrix[axis];
  if (!values) rd.fail(at, "sweep_plot.axis: the matrix has no axis '" + axis + "' (its axes: " + join(axes) + ")");
  if (!values.IsSequence()) return;  // read_matrix reports it
  for (const auto& v : values)
    if (v.IsMap() && !v["value"])
      rd.fail(v, "matrix." + axis + ": each value needs a number 'value' to be the x of sweep_plot '" + rd.at(at) + "'");
}

SweepCurve curve(const Reader& rd, const YAML::Node& c) {
  rd.keys(c, "sweep_plot.curve", {"metric", "label", "scale", "at_most", "at_least"});
  SweepCurve out;
  out.metric = rd.text(rd.required(c, "metric", "sweep_plot.curve"), "sweep_plot.curve.metric");
  if (out.metric.empty() || out.metric[0] != '/')
    rd.fail(c["metric"], "sweep_plot.curve.metric: expected a JSON pointer into metrics.json such as /osc/{run}/ankle_max_error_m");
  if (out.metric.find("{run}") == std::string::npos)
    rd.fail(c["metric"], "sweep_plot.curve.metric: expected {run} in the pointer (the run's name: one value per run)");
  out.label = out.metric;
  rd.optional(c, "label", [&](const YAML::Node& x) { out.label = rd.text(x, "sweep_plot.curve.label"); });
  rd.optional(c, "scale", [&](const YAML::Node& x) { out.scale = rd.positive(x, "sweep_plot.curve.scale"); });
  rd.optional(c, "at_most", [&](const YAML::Node& x) { out.at_most = rd.number(x, "sweep_plot.curve.at_most"); });
  rd.optional(c, "at_least", [&](const YAML::Node& x) { out.at_least = rd.number(x, "sweep_plot.curve.at_least"); });
  return out;
}

}  // namespace

void read_sweep_plots(const Reader& rd, const YAML::Node& list, const YAML::Node& matrix, std::vector<SweepPlotSetup>& out) {
  if (!list.IsSequence()) rd.fail(list, "sweep_plots: expected a list");
  rd.each(list, [&](const YAML::Node& p) {
    rd.keys(p, "sweep_plot", {"file", "axis", "title", "x_label", "y_label", "log_x", "curves"});
    SweepPlotSetup sp;
    sp.where = rd.at(p);
    sp.file = rd.text(rd.required(p, "file", "sweep_plot"), "sweep_plot.file");
    for (const auto& other : out)
      if (other.file == sp.file) rd.fail(p["file"], "sweep_plot.file: '" + sp.file + "' is given twice (first at " + other.where + ")");
    sp.axis = rd.text(rd.required(p, "axis", "sweep_plot"), "sweep_plot.axis");
    check_axis(rd, p["axis"], sp.axis, matrix);
    sp.x_label = sp.axis;
    rd.optional(p, "title", [&](const YAML::Node& x) { sp.title = rd.text(x, "sweep_plot.title"); });
    rd.optional(p, "x_label", [&](const YAML::Node& x) { sp.x_label = rd.text(x, "sweep_plot.x_label"); });
    rd.optional(p, "y_label", [&](const YAML::Node& x) { sp.y_label = rd.text(x, "sweep_plot.y_label"); });
    rd.optional(p, "log_x", [&](const YAML::Node& x) { sp.log_x = rd.boolean(x, "sweep_plot.log_x"); });
    const YAML::Node curves = rd.required(p, "curves", "sweep_plot");
    if (!curves.IsSequence() || curves.size() == 0) rd.fail(curves, "sweep_plot.curves: expected a list of curves ({metric, label, at_most})");
    if (curves.size() > 8) rd.fail(curves, "sweep_plot.curves: at most 8 curves (one axes each)");
    rd.each(curves, [&](const YAML::Node& c) { sp.curves.push_back(curve(rd, c)); });
    out.push_back(sp);
  });
}

}  // namespace dmbd::scenario::detail
