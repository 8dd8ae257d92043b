// Per-slice SVG charts (report/charts/svg_chart.h): the output is well-formed XML; a small chart has one
// tooltip per finite value; a 4000-frame chart stays small and keeps its spike and its dip; text
// is escaped; gaps break the line; y ticks are 1-2-5 steps covering the data (signed, constant,
// logarithmic); marks and the threshold are drawn; empty inputs give "no data"; invalid inputs
// throw naming the offender; the output is deterministic and locale-independent.
#include <gtest/gtest.h>

#include <algorithm>
#include <clocale>
#include <cmath>
#include <iostream>
#include <limits>
#include <locale>
#include <pugixml.hpp>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "report/charts/svg_chart.h"

namespace xsect {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

/// `svg` parsed; fails the test when it is not well-formed XML with one <svg> root.
pugi::xml_document parsed(const std::string& svg) {
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_string(svg.c_str());
  EXPECT_TRUE(r) << r.description() << " at offset " << r.offset;
  EXPECT_STREQ(doc.document_element().name(), "svg");
  return doc;
}

std::size_t count(const pugi::xml_document& doc, const char* xpath) {
  return doc.select_nodes(xpath).size();
}

/// Slices 0 .. n-1.
std::vector<int> iota(int n) {
  std::vector<int> x(n);
  for (int i = 0; i < n; ++i) x[i] = i;
  return x;
}

/// The subpaths of a line path ("M x,y x,y ...", a lone point as "M x,y h0"), as points.
std::vector<std::vector<std::pair<double, double>>> subpaths(const std::string& d) {
  std::vector<std::vector<std::pair<double, double>>> out;
  std::string s = d;
  for (char& ch : s)
    if (ch == ',') ch = ' ';
  std::size_t i = 0;
  while (i < s.size()) {
    if (s[i] == 'M') {
      out.emplace_back();
      ++i;
    } else if (s.compare(i, 2, "h0") == 0) {
      i += 2;
    } else if (s[i] == ' ') {
      ++i;
    } else {
      std::size_t used = 0;
      const double x = std::stod(s.substr(i), &used);
      i += used;
      while (s[i] == ' ') ++i;
      const double y = std::stod(s.substr(i), &used);
      i += used;
      out.back().emplace_back(x, y);
    }
  }
  return out;
}

/// The pixel row of value `v` on the chart's linear y axis, from its tick labels and positions.
double yPixelOf(const pugi::xml_document& doc, double v) {
  const auto ticks = doc.select_nodes("//text[@class='ytick']");
  EXPECT_GE(ticks.size(), 2u);
  const double v0 = std::stod(ticks.first().node().text().get());
  const double y0 = ticks.first().node().attribute("y").as_double();
  const double v1 = std::stod((ticks.end() - 1)->node().text().get());
  const double y1 = (ticks.end() - 1)->node().attribute("y").as_double();
  return y0 + (v - v0) / (v1 - v0) * (y1 - y0);
}

std::vector<double> yTickValues(const std::string& svg) {
  const pugi::xml_document doc = parsed(svg);
  std::vector<double> v;
  for (const auto& t : doc.select_nodes("//text[@class='ytick']"))
    v.push_back(std::stod(t.node().text().get()));
  return v;
}

/// Whether `step` is 1, 2 or 5 times a power of ten.
bool isNiceStep(double step) {
  const double e = std::floor(std::log10(step));
  const double m = step / std::pow(10.0, e);
  for (double nice : {1.0, 2.0, 5.0, 10.0})
    if (std::fabs(m - nice) < 1e-6) return true;
  return false;
}

/// Decimal comma and grouped thousands, as a German locale writes numbers through iostreams.
struct CommaNumbers : std::numpunct<char> {
  char do_decimal_point() const override { return ','; }
  char do_thousands_sep() const override { return '.'; }
  std::string do_grouping() const override { return "\3"; }
};

/// A chart of one series with `values` over slices 0 .. size-1.
SliceChart oneSeries(std::vector<double> values) {
  SliceChart c;
  c.id = "c";
  c.title = "values";
  c.y_label = "value (mm)";
  c.y_unit = "mm";
  c.x = iota(static_cast<int>(values.size()));
  c.series.push_back({"v", "#1f77b4", std::move(values), {}});
  return c;
}

/// Conformity before/after over `n` slices with errors, flagged slices and a threshold.
SliceChart conformityChart(int n) {
  SliceChart c;
  c.id = "conformity";
  c.title = "Disagreement per slice";
  c.y_label = "disagreement (mm)";
  c.y_unit = "mm";
  c.x = iota(n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.1, 1.0);
  ChartSeries before{"before", "#d62728", {}, {}}, after{"after", "#1f77b4", {}, {}};
  for (int i = 0; i < n; ++i) {
    before.values.push_back(u(rng));
    after.values.push_back(0.5 * u(rng));
    after.error.push_back(0.1 * u(rng));
  }
  c.series = {before, after};
  ChartMark flagged{"flagged", "#ff7f0e", {}};
  for (int i = 0; i < n; i += std::max(1, n / 100)) flagged.x_index.push_back(i);
  c.marks = {flagged};
  c.threshold = 0.8;
  c.threshold_label = "flag threshold 0.8 mm";
  return c;
}

TEST(SvgChart, WellFormedAcrossShapes) {
  SliceChart logChart = oneSeries({0.01, 0.5, 3, 40, kNaN, -1, 0});
  logChart.log_y = true;
  SliceChart empty;
  empty.title = "nothing";
  for (const SliceChart& c : {conformityChart(3), conformityChart(150), conformityChart(151),
                              conformityChart(4000), logChart, oneSeries({}), empty}) {
    const std::string svg = svgSliceChart(c);
    const pugi::xml_document doc = parsed(svg);
    EXPECT_EQ(svg.rfind("<svg", 0), 0u) << "no XML declaration, the <svg> element first";
    EXPECT_STREQ(doc.document_element().attribute("width").value(), "760");
  }
}

TEST(SvgChart, SmallChartHasOneTooltipPerFiniteValue) {
  SliceChart c = conformityChart(12);
  c.series[0].values[3] = kNaN;
  c.series[1].values[5] = std::numeric_limits<double>::infinity();
  c.series[1].values[6] = kNaN;
  c.series.push_back({"", "", std::vector<double>(12, kNaN), {}});  // nothing to point at
  c.series[2].values[11] = 0.25;
  const pugi::xml_document doc = parsed(svgSliceChart(c));
  EXPECT_EQ(count(doc, "//g[@class='series']/circle/title"), 11u + 10u + 1u);
  EXPECT_EQ(count(doc, "//g[@class='series']/circle"), 22u);
  // Wording: series, slice number, value with unit, ± error.
  c.series[1].values[2] = 0.31;
  c.series[1].error[2] = 0.05;
  const std::string svg = svgSliceChart(c);
  EXPECT_NE(svg.find("<title>after, slice 2: 0.31 mm \xC2\xB1 0.05 mm</title>"), std::string::npos);
  EXPECT_NE(svg.find("<title>slice 11: 0.25 mm</title>"), std::string::npos);
  // The mark bands have their own tooltips: one per flagged slice.
  EXPECT_EQ(count(parsed(svg), "//g[@class='mark']/rect/title"), c.marks[0].x_index.size());
}

TEST(SvgChart, FourThousandFramesStaySmallAndKeepSpikes) {
  SliceChart c = conformityChart(4000);
  c.series[0].values[2345] = 9.0;   // a spike: the maximum
  c.series[0].values[1234] = -4.0;  // a dip: the minimum
  ChartMark dropped{"dropped", "", {}};
  for (int i = 3000; i < 3050; ++i) dropped.x_index.push_back(i);
  c.marks.push_back(dropped);
  const std::string svg = svgSliceChart(c);
  std::cout << "[ info     ] 4000-frame chart (2 series, a band, 150 marks, threshold): "
            << svg.size() << " bytes\n";
  EXPECT_LT(svg.size(), 60000u);
  const pugi::xml_document doc = parsed(svg);
  EXPECT_EQ(count(doc, "//circle"), 0u) << "no points above the point limit";
  EXPECT_EQ(count(doc, "//g[@class='series']//title"), 0u) << "no per-point tooltips";
  EXPECT_EQ(count(doc, "//path[@class='band']"), 1u);

  const auto lines = doc.select_nodes("//g[@class='series']/path[@class='line']");
  ASSERT_EQ(lines.size(), 2u);
  const auto runs = subpaths(lines.first().node().attribute("d").value());
  ASSERT_EQ(runs.size(), 1u);
  // At most 2 points per pixel column of the 760-pixel-wide chart.
  EXPECT_LE(runs[0].size(), 2u * 760u);
  EXPECT_GT(runs[0].size(), 600u) << "the line still follows the data";
  double top = 1e9, bottom = -1e9;
  for (const auto& p : runs[0]) top = std::min(top, p.second), bottom = std::max(bottom, p.second);
  // The line's y is written to 0.1 pixel.
  EXPECT_NEAR(top, yPixelOf(doc, 9.0), 0.06);
  EXPECT_NEAR(bottom, yPixelOf(doc, -4.0), 0.06);

  // Bands of marked frames: one per scattered flagged frame; the 50 consecutive dropped frames
  // merge into one.
  const auto bands = doc.select_nodes("//g[@class='mark']/path[@class='bands']");
  ASSERT_EQ(bands.size(), 2u);
  const std::string flaggedBands = bands.first().node().attribute("d").value();
  const std::string droppedBands = (bands.end() - 1)->node().attribute("d").value();
  EXPECT_EQ(std::count(flaggedBands.begin(), flaggedBands.end(), 'M'), 100);
  EXPECT_EQ(std::count(droppedBands.begin(), droppedBands.end(), 'M'), 1);
  EXPECT_EQ(count(doc, "//g[@class='mark']//title"), 0u);
}

TEST(SvgChart, TextIsEscaped) {
  const std::string nasty = "a<b>&c\"d'e";
  SliceChart c = oneSeries({1, 2, 3});
  c.id = "id\"x";
  c.title = nasty;
  c.x_label = "<frame>";
  c.y_label = nasty;
  c.series[0].name = nasty;
  c.series[0].colour = "#123\"/><script>";
  c.marks.push_back({nasty, "", {1}});
  c.threshold = 2.5;
  c.threshold_label = nasty + "\x01";  // a control character, invalid in XML, is dropped
  const std::string svg = svgSliceChart(c);
  EXPECT_EQ(svg.find("<b>"), std::string::npos);
  EXPECT_EQ(svg.find("<script>"), std::string::npos);
  EXPECT_NE(svg.find("a&lt;b&gt;&amp;c&quot;d&apos;e"), std::string::npos);
  const pugi::xml_document doc = parsed(svg);
  EXPECT_STREQ(doc.document_element().attribute("id").value(), "id\"x");
  EXPECT_EQ(std::string(doc.select_node("//text[@class='title']").node().text().get()), nasty);
  EXPECT_EQ(std::string(doc.select_node("//g[@class='threshold']/text").node().text().get()),
            nasty);
  EXPECT_NE(svg.find("<title>a&lt;b&gt;&amp;c&quot;d&apos;e, &lt;frame&gt; 1: 2 mm</title>"),
            std::string::npos);
}

TEST(SvgChart, GapsBreakTheLine) {
  // Points: 0-1 a run, 2 a gap, 3-4 a run, 5 a gap, 6 alone (its dot only).
  const pugi::xml_document small = parsed(svgSliceChart(oneSeries({1, 2, kNaN, 3, 4, kNaN, 5})));
  const auto runs =
      subpaths(small.select_node("//path[@class='line']").node().attribute("d").value());
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].size(), 2u);
  EXPECT_EQ(runs[1].size(), 2u);
  EXPECT_LT(runs[0].back().first, runs[1].front().first);
  EXPECT_EQ(count(small, "//g[@class='series']/circle"), 5u);

  // A downsampled line breaks too, and a lone value between gaps stays visible as a dot.
  std::vector<double> v(1000);
  for (int i = 0; i < 1000; ++i) v[i] = std::sin(i * 0.01);
  for (int i = 400; i < 450; ++i) v[i] = kNaN;
  v[700] = v[702] = kNaN;
  const pugi::xml_document dense = parsed(svgSliceChart(oneSeries(v)));
  const std::string d = dense.select_node("//path[@class='line']").node().attribute("d").value();
  const auto denseRuns = subpaths(d);
  ASSERT_EQ(denseRuns.size(), 4u);
  EXPECT_EQ(denseRuns[2].size(), 1u) << "frame 701 alone";
  EXPECT_NE(d.find("h0"), std::string::npos);
}

