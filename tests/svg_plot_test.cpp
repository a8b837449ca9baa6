// The SVG plot writer of `radiosity study`: well-formed standalone SVG, escaped text, ticks,
// skipped points, legends and byte-for-byte repeatable output.
#include "jobs/study/svg_plot.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace radiosity::jobs {
namespace {

/// Empty when `xml` is well-formed as far as this writer's output goes (one root element,
/// balanced tags, quoted attributes, known entities, no stray '<' or '&'); else the first fault.
std::string xmlFault(const std::string& xml) {
  std::vector<std::string> open;
  bool rootSeen = false;
  size_t i = 0;
  const auto isNameChar = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == ':' ||
           c == '.';
  };
  const auto entityOk = [&](size_t at) {  // xml[at] == '&'
    for (const char* name : {"&amp;", "&lt;", "&gt;", "&quot;", "&apos;"}) {
      if (xml.compare(at, std::char_traits<char>::length(name), name) == 0) return true;
    }
    return false;
  };
  while (i < xml.size()) {
    if (xml[i] == '&' && !entityOk(i)) return "bad entity at " + std::to_string(i);
    if (xml[i] == '>') return "stray '>' at " + std::to_string(i);
    if (xml[i] != '<') {
      if (open.empty() && !std::isspace(static_cast<unsigned char>(xml[i]))) {
        return "text outside the root at " + std::to_string(i);
      }
      ++i;
      continue;
    }
    if (xml.compare(i, 2, "<?") == 0) {  // a declaration, only before the root
      if (rootSeen || !open.empty()) return "late <? at " + std::to_string(i);
      const size_t end = xml.find("?>", i);
      if (end == std::string::npos) return "unterminated <?";
      i = end + 2;
      continue;
    }
    const bool closing = xml.compare(i, 2, "</") == 0;
    size_t j = i + (closing ? 2 : 1);
    const size_t nameStart = j;
    while (j < xml.size() && isNameChar(xml[j])) ++j;
    const std::string name = xml.substr(nameStart, j - nameStart);
    if (name.empty()) return "tag without a name at " + std::to_string(i);
    if (closing) {
      if (open.empty() || open.back() != name) return "unmatched </" + name + ">";
      open.pop_back();
      if (j >= xml.size() || xml[j] != '>') return "bad </" + name;
      i = j + 1;
      continue;
    }
    // Attributes: name="value", no '<' in the value, each name once.
    std::vector<std::string> attributes;
    while (true) {
      while (j < xml.size() && std::isspace(static_cast<unsigned char>(xml[j]))) ++j;
      if (j >= xml.size()) return "unterminated <" + name;
      if (xml[j] == '>' || xml.compare(j, 2, "/>") == 0) break;
      const size_t attributeStart = j;
      while (j < xml.size() && isNameChar(xml[j])) ++j;
      const std::string attribute = xml.substr(attributeStart, j - attributeStart);
      if (attribute.empty()) return "bad attribute in <" + name;
      for (const auto& seen : attributes) {
        if (seen == attribute) return "repeated attribute " + attribute;
      }
      attributes.push_back(attribute);
      if (xml.compare(j, 2, "=\"") != 0) return "unquoted attribute " + attribute;
      const size_t end = xml.find('"', j + 2);
      if (end == std::string::npos) return "unterminated value of " + attribute;
      for (size_t k = j + 2; k < end; ++k) {
        if (xml[k] == '<') return "'<' in the value of " + attribute;
        if (xml[k] == '&' && !entityOk(k)) return "bad entity in the value of " + attribute;
      }
      j = end + 1;
    }
    if (open.empty() && rootSeen) return "second root <" + name + ">";
    rootSeen = true;
    if (xml[j] == '>') {
      open.push_back(name);
      i = j + 1;
    } else {
      i = j + 2;
    }
  }
  if (!open.empty()) return "unclosed <" + open.back() + ">";
  return rootSeen ? "" : "no root element";
}

