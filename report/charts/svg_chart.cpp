// Per-slice SVG charts (see svg_chart.h): layout (title, legend rows, margins sized to the tick
// labels), nice 1-2-5 (or decade) ticks, then the marks, the series (points with tooltips, or
// min/max-per-pixel-column lines), the threshold and the axes, as text.
#include "report/charts/svg_chart.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace xsect {

namespace {

// ---- text ---------------------------------------------------------------------------------------

/// `s` escaped for XML text and attribute values; C0 control characters other than tab, line
/// feed and carriage return (not allowed in XML 1.0) are dropped.
std::string xmlEscaped(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char ch : s) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20 && ch != '\t' && ch != '\n' && ch != '\r') break;
        out += ch;
    }
  }
  return out;
}

/// `v` (finite) in fixed notation with `decimals` decimals, locale-independent; "-0..." is "0...".
std::string fixedText(double v, int decimals) {
  char buf[512];  // the longest fixed double (~310 digits) fits
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  std::string s(buf, r.ptr);
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

/// `s` (fixed notation) without trailing zero decimals and without a bare decimal point.
std::string trimmedZeros(std::string s) {
  if (s.find('.') == std::string::npos) return s;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  if (s == "-0") s = "0";
  return s;
}

/// A pixel coordinate: at most `decimals` decimals, trailing zeros dropped ("12.5", "40").
std::string px(double v, int decimals = 2) { return trimmedZeros(fixedText(v, decimals)); }

/// `v` in scientific notation with 3 significant digits ("1.23e+12").
std::string scientificText(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific, 2);
  return std::string(buf, r.ptr);
}

/// A data value for a tooltip: 3 significant digits, trailing zeros dropped ("0.31", "1250",
/// "0.00412"); scientific outside [1e-4, 1e9).
std::string valueText(double v) {
  if (v == 0) return "0";
  const double a = std::fabs(v);
  if (a < 1e-4 || a >= 1e9) return scientificText(v);
  const int decimals = std::clamp(2 - static_cast<int>(std::floor(std::log10(a))), 0, 6);
  return trimmedZeros(fixedText(v, decimals));
}

/// The approximate width in pixels of `s` (UTF-8) at font size 11 sans-serif.
double textWidth(const std::string& s) {
  int codePoints = 0;
  for (char ch : s) codePoints += (static_cast<unsigned char>(ch) & 0xC0) != 0x80;
  return 6.2 * codePoints;
}

const char* const kSeriesPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd",
                                      "#8c564b", "#e377c2", "#17becf", "#bcbd22"};
const char* const kMarkPalette[] = {"#d62728", "#7f7f7f", "#ff7f0e", "#9467bd"};

std::string seriesColour(const ChartSeries& s, std::size_t i) {
  return xmlEscaped(s.colour.empty() ? kSeriesPalette[i % 8] : s.colour);
}
std::string markColour(const ChartMark& m, std::size_t i) {
  return xmlEscaped(m.colour.empty() ? kMarkPalette[i % 4] : m.colour);
}

// ---- validation ---------------------------------------------------------------------------------

void validate(const SliceChart& c, int width, int height) {
  const std::string who = "svgSliceChart(\"" + c.id + "\"): ";
  if (width < 200 || height < 120)
    throw std::invalid_argument(who + "size " + std::to_string(width) + " x " +
                                std::to_string(height) + " below 200 x 120");
  for (std::size_t i = 1; i < c.x.size(); ++i)
    if (c.x[i] <= c.x[i - 1])
      throw std::invalid_argument(who + "slice numbers not strictly ascending at index " +
                                  std::to_string(i) + " (" + std::to_string(c.x[i - 1]) + " then " +
                                  std::to_string(c.x[i]) + ")");
  const std::string n = std::to_string(c.x.size());
  for (const ChartSeries& s : c.series) {
    if (s.values.size() != c.x.size())
      throw std::invalid_argument(who + "series \"" + s.name + "\" has " +
                                  std::to_string(s.values.size()) + " values for " + n + " slices");
    if (!s.error.empty() && s.error.size() != c.x.size())
      throw std::invalid_argument(who + "series \"" + s.name + "\" has " +
                                  std::to_string(s.error.size()) + " errors for " + n + " slices");
    for (std::size_t i = 0; i < s.error.size(); ++i)
      if (s.error[i] < 0)
        throw std::invalid_argument(who + "series \"" + s.name + "\" has a negative error at " +
                                    c.x_label + " " + std::to_string(c.x[i]));
  }
  for (const ChartMark& m : c.marks)
    for (int i : m.x_index)
      if (i < 0 || static_cast<std::size_t>(i) >= c.x.size())
        throw std::invalid_argument(who + "mark \"" + m.name + "\" has index " + std::to_string(i) +
                                    " outside the " + n + " slices");
}