TEST(SvgChart, TicksAreNiceAndCoverTheData) {
  struct Case {
    std::vector<double> values;
    double lo, hi;  // the range the ticks must cover
  };
  const std::vector<Case> cases = {
      {{0.13, 0.87, 0.5}, 0.13, 0.87},
      {{-3.2, 7.9, 0.0}, -3.2, 7.9},
      {{1234, 5678, 3000}, 1234, 5678},
      {{0.0012, 0.0019}, 0.0012, 0.0019},
      {{-0.4, -0.05, -0.2}, -0.4, -0.05},
      {{5, 5, 5}, 0, 5},  // constant: from 0
      {{0, 0}, 0, 1},
      {{-2, -2}, -2, 0},
      {{100.2, 100.9, 100.5}, 100.2, 100.9},  // far from 0: not stretched to it
  };
  for (const Case& k : cases) {
    const std::vector<double> t = yTickValues(svgSliceChart(oneSeries(k.values)));
    SCOPED_TRACE(::testing::PrintToString(k.values));
    ASSERT_GE(t.size(), 3u);
    EXPECT_LE(t.size(), 10u);
    const double step = t[1] - t[0];
    EXPECT_TRUE(isNiceStep(step)) << step;
    for (std::size_t i = 1; i < t.size(); ++i) {
      EXPECT_NEAR(t[i] - t[i - 1], step, 1e-9 * step * 1e3);
      EXPECT_NEAR(std::remainder(t[i], step), 0.0, 1e-6 * step) << "ticks on multiples of the step";
    }
    EXPECT_LE(t.front(), k.lo);
    EXPECT_GE(t.back(), k.hi);
    EXPECT_LE(t.back() - t.front(), 2.5 * (k.hi - k.lo)) << "not needlessly wide";
  }
  // 0 is a tick when values are signed; the far-from-0 case does not include it.
  const std::vector<double> s = yTickValues(svgSliceChart(oneSeries({-3.2, 7.9})));
  EXPECT_NE(std::find(s.begin(), s.end(), 0.0), s.end());
  EXPECT_GT(yTickValues(svgSliceChart(oneSeries({100.2, 100.9})))[0], 99.0);
  // Errors and the threshold widen the range.
  SliceChart c = oneSeries({1, 2, 3});
  c.series[0].error = {0.5, kNaN, 4};
  c.threshold = -2;
  const std::vector<double> w = yTickValues(svgSliceChart(c));
  EXPECT_LE(w.front(), -2);
  EXPECT_GE(w.back(), 7);

  // Log axis: decades covering the positive values; with at most two decades, 2 and 5 between.
  SliceChart lg = oneSeries({0.003, 0.2, 40, 0, -1});
  lg.log_y = true;
  std::vector<double> d = yTickValues(svgSliceChart(lg));
  std::sort(d.begin(), d.end());
  EXPECT_DOUBLE_EQ(d.front(), 0.001);
  EXPECT_DOUBLE_EQ(d.back(), 100);
  for (double v : d) EXPECT_NEAR(std::log10(v), std::round(std::log10(v)), 1e-9);
  lg.series[0].values = {0.3, 2, 7, kNaN, 5};
  d = yTickValues(svgSliceChart(lg));
  EXPECT_EQ(d, (std::vector<double>{0.1, 0.2, 0.5, 1, 2, 5, 10}));
}