size_t occurrences(const std::string& text, const std::string& part) {
  size_t count = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) {
    ++count;
  }
  return count;
}

/// Error against time for two estimators, one dashed: data spanning 1e-4 to 0.1 on both axes.
PlotPanel convergencePanel() {
  PlotPanel panel;
  panel.title = "Cornell box: error against run time";
  panel.xLabel = "wall time (s)";
  panel.yLabel = "relative L2 error";
  panel.series.push_back({"hemisphere", {1e-4, 1e-3, 1e-2, 0.1}, {0.1, 0.03, 0.01, 1e-3}});
  panel.series.push_back({"mis", {2e-4, 2e-3, 2e-2}, {0.05, 5e-3, 1e-4}, true});
  return panel;
}

PlotPanel iterationPanel() {
  PlotPanel panel;
  panel.title = "error and residual against iteration";
  panel.xLabel = "iteration";
  panel.yLabel = "norm";
  panel.logX = false;
  panel.series.push_back({"residual", {0, 1, 2, 3, 4, 5}, {1, 0.1, 0.01, 1e-3, 1e-4, 1e-5}});
  panel.series.push_back({"error", {0, 1, 2, 3, 4, 5}, {0.5, 0.06, 7e-3, 8e-4, 2e-4, 1e-4}});
  return panel;
}

TEST(XmlFault, CatchesWhatItShould) {  // the checker below must not pass anything
  EXPECT_EQ(xmlFault("<a x=\"1\"><b/>t &amp; u</a>"), "");
  EXPECT_NE(xmlFault("<a><b></a></b>"), "");
  EXPECT_NE(xmlFault("<a x=1/>"), "");
  EXPECT_NE(xmlFault("<a>x & y</a>"), "");
  EXPECT_NE(xmlFault("<a>x < y</a>"), "");
  EXPECT_NE(xmlFault("<a/><b/>"), "");
  EXPECT_NE(xmlFault("<a>"), "");
}