// ---- scales -------------------------------------------------------------------------------------

/// Whether a value is drawn.
bool usable(double v, bool logY) { return std::isfinite(v) && (!logY || v > 0); }

/// The 1-2-5 multiple of a power of ten nearest above `raw` (> 0).
double niceStep(double raw) {
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double n = raw / mag;
  return (n <= 1 + 1e-9 ? 1 : n <= 2 + 1e-9 ? 2 : n <= 5 + 1e-9 ? 5 : 10) * mag;
}

/// The 1-2-5 step just below `step` (itself one): 1 -> 0.5, 2 -> 1, 5 -> 2 (times its power of
/// ten).
double finerStep(double step) {
  const double mag = std::pow(10.0, std::floor(std::log10(step) + 1e-9));
  return step / mag > 3 ? 0.4 * step : 0.5 * step;
}

/// A value axis: [lo, hi] (linear or log10) with its ticks and their labels.
struct ValueAxis {
  bool log = false;
  double lo = 0, hi = 1;
  std::vector<double> ticks;
  std::vector<std::string> labels;

  /// Where `v` lies between lo (0) and hi (1).
  double fraction(double v) const {
    if (log) return (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
    return (v - lo) / (hi - lo);
  }
};

/// Linear axis over [lo, hi] (finite, lo < hi) with ticks at multiples of a 1-2-5 step, widened
/// to the ticks just outside: the step giving about `target` intervals, or the next finer one
/// when that covers a narrower range in at most 2 `target` intervals (a value just below a tick
/// does not cost a whole coarse step).
ValueAxis linearAxis(double lo, double hi, int target) {
  ValueAxis a;
  double step = niceStep((hi - lo) / target);
  double k0 = std::floor(lo / step + 1e-9), k1 = std::ceil(hi / step - 1e-9);
  const double fine = finerStep(step);
  const double f0 = std::floor(lo / fine + 1e-9), f1 = std::ceil(hi / fine - 1e-9);
  if (f1 - f0 <= 2 * target && (f1 - f0) * fine < (k1 - k0) * step * (1 - 1e-9))
    step = fine, k0 = f0, k1 = f1;
  if (!(step > 0) || !std::isfinite(step) || !(k1 - k0 <= 1000)) {  // absurd magnitudes
    a.lo = lo, a.hi = hi, a.ticks = {lo, hi};
    a.labels = {scientificText(lo), scientificText(hi)};
    return a;
  }
  if (k1 <= k0) k1 = k0 + 1;
  a.lo = k0 * step;
  a.hi = k1 * step;
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  const double largest = std::max(std::fabs(a.lo), std::fabs(a.hi));
  const bool scientific = decimals > 6 || largest >= 1e9;
  for (double k = k0; k <= k1; ++k) {
    const double v = k == 0 ? 0.0 : k * step;
    a.ticks.push_back(v);
    a.labels.push_back(scientific ? scientificText(v) : fixedText(v, decimals));
  }
  return a;
}

/// The label of d · 10^e (d = 1, 2 or 5).
std::string decadeLabel(int d, int e) {
  if (e >= -4 && e <= 8) return fixedText(d * std::pow(10.0, e), std::max(0, -e));
  return std::to_string(d) + "e" + std::to_string(e);
}

/// Log axis over [lo, hi] (0 < lo <= hi) from the decade at or below lo to the one at or above
/// hi: a tick every `every` decades (about `target` ticks), with 2 and 5 between when it spans
/// at most two decades.
ValueAxis logAxis(double lo, double hi, int target) {
  ValueAxis a;
  a.log = true;
  const int e0 = static_cast<int>(std::floor(std::log10(lo) + 1e-9));
  int e1 = static_cast<int>(std::ceil(std::log10(hi) - 1e-9));
  if (e1 <= e0) e1 = e0 + 1;
  const int every = std::max(1, (e1 - e0 + 2 * target - 1) / (2 * target));  // short labels
  e1 = e0 + every * ((e1 - e0 + every - 1) / every);
  a.lo = std::pow(10.0, e0);
  a.hi = std::pow(10.0, e1);
  for (int e = e0; e <= e1; e += every) {
    a.ticks.push_back(std::pow(10.0, e));
    a.labels.push_back(decadeLabel(1, e));
    if (e1 - e0 <= 2 && e < e1)
      for (int d : {2, 5}) {
        a.ticks.push_back(d * std::pow(10.0, e));
        a.labels.push_back(decadeLabel(d, e));
      }
  }
  return a;
}

/// The y axis of `c` with about `target` ticks; false when nothing is drawn.
bool yAxisOf(const SliceChart& c, int target, ValueAxis* axis) {
  const bool logY = c.log_y;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  auto include = [&](double v) {
    if (!usable(v, logY)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  };
  bool any = false;
  for (const ChartSeries& s : c.series)
    for (std::size_t i = 0; i < s.values.size(); ++i) {
      const double v = s.values[i];
      if (!usable(v, logY)) continue;
      any = true;
      include(v);
      if (!s.error.empty() && std::isfinite(s.error[i])) {
        include(v - s.error[i]);  // with a log axis, a lower end <= 0 is cut at the axis
        include(v + s.error[i]);
      }
    }
  if (!any) return false;
  include(c.threshold);
  if (logY) {
    *axis = logAxis(lo, hi, target);
    return true;
  }
  if (hi - lo <= 1e-12 * std::max(std::fabs(lo), std::fabs(hi))) {  // constant
    if (lo > 0)
      lo = 0;
    else if (hi < 0)
      hi = 0;
    else
      lo = 0, hi = 1;
  } else if (lo > 0 && lo <= hi - lo) {
    lo = 0;
  } else if (hi < 0 && hi >= lo - hi) {
    hi = 0;
  }
  *axis = linearAxis(lo, hi, target);
  return true;
}

// ---- drawing ------------------------------------------------------------------------------------

struct Point {
  double x, y;
};

/// Path data of polylines: "M x,y x,y ..." per run, y with at most `yDecimals` decimals; a run of
/// one point is a dot (zero-length segment, drawn by round line caps).
std::string polylinePath(const std::vector<std::vector<Point>>& runs, int yDecimals) {
  std::string d;
  for (const auto& run : runs) {
    if (run.empty()) continue;
    d += 'M';
    for (std::size_t i = 0; i < run.size(); ++i) {
      if (i) d += ' ';
      d += px(run[i].x) + ',' + px(run[i].y, yDecimals);
    }
    if (run.size() == 1) d += "h0";
  }
  return d;
}

/// The plot: where values and slices land in pixels.
struct Frame {
  double left, top, width, height;  // the plot area, pixels
  double x0, x1;                    // slice numbers at its left and right edges
  ValueAxis y;

  double xPx(double sliceNumber) const { return left + (sliceNumber - x0) / (x1 - x0) * width; }
  /// The pixel row of `v`, clamped to the plot (a log axis cuts values <= 0 at its bottom).
  double yPx(double v) const {
    const double f = y.log && !(v > 0) ? 0.0 : std::clamp(y.fraction(v), 0.0, 1.0);
    return top + (1 - f) * height;
  }
};

struct LegendEntry {
  bool isMark;
  std::size_t index;
  double x;
  int row;
};

/// What the parts of a slice chart read: the frame, the x axis' words and whether slices are drawn
/// as points (few slices) or as lines (one pixel column each).
struct ChartContext {
  const SliceChart& c;
  Frame f;
  std::size_t n = 0;  ///< slices
  double slotPx = 0;  ///< pixels per slice spacing
  bool points = false;
  std::string xWord, unit;
  double right = 0;  ///< the plot's right edge, px

  /// The legend's entries (series, then marks), `titleHeight` px from the top.
  std::string legendSvg(const std::vector<LegendEntry>& legend, double titleHeight) const {
    std::string out;
    out += "<g class=\"legend\">\n";
    for (const LegendEntry& e : legend) {
      const double y = titleHeight + 12 + 16.0 * e.row;
      if (e.isMark) {
        out += "<rect x=\"" + px(e.x + 2) + "\" y=\"" + px(y - 9) +
               "\" width=\"10\" height=\"10\" fill=\"" + markColour(c.marks[e.index], e.index) +
               "\" fill-opacity=\"0.35\"/>\n";
      } else {
        const std::string col = seriesColour(c.series[e.index], e.index);
        out += "<path d=\"M" + px(e.x) + ',' + px(y - 4) + "h14\" stroke=\"" + col +
               "\" stroke-width=\"2\"/>\n";
        if (points)
          out += "<circle cx=\"" + px(e.x + 7) + "\" cy=\"" + px(y - 4) + "\" r=\"2.5\" fill=\"" +
                 col + "\"/>\n";
      }
      const std::string& name = e.isMark ? c.marks[e.index].name : c.series[e.index].name;
      out +=
          "<text x=\"" + px(e.x + 18) + "\" y=\"" + px(y) + "\">" + xmlEscaped(name) + "</text>\n";
    }
    out += "</g>\n";
    return out;
  }

  /// Horizontal grid lines at the y ticks.
  std::string gridSvg() const {
    std::string d;
    for (double t : f.y.ticks) d += "M" + px(f.left) + ',' + px(f.yPx(t)) + "H" + px(right);
    return "<path class=\"grid\" d=\"" + d + "\" stroke=\"#e8e8e8\" fill=\"none\"/>\n";
  }

  /// Marks: thin vertical bands behind the data. With points, a rectangle with a tooltip per
  /// slice; with lines, one path whose bands merge where neighbouring slices' bands touch.
  std::string marksSvg() const {
    std::string out;
    const double markWidth = std::clamp(0.6 * slotPx, 1.0, 12.0);
    for (std::size_t m = 0; m < c.marks.size(); ++m) {
      std::vector<int> idx = c.marks[m].x_index;
      std::sort(idx.begin(), idx.end());
      idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
      if (idx.empty()) continue;
      out += "<g class=\"mark\" fill=\"" + markColour(c.marks[m], m) + "\" fill-opacity=\"0.25\">\n";
      if (points) {
        for (int i : idx) {
          out += "<rect x=\"" + px(f.xPx(c.x[i]) - markWidth / 2) + "\" y=\"" + px(f.top) +
                 "\" width=\"" + px(markWidth) + "\" height=\"" + px(f.height) + "\"><title>" +
                 xWord + " " + std::to_string(c.x[i]) +
                 (c.marks[m].name.empty() ? "" : ": " + xmlEscaped(c.marks[m].name)) +
                 "</title></rect>\n";
        }
      } else {
        std::string d;
        const std::string vertical = "V" + px(f.top + f.height);
        auto band = [&](double a, double b) {
          d += "M" + px(a) + ',' + px(f.top) + "h" + px(b - a) + vertical + "H" + px(a) + "Z";
        };
        double a = 0, b = -1;
        for (int i : idx) {
          const double x = f.xPx(c.x[i]);
          if (b >= a && x - markWidth / 2 <= b + 0.5) {
            b = x + markWidth / 2;
            continue;
          }
          if (b >= a) band(a, b);
          a = x - markWidth / 2, b = x + markWidth / 2;
        }
        band(a, b);
        out += "<path class=\"bands\" d=\"" + d + "\"/>\n";
      }
      out += "</g>\n";
    }
    return out;
  }

  /// Whether series cs has a usable value at slice i (on a log axis: positive), and an error too.
  bool ok(const ChartSeries& cs, std::size_t i) const { return usable(cs.values[i], c.log_y); }
  bool errorOk(const ChartSeries& cs, std::size_t i) const {
    return ok(cs, i) && !cs.error.empty() && std::isfinite(cs.error[i]);
  }

  /// Series s with few slices: a dot per slice with its tooltip (and error whiskers), joined by a
  /// line; `dodgeStep` px between the series at one slice.
  std::string seriesPointsSvg(std::size_t s, double dodgeStep, double radius) const {
    const ChartSeries& cs = c.series[s];
    const std::string col = seriesColour(cs, s);
    std::vector<std::vector<Point>> runs;
    std::string out;
    const double dx = (double(s) - (c.series.size() - 1) / 2.0) * dodgeStep;
    std::string whiskers, dots;
    const double cap = std::clamp(0.4 * slotPx, 2.0, 6.0);
    for (std::size_t i = 0; i < n; ++i) {
      if (!ok(cs, i)) {
        if (!runs.empty() && !runs.back().empty()) runs.emplace_back();
        continue;
      }
      if (runs.empty()) runs.emplace_back();
      const Point p{f.xPx(c.x[i]) + dx, f.yPx(cs.values[i])};
      runs.back().push_back(p);
      std::string tip = (cs.name.empty() ? "" : xmlEscaped(cs.name) + ", ") + xWord + " " +
                        std::to_string(c.x[i]) + ": " + valueText(cs.values[i]) + unit;
      if (errorOk(cs, i)) {
        const double y0 = f.yPx(cs.values[i] - cs.error[i]),
                     y1 = f.yPx(cs.values[i] + cs.error[i]);
        const std::string l = px(p.x - cap / 2), r = "h" + px(cap);
        whiskers += "M" + px(p.x) + ',' + px(y0) + "V" + px(y1) + "M" + l + ',' + px(y0) + r +
                    "M" + l + ',' + px(y1) + r;
        tip += " \xC2\xB1 " + valueText(cs.error[i]) + unit;
      }
      dots += "<circle cx=\"" + px(p.x) + "\" cy=\"" + px(p.y) + "\" r=\"" + px(radius) +
              "\"><title>" + tip + "</title></circle>\n";
    }
    for (auto& run : runs)
      if (run.size() < 2) run.clear();  // a lone point is its dot
    const std::string line = polylinePath(runs, 2);
    if (!line.empty())
      out += "<path class=\"line\" d=\"" + line + "\" fill=\"none\" stroke=\"" + col +
             "\" stroke-width=\"1.5\" stroke-opacity=\"0.7\" stroke-linejoin=\"round\"/>\n";
    if (!whiskers.empty())
      out += "<path class=\"error\" d=\"" + whiskers + "\" fill=\"none\" stroke=\"" + col +
             "\" stroke-width=\"1\"/>\n";
    out += dots;
    return out;
  }

  /// Series s with many slices: per pixel column of a run, its lowest and highest values in slice
  /// order (a spike keeps its extreme), at the column's centre; and the band from the lowest value
  /// - error to the highest value + error. y to 0.1 pixel: a few kB less per series.
  std::string seriesLinesSvg(std::size_t s) const {
    const ChartSeries& cs = c.series[s];
    const std::string col = seriesColour(cs, s);
    std::vector<std::vector<Point>> runs;
    std::string out;
    std::string band;
    std::vector<Point> upper, lower;
    auto flushBand = [&] {
      if (upper.size() == 1) {  // one column: half a pixel either side
        upper = {{upper[0].x - 0.5, upper[0].y}, {upper[0].x + 0.5, upper[0].y}};
        lower = {{lower[0].x - 0.5, lower[0].y}, {lower[0].x + 0.5, lower[0].y}};
      }
      if (!upper.empty()) {
        band += 'M';
        for (std::size_t k = 0; k < upper.size(); ++k)
          band += (k ? " " : "") + px(upper[k].x) + ',' + px(upper[k].y, 1);
        for (std::size_t k = lower.size(); k-- > 0;)
          band += ' ' + px(lower[k].x) + ',' + px(lower[k].y, 1);
        band += 'Z';
      }
      upper.clear(), lower.clear();
    };
    long column = -1, bandColumn = -1;
    std::size_t iMin = 0, iMax = 0;
    auto flushColumn = [&] {
      if (column < 0) return;
      const double x = f.left + column + 0.5;
      const std::size_t a = std::min(iMin, iMax), b = std::max(iMin, iMax);
      runs.back().push_back({x, f.yPx(cs.values[a])});
      if (cs.values[a] != cs.values[b]) runs.back().push_back({x, f.yPx(cs.values[b])});
      column = -1;
    };
    const long lastColumn = std::max(0L, static_cast<long>(std::ceil(f.width)) - 1);
    for (std::size_t i = 0; i < n; ++i) {
      if (!errorOk(cs, i)) flushBand(), bandColumn = -1;
      if (!ok(cs, i)) {
        flushColumn();
        if (!runs.empty() && !runs.back().empty()) runs.emplace_back();
        continue;
      }
      if (runs.empty()) runs.emplace_back();
      const long col =
          std::clamp(static_cast<long>(std::floor(f.xPx(c.x[i]) - f.left)), 0L, lastColumn);
      const double v = cs.values[i];
      if (col != column) {
        flushColumn();
        column = col, iMin = iMax = i;
      } else {
        if (v < cs.values[iMin]) iMin = i;
        if (v > cs.values[iMax]) iMax = i;
      }
      if (errorOk(cs, i)) {
        const double yHi = f.yPx(v + cs.error[i]), yLo = f.yPx(v - cs.error[i]);
        if (col != bandColumn) {
          upper.push_back({f.left + col + 0.5, yHi});
          lower.push_back({f.left + col + 0.5, yLo});
          bandColumn = col;
        } else {
          upper.back().y = std::min(upper.back().y, yHi);
          lower.back().y = std::max(lower.back().y, yLo);
        }
      }
    }
    flushColumn();
    flushBand();
    if (!band.empty())
      out += "<path class=\"band\" d=\"" + band + "\" fill-opacity=\"0.2\" stroke=\"none\"/>\n";
    const std::string line = polylinePath(runs, 1);
    if (!line.empty())
      out += "<path class=\"line\" d=\"" + line + "\" fill=\"none\" stroke=\"" + col +
             "\" stroke-width=\"1.25\" stroke-linejoin=\"round\" stroke-linecap=\"round\"/>\n";
    return out;
  }

  /// The threshold: a dashed line, its label at the right end above it.
  std::string thresholdSvg() const {
    std::string out;
    if (usable(c.threshold, c.log_y)) {
      const std::string y = px(f.yPx(c.threshold));
      out += "<g class=\"threshold\">\n<path d=\"M" + px(f.left) + ',' + y + "H" + px(right) +
             "\" stroke=\"#555\" stroke-width=\"1\" stroke-dasharray=\"5,4\" fill=\"none\"/>\n";
      if (!c.threshold_label.empty())
        out += "<text x=\"" + px(right - 4) + "\" y=\"" + px(f.yPx(c.threshold) - 4) +
               "\" text-anchor=\"end\" fill=\"#555\" stroke=\"#fff\" stroke-width=\"3\" "
               "paint-order=\"stroke\">" +
               xmlEscaped(c.threshold_label) + "</text>\n";
      out += "</g>\n";
    }
    return out;
  }

  /// Axes: frame lines, ticks, tick labels, axis labels.
  std::string axesSvg() const {
    std::string out;
    {
      const double bottom = f.top + f.height;
      std::string d = "M" + px(f.left) + ',' + px(f.top) + "V" + px(bottom) + "H" + px(right);
      std::string labels;
      for (std::size_t k = 0; k < f.y.ticks.size(); ++k) {
        const std::string y = px(f.yPx(f.y.ticks[k]));
        d += "M" + px(f.left - 4) + ',' + y + "h4";
        labels += "<text class=\"ytick\" x=\"" + px(f.left - 6) + "\" y=\"" + y +
                  "\" text-anchor=\"end\" dominant-baseline=\"middle\">" + f.y.labels[k] +
                  "</text>\n";
      }
      // x ticks: integer multiples of a 1-2-5 step of slice numbers, inside the padded range.
      const double span = std::max(1.0, double(c.x.back()) - c.x.front());
      const double step = std::max(1.0, niceStep(span / std::max(2.0, std::floor(f.width / 70))));
      const double k0 = std::ceil(f.x0 / step), k1 = std::floor(f.x1 / step);
      for (double k = k0; k <= k1 && k - k0 <= 1000; ++k) {
        const double v = k * step;
        const std::string x = px(f.xPx(v));
        d += "M" + x + ',' + px(bottom) + "v4";
        labels += "<text class=\"xtick\" x=\"" + x + "\" y=\"" + px(bottom + 15) +
                  "\" text-anchor=\"middle\">" + fixedText(v, 0) + "</text>\n";
      }
      out += "<g class=\"axes\" fill=\"#333\">\n<path d=\"" + d +
             "\" stroke=\"#333\" stroke-width=\"1\" fill=\"none\"/>\n" + labels;
      if (!c.x_label.empty())
        out += "<text class=\"x-label\" x=\"" + px(f.left + f.width / 2) + "\" y=\"" +
               px(bottom + 31) + "\" text-anchor=\"middle\">" + xWord + "</text>\n";
      if (!c.y_label.empty())
        out += "<text class=\"y-label\" transform=\"translate(14," + px(f.top + f.height / 2) +
               ") rotate(-90)\" text-anchor=\"middle\">" + xmlEscaped(c.y_label) + "</text>\n";
      out += "</g>\n";
    }
    return out;
  }
};

}  // namespace

std::string svgSliceChart(const SliceChart& c, int width, int height) {
  validate(c, width, height);
  const std::string w = std::to_string(width);
  std::string out;
  out.reserve(8192);
  auto open = [&](int h) {
    out += "<svg xmlns=\"http://www.w3.org/2000/svg\"";
    if (!c.id.empty()) out += " id=\"" + xmlEscaped(c.id) + "\"";
    out += " class=\"xsect-chart\" width=\"" + w + "\" height=\"" + std::to_string(h) +
           "\" viewBox=\"0 0 " + w + " " + std::to_string(h) +
           "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    if (!c.title.empty())
      out += "<text class=\"title\" x=\"8\" y=\"15\" font-size=\"13\" font-weight=\"bold\">" +
             xmlEscaped(c.title) + "</text>\n";
  };

  // Layout, top down: title, legend rows, plot, x tick labels and label.
  const double titleHeight = c.title.empty() ? 4 : 22;
  std::vector<LegendEntry> legend;
  {
    double x = 8;
    int row = 0;
    auto place = [&](bool isMark, std::size_t i, const std::string& name) {
      if (name.empty()) return;
      const double entryWidth = 18 + textWidth(name) + 14;
      if (x > 8 && x + entryWidth > width - 8) ++row, x = 8;
      legend.push_back({isMark, i, x, row});
      x += entryWidth;
    };
    for (std::size_t i = 0; i < c.series.size(); ++i) place(false, i, c.series[i].name);
    for (std::size_t i = 0; i < c.marks.size(); ++i) place(true, i, c.marks[i].name);
  }
  const int legendRows = legend.empty() ? 0 : legend.back().row + 1;
  const double bottomMargin = c.x_label.empty() ? 24 : 38;
  const double plotBottom = height - bottomMargin;
  const double top = std::min(titleHeight + 16.0 * legendRows + 8, plotBottom - 40);
  const double plotHeight = plotBottom - top;

  Frame f;
  f.top = top;
  f.height = plotHeight;
  if (c.x.empty() || !yAxisOf(c, std::clamp(static_cast<int>(plotHeight / 36), 2, 8), &f.y)) {
    open(48);
    out += "<text class=\"no-data\" x=\"" + px(width / 2.0) +
           "\" y=\"38\" text-anchor=\"middle\" fill=\"#777\">no data</text>\n</svg>\n";
    return out;
  }

  double labelWidth = 0;
  for (const std::string& l : f.y.labels) labelWidth = std::max(labelWidth, textWidth(l));
  // The frame on pixel centres (x.5): crisp 1-pixel axes, and pixel columns centred on integers.
  f.left = std::ceil(4 + (c.y_label.empty() ? 0 : 16) + labelWidth + 8) + 0.5;
  f.width = width - f.left - 16;

  // x: slice numbers, padded by half the smallest spacing so that end points are not on the frame.
  const std::size_t n = c.x.size();
  double spacing = 1;
  for (std::size_t i = 1; i < n; ++i)
    spacing = i == 1 ? double(c.x[1]) - c.x[0] : std::min(spacing, double(c.x[i]) - c.x[i - 1]);
  f.x0 = c.x.front() - spacing / 2;
  f.x1 = c.x.back() + spacing / 2;
  const ChartContext k{c,
                       f,
                       n,
                       spacing / (f.x1 - f.x0) * f.width,
                       n <= static_cast<std::size_t>(SliceChart::kMaxPointSlices),
                       xmlEscaped(c.x_label),
                       c.y_unit.empty() ? "" : " " + xmlEscaped(c.y_unit),
                       f.left + f.width};

  open(height);
  if (!legend.empty()) out += k.legendSvg(legend, titleHeight);
  out += k.gridSvg();
  out += k.marksSvg();
  // Series.
  const double dodgeStep =
      c.series.size() > 1 ? std::min(4.0, 0.5 * k.slotPx / double(c.series.size())) : 0.0;
  const double radius = std::clamp(0.3 * k.slotPx, 1.5, 2.5);
  for (std::size_t s = 0; s < c.series.size(); ++s) {
    out += "<g class=\"series\" fill=\"" + seriesColour(c.series[s], s) + "\">\n";
    out += k.points ? k.seriesPointsSvg(s, dodgeStep, radius) : k.seriesLinesSvg(s);
    out += "</g>\n";
  }
  out += k.thresholdSvg();
  out += k.axesSvg();
  out += "</svg>\n";
  return out;
}


}  // namespace xsect