TEST(SvgChart, MarksAndThresholdAreDrawn) {
  SliceChart c = oneSeries({1, 2, 3, 4, 5});
  c.marks.push_back({"flagged", "#ff7f0e", {3, 1, 3}});
  c.marks.push_back({"dropped", "", {4}});
  c.threshold = 3.5;
  c.threshold_label = "threshold";
  const pugi::xml_document doc = parsed(svgSliceChart(c));
  const auto marks = doc.select_nodes("//g[@class='mark']");
  ASSERT_EQ(marks.size(), 2u);
  EXPECT_EQ(count(doc, "//g[@class='mark'][1]/rect"), 2u) << "duplicates drawn once";
  EXPECT_STREQ(marks.first().node().attribute("fill").value(), "#ff7f0e");
  EXPECT_EQ(count(doc, "//g[@class='legend']/text"), 3u) << "the series and both marks";
  const pugi::xml_node dashed = doc.select_node("//g[@class='threshold']/path").node();
  ASSERT_TRUE(dashed);
  EXPECT_TRUE(dashed.attribute("stroke-dasharray"));
  // The dashed line is at 3.5 on the axis: "M left,y H right".
  const std::string d = dashed.attribute("d").value();
  EXPECT_NEAR(std::stod(d.substr(d.find(',') + 1)), yPixelOf(doc, 3.5), 0.01);
}