TEST(SvgPlot, IsWellFormedStandaloneSvg) {
  const std::string svg = svgPlot({convergencePanel(), iterationPanel()});
  EXPECT_EQ(xmlFault(svg), "");
  const size_t root = svg.find("<svg");
  ASSERT_NE(root, std::string::npos);
  EXPECT_TRUE(root == 0 || svg.compare(0, 5, "<?xml") == 0);
  EXPECT_EQ(svg.find('<'), svg.compare(0, 5, "<?xml") == 0 ? 0 : root);
  EXPECT_NE(svg.find("xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
  EXPECT_NE(svg.find("width=\"1120\" height=\"420\" viewBox=\"0 0 1120 420\""), std::string::npos);
}

TEST(SvgPlot, XmllintAcceptsIt) {
  if (!std::filesystem::exists("/usr/bin/xmllint")) GTEST_SKIP() << "no /usr/bin/xmllint";
  PlotPanel panel = convergencePanel();
  panel.title = "\"quoted\" & 'apostrophes' <tag> µs";
  panel.series[0].label = "a<b&c";
  const auto path = std::filesystem::temp_directory_path() /
                    ("svg_plot_test_" +
                     std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".svg");
  std::ofstream(path) << svgPlot({panel, iterationPanel()});
  const int status = std::system(("/usr/bin/xmllint --noout " + path.string()).c_str());
  std::filesystem::remove(path);
  EXPECT_EQ(status, 0);
}

TEST(SvgPlot, EscapesAllText) {
  PlotPanel panel = convergencePanel();
  panel.series[0].label = "a<b&c";
  panel.title = "say \"hi\" 'x' > y";
  panel.xLabel = "t\x01(s)";  // a control character: not allowed in XML even escaped
  const std::string svg = svgPlot({panel});
  EXPECT_EQ(xmlFault(svg), "");
  EXPECT_NE(svg.find(">a&lt;b&amp;c</text>"), std::string::npos);
  EXPECT_EQ(svg.find("a<b&c"), std::string::npos);
  EXPECT_NE(svg.find("say &quot;hi&quot; &apos;x&apos; &gt; y"), std::string::npos);
  EXPECT_NE(svg.find(">t (s)</text>"), std::string::npos);
  EXPECT_NE(svg.find(">mis</text>"), std::string::npos);
}

TEST(SvgPlot, LogAxisHasALabelAtEachDecade) {
  const std::string svg = svgPlot({convergencePanel()});
  for (const char* label : {">1e-4<", ">1e-3<", ">0.01<", ">0.1<"}) {
    EXPECT_EQ(occurrences(svg, label), 2u) << label;  // on both axes
  }
  EXPECT_EQ(svg.find(">1e-5<"), std::string::npos);
  EXPECT_EQ(svg.find(">1<"), std::string::npos);
}

TEST(AxisTicks, LogTicksCoverWholeDecades) {
  EXPECT_EQ(axisTicks(2e-4, 0.05, true), (std::vector<double>{1e-4, 1e-3, 1e-2, 1e-1}));
  EXPECT_EQ(axisTicks(1e-4, 0.1, true), (std::vector<double>{1e-4, 1e-3, 1e-2, 1e-1}));
  EXPECT_EQ(axisTicks(3, 5, true), (std::vector<double>{1, 10}));  // at least one decade
  EXPECT_EQ(axisTicks(100, 100, true), (std::vector<double>{100, 1000}));
  EXPECT_THROW(axisTicks(0, 1, true), std::invalid_argument);
  EXPECT_THROW(axisTicks(2, 1, false), std::invalid_argument);
  EXPECT_THROW(axisTicks(0, std::numeric_limits<double>::infinity(), false), std::invalid_argument);
}

TEST(AxisTicks, LinearTicksAreFourToEightRoundNumbersCoveringTheData) {
  std::vector<std::pair<double, double>> ranges = {
      {0, 1}, {0, 200}, {0.3, 0.7}, {-3, 17}, {0, 9999}, {1e-6, 3e-6}, {-0.5, 0.5}, {5, 5}, {0, 0}};
  for (double lo = -7.3; lo < 5; lo += 1.7) {
    for (double span = 1e-3; span < 1e5; span *= 1.37) ranges.push_back({lo, lo + span});
  }
  for (const auto& [lo, hi] : ranges) {
    const std::vector<double> ticks = axisTicks(lo, hi, false);
    SCOPED_TRACE(std::to_string(lo) + ".." + std::to_string(hi));
    ASSERT_GE(ticks.size(), 4u);
    ASSERT_LE(ticks.size(), 8u);
    const double step = ticks[1] - ticks[0];
    // Ends on the data to within rounding: 0.3 may be 3 × 0.1 = 0.30000000000000004.
    EXPECT_LE(ticks.front(), lo + 1e-9 * step);
    EXPECT_GE(ticks.back(), hi - 1e-9 * step);
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 ||
                std::abs(mantissa - 5) < 1e-6)
        << step;
  }
  const std::vector<double> unit = axisTicks(0, 1, false);  // 0, 0.2, ..., 1
  ASSERT_EQ(unit.size(), 6u);
  EXPECT_EQ(unit.front(), 0);
  EXPECT_EQ(unit.back(), 1);
}

TEST(FormatTick, IsCompact) {
  EXPECT_EQ(formatTick(1e-3), "1e-3");
  EXPECT_EQ(formatTick(0.01), "0.01");
  EXPECT_EQ(formatTick(0.1), "0.1");
  EXPECT_EQ(formatTick(10), "10");
  EXPECT_EQ(formatTick(1000), "1000");
  EXPECT_EQ(formatTick(1e4), "1e4");
  EXPECT_EQ(formatTick(2.5e-7), "2.5e-7");
  EXPECT_EQ(formatTick(-1.5e6), "-1.5e6");
  EXPECT_EQ(formatTick(0), "0");
  EXPECT_EQ(formatTick(-0.0), "0");
  EXPECT_EQ(formatTick(0.1 + 0.2), "0.3");
  EXPECT_EQ(formatTick(9999.9999), "1e4");
  EXPECT_EQ(formatTick(std::pow(10.0, -4)), "1e-4");
}

TEST(SvgPlot, SkipsAndCountsPointsItCannotDraw) {
  PlotPanel panel = convergencePanel();
  panel.series[0].y = {1e-3, 0, -1, 1e-2};  // two points at or below 0 on a log axis
  panel.series[1].x[1] = std::nan("");      // and one not finite
  const std::string svg = svgPlot({panel});
  EXPECT_EQ(xmlFault(svg), "");
  EXPECT_NE(svg.find(">3 points not shown (not finite, or &lt;= 0 on a log axis)</text>"),
            std::string::npos);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
  // The lines break at the gaps: series 0 as two runs, series 1 as two.
  EXPECT_EQ(occurrences(svg, "<polyline"), 4u);

  // Zero and negatives are fine on a linear axis.
  panel.logY = false;
  panel.series[1].x[1] = 2e-3;
  const std::string linear = svgPlot({panel});
  EXPECT_EQ(linear.find("not shown"), std::string::npos);
  EXPECT_NE(linear.find(">-1<"), std::string::npos);

  const std::string all = svgPlot({convergencePanel()});
  EXPECT_EQ(all.find("not shown"), std::string::npos);
}

TEST(SvgPlot, OneLegendPerPanelWithDistinctColoursAndMarkers) {
  const std::string svg = svgPlot({convergencePanel(), iterationPanel()});
  EXPECT_EQ(occurrences(svg, "class=\"legend\""), 2u);
  EXPECT_EQ(occurrences(svg, "class=\"panel\""), 2u);
  EXPECT_EQ(occurrences(svg, "stroke-dasharray"), 2u);  // the dashed series: curve and legend

  PlotPanel many;
  many.title = many.xLabel = many.yLabel = "x";
  for (int k = 0; k < 8; ++k) {
    many.series.push_back({"s" + std::to_string(k), {1.0 + k, 2.0 + k}, {1.0, 2.0}});
  }
  const std::string eight = svgPlot({many});
  for (const char* colour :
       {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#F0E442"}) {
    EXPECT_NE(eight.find(std::string("<g fill=\"") + colour), std::string::npos) << colour;
  }
  EXPECT_GT(occurrences(eight, "<circle"), 0u);
  EXPECT_GT(occurrences(eight, "<polygon"), 0u);
}

TEST(SvgPlot, PanelsWithoutDrawableData) {
  PlotPanel empty;
  PlotPanel noPoints = iterationPanel();
  for (auto& series : noPoints.series) series.x.clear(), series.y.clear();
  const std::string svg = svgPlot({empty, noPoints});
  EXPECT_EQ(xmlFault(svg), "");
  EXPECT_EQ(occurrences(svg, "class=\"legend\""), 1u);  // none for a panel without series
}

TEST(SvgPlot, IsDeterministic) {
  const std::vector<PlotPanel> panels = {convergencePanel(), iterationPanel()};
  EXPECT_EQ(svgPlot(panels), svgPlot(panels));
  EXPECT_EQ(svgPlot(panels, 400, 300), svgPlot(panels, 400, 300));
}

TEST(SvgPlot, RefusesBadInput) {
  EXPECT_THROW(svgPlot({}), std::invalid_argument);
  PlotPanel uneven = convergencePanel();
  uneven.series[0].y.pop_back();
  EXPECT_THROW(svgPlot({uneven}), std::invalid_argument);
  EXPECT_THROW(svgPlot({convergencePanel()}, 100, 100), std::invalid_argument);
}

}  // namespace
}  // namespace radiosity::jobs
