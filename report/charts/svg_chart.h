// Per-slice charts for report.html as standalone inline SVG: series of values per slice (a gap
// where a value is missing), optional ± errors (whiskers or a shaded band), highlighted slices
// (flagged, dropped) as thin vertical bands, an optional dashed threshold line, axes with 1-2-5
// ticks, a legend. Small and readable at any slice count: up to SliceChart::kMaxPointSlices slices
// every value is a point with a tooltip; above, each series is a line downsampled to its minimum
// and maximum per pixel column (spikes survive), with no per-point tooltips (a 4000-frame sweep
// stays a few tens of kB). A pure function: the same chart gives the same bytes, whatever the
// locale.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace xsect {

/// One quantity plotted per slice.
struct ChartSeries {
  /// Legend text, and the prefix of its tooltips; empty: no legend entry.
  std::string name;
  /// CSS colour of its line, points and errors (e.g. "#1f77b4"); empty: a fixed palette's colour
  /// chosen by the series' index.
  std::string colour;
  /// One value per SliceChart::x, in the chart's y unit. NaN or ±infinity: no value at that
  /// slice (the line breaks there); with SliceChart::log_y, values <= 0 are gaps too.
  std::vector<double> values;
  /// Empty, or one ± half-width per SliceChart::x, in the y unit, >= 0; NaN: none at that slice.
  /// Drawn as whiskers when points are drawn, as a shaded band (per pixel column, the lowest
  /// value - error to the highest value + error) above.
  std::vector<double> error;
};

/// Highlighted slices, e.g. the flagged or the dropped ones: a thin vertical band of `colour`
/// across the plot at each.
struct ChartMark {
  /// Legend text, and the tooltip of each band ("slice 12: flagged"); empty: no legend entry.
  std::string name;
  /// CSS colour of the bands (drawn a quarter opaque); empty: a fixed palette's colour.
  std::string colour;
  /// Indices into SliceChart::x (not slice numbers), any order; duplicates are drawn once.
  std::vector<int> x_index;
};

/// A chart of values per slice.
struct SliceChart {
  /// Up to this many slices, every finite value is drawn as a point with a tooltip; above, as a
  /// min/max-downsampled line without tooltips.
  static constexpr int kMaxPointSlices = 150;

  /// The id attribute of the <svg> element; empty: none.
  std::string id;
  /// Drawn above the plot, left-aligned; empty: none.
  std::string title;
  /// Below the x axis, and the word before a slice number in tooltips ("slice 12: ...").
  std::string x_label = "slice";
  /// Beside the y axis, with its unit, e.g. "disagreement (mm)"; empty: none.
  std::string y_label;
  /// The y unit written after values in tooltips, e.g. "mm" or "°"; empty: none.
  std::string y_unit;
  /// The slice numbers, strictly ascending; the x axis is linear in them (gaps in the numbering
  /// show as gaps).
  std::vector<int> x;
  std::vector<ChartSeries> series;
  std::vector<ChartMark> marks;
  /// A horizontal dashed line at this y (in the y unit), e.g. the flag threshold; NaN or
  /// infinite: none (with log_y, also <= 0). The y range always includes it.
  double threshold = std::numeric_limits<double>::quiet_NaN();
  /// Written at the right end of the threshold line; empty: none.
  std::string threshold_label;
  /// A logarithmic y axis (decade ticks, with 2 and 5 between when the range spans at most two
  /// decades).
  bool log_y = false;
};

/// `chart` as one standalone <svg> element (no XML declaration; UTF-8 text as given, XML-escaped,
/// control characters dropped), `width` x `height` CSS pixels (at least 200 x 120). Coordinates are
/// written with at most 2 decimals (1 for the y of downsampled lines and bands: 0.1 pixel), numbers
/// locale-independently. The y range covers every finite
/// value ± its error and the threshold, widened to nice 1-2-5 ticks (linear: to include 0 when the
/// data lie on one side of it and no farther than their own span from it; a constant series gets
/// 0 to its value, or 0 to 1 when 0). Without any value to draw (no slice, no series, every value
/// a gap) the result is a `width` x 48 SVG with the title and "no data".
/// Throws std::invalid_argument naming the chart and the offender on: a size below 200 x 120;
/// slice numbers not strictly ascending; a series whose values (or non-empty errors) do not number
/// one per slice, or with a negative error; a mark index outside x.
std::string svgSliceChart(const SliceChart& chart, int width = 760, int height = 240);

}  // namespace xsect