TEST(SvgChart, NoDataIsASmallSvgNotAnError) {
  SliceChart none;
  none.title = "Pose corrections";
  SliceChart gaps = oneSeries({kNaN, kNaN, std::numeric_limits<double>::infinity()});
  SliceChart noSeries = oneSeries({1, 2});
  noSeries.series.clear();
  SliceChart nonPositiveLog = oneSeries({0, -1});
  nonPositiveLog.log_y = true;
  for (const SliceChart& c : {none, gaps, noSeries, nonPositiveLog}) {
    const std::string svg = svgSliceChart(c);
    const pugi::xml_document doc = parsed(svg);
    EXPECT_STREQ(doc.select_node("//text[@class='no-data']").node().text().get(), "no data");
    EXPECT_STREQ(doc.document_element().attribute("height").value(), "48");
    EXPECT_LT(svg.size(), 600u);
  }
}

TEST(SvgChart, InvalidInputThrowsNamingTheOffender) {
  auto message = [](const SliceChart& c, int w = 760, int h = 240) -> std::string {
    try {
      svgSliceChart(c, w, h);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "(no exception)";
  };
  SliceChart c = oneSeries({1, 2, 3});
  c.series.push_back({"shift", "", {1, 2}, {}});
  EXPECT_NE(message(c).find("series \"shift\" has 2 values for 3 slices"), std::string::npos)
      << message(c);
  c.series[1].values.push_back(3);
  c.series[1].error = {0.1};
  EXPECT_NE(message(c).find("series \"shift\" has 1 errors"), std::string::npos) << message(c);
  c.series[1].error = {0.1, -0.2, 0.1};
  EXPECT_NE(message(c).find("\"shift\" has a negative error at slice 1"), std::string::npos);
  c.series[1].error.clear();
  EXPECT_EQ(message(c), "(no exception)");
  c.marks.push_back({"dropped", "", {3}});
  EXPECT_NE(message(c).find("mark \"dropped\" has index 3"), std::string::npos) << message(c);
  c.marks.clear();
  c.x = {0, 2, 2};
  EXPECT_NE(message(c).find("not strictly ascending"), std::string::npos) << message(c);
  c.x = {0, 1, 2};
  EXPECT_NE(message(c, 100, 240).find("size 100 x 240"), std::string::npos);
  // Empty slices with values is a size mismatch, not "no data".
  c.x.clear();
  EXPECT_NE(message(c).find("has 3 values for 0 slices"), std::string::npos);
}

TEST(SvgChart, DeterministicAndLocaleIndependent) {
  for (int n : {5, 4000}) {
    SliceChart c = conformityChart(n);
    c.series[1].values[1] = -1234.5678;
    const std::string a = svgSliceChart(c), b = svgSliceChart(c);
    EXPECT_EQ(a, b);
    // A global C++ locale with a decimal comma (iostreams), and a C locale with one (printf)
    // when the machine has it.
    const std::locale oldLocale =
        std::locale::global(std::locale(std::locale::classic(), new CommaNumbers));
    const std::string oldC = std::setlocale(LC_ALL, nullptr);
    for (const char* name : {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "de_DE"})
      if (std::setlocale(LC_NUMERIC, name)) break;
    const std::string d = svgSliceChart(c);
    std::setlocale(LC_ALL, oldC.c_str());
    std::locale::global(oldLocale);
    EXPECT_EQ(a, d);
  }
  // Distinct inputs give distinct output (the chart is not a constant).
  EXPECT_NE(svgSliceChart(oneSeries({1, 2})), svgSliceChart(oneSeries({1, 3})));
}

TEST(SvgChart, SparseSliceNumbersAndOneSlice) {
  // Slice numbers with gaps: x positions are linear in the numbers.
  SliceChart c = oneSeries({1, 2, 3});
  c.x = {0, 10, 40};
  const pugi::xml_document doc = parsed(svgSliceChart(c));
  std::vector<double> cx;
  for (const auto& n : doc.select_nodes("//g[@class='series']/circle"))
    cx.push_back(n.node().attribute("cx").as_double());
  ASSERT_EQ(cx.size(), 3u);
  EXPECT_NEAR((cx[2] - cx[1]) / (cx[1] - cx[0]), 3.0, 1e-3);
  // One slice, one value.
  const pugi::xml_document one = parsed(svgSliceChart(oneSeries({0.7})));
  EXPECT_EQ(count(one, "//g[@class='series']/circle/title"), 1u);
  EXPECT_GE(count(one, "//text[@class='xtick']"), 1u);
}

}  // namespace
}  // namespace xsect
