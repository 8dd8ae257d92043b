// Per-slice plots for report.html (see slice_plots.h).
#include "report/run/slice_plots.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "report/page/report_page.h"
#include "report/charts/svg_chart.h"
#include "report/run/page_text.h"

namespace xsect {

using json = nlohmann::ordered_json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double number(const json& v) { return v.is_number() ? v.get<double>() : kNaN; }

/// The rows of conformity.json in slice order, and the marks every plot carries.
struct Rows {
  std::vector<const json*> rows;
  std::vector<int> x;
  std::vector<ChartMark> marks;
};

Rows rowsOf(const json& conformity) {
  Rows r;
  for (const json& s : field(conformity, {"slices"})) r.rows.push_back(&s);
  std::stable_sort(r.rows.begin(), r.rows.end(),
                   [](const json* a, const json* b) { return a->value("slice", 0) < b->value("slice", 0); });
  // Repeated slice numbers cannot happen (one row per plane); kept strictly ascending regardless.
  r.rows.erase(std::unique(r.rows.begin(), r.rows.end(),
                           [](const json* a, const json* b) { return a->value("slice", 0) == b->value("slice", 0); }),
               r.rows.end());
  ChartMark flagged{"flagged", "#f59e0b", {}}, dropped{"dropped", "#d64545", {}}, outlier{"pose outlier", "#9b59b6", {}};
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const json& s = *r.rows[i];
    r.x.push_back(s.value("slice", 0));
    if (s.value("dropped", false)) dropped.x_index.push_back(int(i));
    else if (s.value("flagged", false)) flagged.x_index.push_back(int(i));
    if (field(s, {"pose_correction", "outlier"}) == json(true)) outlier.x_index.push_back(int(i));
  }
  for (ChartMark* m : {&flagged, &dropped, &outlier})
    if (!m->x_index.empty()) r.marks.push_back(*m);
  return r;
}

template <typename Get>
ChartSeries series(const Rows& r, const std::string& name, const std::string& colour, const Get& get) {
  ChartSeries s{name, colour, {}, {}};
  for (const json* row : r.rows) s.values.push_back(get(*row));
  return s;
}

bool anyFinite(const ChartSeries& s) {
  return std::any_of(s.values.begin(), s.values.end(), [](double v) { return std::isfinite(v); });
}

/// A chart over the rows' slices with their marks.
SliceChart chartOf(const Rows& r, const std::string& id, const std::string& title, const std::string& yLabel,
                   const std::string& yUnit) {
  SliceChart c;
  c.id = id;
  c.title = title;
  c.y_label = yLabel;
  c.y_unit = yUnit;
  c.x = r.x;
  c.marks = r.marks;
  return c;
}

/// The name of the disagreement measured before enforcement: after pose correction when asked.
std::string measuredName(const json& conformity) {
  return field(conformity, {"summary", "pose_correction"}).is_null() ? "measured" : "measured after pose correction";
}

/// The chart with its caption, or nothing when no series holds a value other than zero (a plot
/// flat at zero, or empty, shows nothing).
std::string plot(const std::string& what, SliceChart chart) {
  const bool shows = std::any_of(chart.series.begin(), chart.series.end(), [](const ChartSeries& s) {
    return std::any_of(s.values.begin(), s.values.end(), [](double v) { return std::isfinite(v) && v != 0; });
  });
  return shows ? "<p>" + htmlEscape(what) + "</p>\n" + svgSliceChart(chart) + "\n" : std::string();
}

}  // namespace

std::string slicePlotsHtml(const json& conformity) {
  const Rows r = rowsOf(conformity);
  if (r.rows.empty()) return "";  // no pair of slices crosses with sections
  std::string html;

  SliceChart disagreement = chartOf(r, "plot-disagreement", "Disagreement with the slices each slice crosses",
                                    "median over its crossings (mm)", "mm");
  disagreement.series.push_back(series(r, measuredName(conformity), "#d64545", [](const json& s) { return number(field(s, {"before", "median_mismatch_mm"})); }));
  ChartSeries after = series(r, "after enforcement", "#3aa35b", [](const json& s) { return number(field(s, {"after", "median_mismatch_mm"})); });
  if (anyFinite(after)) disagreement.series.push_back(after);
  disagreement.threshold = number(field(conformity, {"summary", "flagged_above_mm"}));
  disagreement.threshold_label = "flagged above";
  // Disagreements span decades (a well-tracked series sits far below its flag threshold): a
  // logarithmic axis when the threshold would squash them against zero.
  double largest = 0;
  for (const ChartSeries& s : disagreement.series)
    for (const double v : s.values)
      if (std::isfinite(v)) largest = std::max(largest, v);
  disagreement.log_y = largest > 0 && disagreement.threshold > 20 * largest;
  html += plot("How far each slice's contours are from those of the slices it crosses, along their common lines "
               "(conformity, stage 3). Slices far above the others are probable tracking or segmentation failures.",
               disagreement);

  if (!field(conformity, {"summary", "pose_correction"}).is_null()) {
    SliceChart shift = chartOf(r, "plot-pose-shift", "Pose correction: shift", "shift (mm)", "mm");
    ChartSeries s = series(r, "shift ± its uncertainty", "#4e79a7", [](const json& row) { return number(field(row, {"pose_correction", "shift_mm"})); });
    for (const json* row : r.rows) s.error.push_back(number(field(*row, {"pose_correction", "sigma_shift_mm"})));
    shift.series.push_back(s);
    html += plot("The translation each slice's pose was corrected by, with its standard uncertainty from the fit.", shift);

    SliceChart rotation = chartOf(r, "plot-pose-rotation", "Pose correction: rotation", "rotation (°)", "°");
    ChartSeries a = series(r, "rotation ± its uncertainty", "#b07aa1", [](const json& row) { return number(field(row, {"pose_correction", "rotation_deg"})); });
    for (const json* row : r.rows) a.error.push_back(number(field(*row, {"pose_correction", "sigma_rotation_deg"})));
    rotation.series.push_back(a);
    html += plot("The rotation each slice's pose was corrected by, with its standard uncertainty.", rotation);

    SliceChart gaps = chartOf(r, "plot-pose-gaps", "Pose correction: gaps where contours cross other slices", "gap (mm)", "mm");
    gaps.series = {series(r, "before", "#d64545", [](const json& row) { return number(field(row, {"pose_correction", "gap_before_mm"})); }),
                   series(r, "after", "#3aa35b", [](const json& row) { return number(field(row, {"pose_correction", "gap_after_mm"})); })};
    html += plot("Where a slice's contour pierces another slice, the distance to that slice's contour, before and after correction.", gaps);
  }

  if (!field(conformity, {"summary", "pose_smoothing"}).is_null()) {
    SliceChart smoothing = chartOf(r, "plot-pose-smoothing", "Pose change per slice (smoothing along the sweep)",
                                   "shift (mm)", "mm");
    smoothing.series.push_back(series(r, "shift", "#4e79a7", [](const json& s) { return number(field(s, {"pose_shift_mm"})); }));
    html += plot("How far each frame's pose moved when the sweep's trajectory was smoothed (and corrected, when asked).", smoothing);
  }
  return html;
}

}  // namespace xsect
