// SVG line plots for `radiosity study`: each panel a plot area framed by tick labels, axis
// labels and a title, with the curves, their markers and a legend inside.
#include "jobs/study/svg_plot.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string_view>
#include <utility>
#include <vector>

#include "core/xml_text.h"

namespace radiosity::jobs {

namespace {

// Okabe and Ito's colour-blind-safe palette; yellow last, as it is faint on white.
constexpr std::array<const char*, 8> kColours = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                 "#E69F00", "#56B4E9", "#000000", "#F0E442"};
// Markers differ in shape as well as colour, so curves stay apart in grey print: a circle, then
// these outlines (unit offsets from the centre, y down): square, triangles, diamond, plus.
// clang-format off
const std::vector<std::vector<std::pair<double, double>>> kOutlines = {
    {{-0.9, -0.9}, {0.9, -0.9}, {0.9, 0.9}, {-0.9, 0.9}},
    {{0, -1.2}, {1.1, 0.8}, {-1.1, 0.8}},
    {{0, -1.3}, {1.1, 0}, {0, 1.3}, {-1.1, 0}},
    {{0, 1.2}, {1.1, -0.8}, {-1.1, -0.8}},
    {{-0.35, -1.2}, {0.35, -1.2}, {0.35, -0.35}, {1.2, -0.35}, {1.2, 0.35}, {0.35, 0.35},
     {0.35, 1.2}, {-0.35, 1.2}, {-0.35, 0.35}, {-1.2, 0.35}, {-1.2, -0.35}, {-0.35, -0.35}}};
// clang-format on
constexpr int kMarkerShapes = 1 + 5;

// Room around a panel's plot area: title above; tick labels, axis label and caption below;
// tick labels and the rotated axis label on the left.
constexpr double kLeft = 72, kRight = 16, kTop = 34, kBottom = 62;
constexpr int kMinWidth = 200, kMinHeight = 150;
// At most this many tick labels per axis; more decades label every second (third, ...) one.
constexpr size_t kMaxTickLabels = 10;

/// A coordinate with two decimals. to_chars, unlike printf, ignores the locale.
std::string num(double v) {
  char buffer[64];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::fixed, 2);
  return std::string(buffer, end.ptr);
}

/// About the width of `text` in a sans-serif font, without font metrics: to size the legend.
double textWidth(std::string_view text, double fontSize) {
  // Count UTF-8 characters, not bytes: labels may hold "µs" or "–".
  const auto chars = std::count_if(text.begin(), text.end(), [](char c) {
    return (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  });
  return 0.6 * fontSize * static_cast<double>(chars);
}

std::vector<double> logTicks(double lo, double hi) {
  // The tolerance keeps an exact power of ten (log10 may give -3.9999...) on its own decade.
  const int first = static_cast<int>(std::floor(std::log10(lo) + 1e-9));
  const int last = std::max(static_cast<int>(std::ceil(std::log10(hi) - 1e-9)), first + 1);
  std::vector<double> ticks;
  for (int k = first; k <= last; ++k) ticks.push_back(std::pow(10.0, k));
  return ticks;
}

/// Steps of 1, 2 or 5 × 10^k: of those giving 4 to 8 ticks, the one nearest 6 ticks (one
/// always exists, as each step is at most 2.5 times the last).
std::vector<double> linearTicks(double lo, double hi) {
  if (lo == hi) {
    const double pad = lo == 0 ? 1 : std::abs(lo) / 2;
    lo -= pad;
    hi += pad;
  }
  const int decade = static_cast<int>(std::floor(std::log10(hi - lo)));
  double bestStep = 0;
  long long bestFirst = 0, bestLast = 0;
  for (int e = decade - 2; e <= decade + 1; ++e) {
    for (const double mantissa : {1.0, 2.0, 5.0}) {
      const double step = mantissa * std::pow(10.0, e);
      // The tolerance stops 0.3 / 0.1 = 2.9999... from adding a tick below the data.
      const auto first = static_cast<long long>(std::floor(lo / step + 1e-9));
      const auto last = static_cast<long long>(std::ceil(hi / step - 1e-9));
      const long long count = last - first + 1;
      if (count < 4 || count > 8) continue;
      if (bestStep == 0 || std::abs(count - 6) < std::abs(bestLast - bestFirst + 1 - 6)) {
        bestStep = step;
        bestFirst = first;
        bestLast = last;
      }
    }
  }
  std::vector<double> ticks;
  // Multiples of the step, not sums of it, so rounding does not accumulate and 0 is exact.
  for (long long n = bestFirst; n <= bestLast; ++n) {
    ticks.push_back(static_cast<double>(n) * bestStep);
  }
  return ticks;
}

bool drawable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }

struct Point {
  double x, y;
};

/// The series' drawable points, in runs between the others: a line must not bridge a gap.
std::vector<std::vector<Point>> drawableRuns(const PlotSeries& series, bool logX, bool logY) {
  std::vector<std::vector<Point>> runs(1);
  for (size_t k = 0; k < series.x.size(); ++k) {
    if (drawable(series.x[k], logX) && drawable(series.y[k], logY)) {
      runs.back().push_back({series.x[k], series.y[k]});
    } else if (!runs.back().empty()) {
      runs.emplace_back();
    }
  }
  if (runs.back().empty()) runs.pop_back();
  return runs;
}

/// The ticks of an axis spanning `values` (a default decade or unit range when empty).
std::vector<double> ticksSpanning(const std::vector<double>& values, bool log) {
  if (values.empty()) return log ? axisTicks(1, 10, true) : axisTicks(0, 1, false);
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return axisTicks(*lo, *hi, log);
}

/// Maps data values to pixels along one axis: ticks.front() to `from`, ticks.back() to `to`.
struct Axis {
  bool log;
  std::vector<double> ticks;
  double from, to;

  double pixel(double v) const {
    const auto scale = [this](double u) { return log ? std::log10(u) : u; };
    const double lo = scale(ticks.front()), hi = scale(ticks.back());
    return from + (scale(v) - lo) / (hi - lo) * (to - from);
  }
};

/// Where one panel's plot area lies in the document.
struct Frame {
  double left, top, right, bottom;
};

std::string strokeStyle(size_t seriesIndex, bool dashed) {
  std::string style = std::string("fill=\"none\" stroke=\"") +
                      kColours[seriesIndex % kColours.size()] + "\" stroke-width=\"1.5\"";
  if (dashed) style += " stroke-dasharray=\"6,4\"";
  return style;
}

/// A marker centred on (x, y); its colour comes from the enclosing group's fill.
std::string marker(size_t seriesIndex, double x, double y) {
  constexpr double radius = 3.5;
  const size_t shape = seriesIndex % kMarkerShapes;
  if (shape == 0) {
    return "<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"" + num(radius) + "\"/>\n";
  }
  std::string points;
  for (const auto& [dx, dy] : kOutlines[shape - 1]) {
    if (!points.empty()) points += ' ';
    points += num(x + radius * dx) + "," + num(y + radius * dy);
  }
  return "<polygon points=\"" + points + "\"/>\n";
}

std::string line(double x1, double y1, double x2, double y2, std::string_view style) {
  return "<line x1=\"" + num(x1) + "\" y1=\"" + num(y1) + "\" x2=\"" + num(x2) + "\" y2=\"" +
         num(y2) + "\" " + std::string(style) + "/>\n";
}

std::string text(double x, double y, std::string_view content, std::string_view attributes = {}) {
  std::string element = "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\"";
  if (!attributes.empty()) element.append(" ").append(attributes);
  return element + ">" + escapeXml(content) + "</text>\n";
}

/// Grid lines and labels at the ticks, short marks at 2..9 × 10^k on a log axis of few decades,
/// and the axis label. `vertical`: the y axis.
void drawAxis(std::string& out, const Axis& axis, const Frame& frame, bool vertical,
              const std::string& label) {
  const size_t labelEvery = (axis.ticks.size() + kMaxTickLabels - 1) / kMaxTickLabels;
  for (size_t k = 0; k < axis.ticks.size(); ++k) {
    const double p = axis.pixel(axis.ticks[k]);
    const bool labelled = k % labelEvery == 0;
    if (vertical) {
      out += line(frame.left, p, frame.right, p, "stroke=\"#dddddd\"");
      out += line(frame.left - 5, p, frame.left, p, "stroke=\"black\"");
      if (labelled) {
        out += text(frame.left - 8, p + 4, formatTick(axis.ticks[k]), "text-anchor=\"end\"");
      }
    } else {
      out += line(p, frame.top, p, frame.bottom, "stroke=\"#dddddd\"");
      out += line(p, frame.bottom, p, frame.bottom + 5, "stroke=\"black\"");
      if (labelled) {
        out += text(p, frame.bottom + 18, formatTick(axis.ticks[k]), "text-anchor=\"middle\"");
      }
    }
  }
  if (axis.log && axis.ticks.size() <= 7) {
    for (size_t k = 0; k + 1 < axis.ticks.size(); ++k) {
      for (int m = 2; m <= 9; ++m) {
        const double p = axis.pixel(m * axis.ticks[k]);
        out += vertical ? line(frame.left - 3, p, frame.left, p, "stroke=\"black\"")
                        : line(p, frame.bottom, p, frame.bottom + 3, "stroke=\"black\"");
      }
    }
  }
  if (vertical) {
    const double x = frame.left - kLeft + 16, y = (frame.top + frame.bottom) / 2;
    out += text(x, y, label,
                "text-anchor=\"middle\" transform=\"rotate(-90 " + num(x) + " " + num(y) + ")\"");
  } else {
    out += text((frame.left + frame.right) / 2, frame.bottom + 38, label, "text-anchor=\"middle\"");
  }
}

void drawSeries(std::string& out, size_t index, const PlotSeries& series,
                const std::vector<std::vector<Point>>& runs, const Axis& x, const Axis& y) {
  out += "<g class=\"series\">\n";
  for (const auto& run : runs) {
    std::string points;
    for (const Point& point : run) {
      if (!points.empty()) points += ' ';
      points += num(x.pixel(point.x)) + "," + num(y.pixel(point.y));
    }
    out += "<polyline points=\"" + points + "\" " + strokeStyle(index, series.dashed) + "/>\n";
  }
  out += std::string("<g fill=\"") + kColours[index % kColours.size()] + "\">\n";
  for (const auto& run : runs) {
    for (const Point& point : run) out += marker(index, x.pixel(point.x), y.pixel(point.y));
  }
  out += "</g>\n</g>\n";
}

/// A box in the plot area's top right corner: each series' line style, marker and label.
void drawLegend(std::string& out, const std::vector<PlotSeries>& series, const Frame& frame) {
  if (series.empty()) return;
  constexpr double row = 16, fontSize = 11;  // fontSize: as the group's font-size below
  double labelWidth = 0;
  for (const auto& s : series) labelWidth = std::max(labelWidth, textWidth(s.label, fontSize));
  const double width = 46 + labelWidth, height = 8 + row * static_cast<double>(series.size());
  const double left = std::max(frame.left + 4, frame.right - 8 - width), top = frame.top + 8;
  out += "<g class=\"legend\" font-size=\"11\">\n";
  out += "<rect x=\"" + num(left) + "\" y=\"" + num(top) + "\" width=\"" + num(width) +
         "\" height=\"" + num(height) +
         "\" fill=\"white\" fill-opacity=\"0.9\" stroke=\"#999999\"/>\n";
  for (size_t k = 0; k < series.size(); ++k) {
    const double y = top + 4 + row * (static_cast<double>(k) + 0.5);
    out += line(left + 8, y, left + 34, y, strokeStyle(k, series[k].dashed));
    out += std::string("<g fill=\"") + kColours[k % kColours.size()] + "\">\n" +
           marker(k, left + 21, y) + "</g>\n";
    out += text(left + 40, y + 4, series[k].label);
  }
  out += "</g>\n";
}

void drawPanel(std::string& out, const PlotPanel& panel, double offset, double width,
               double height) {
  const Frame frame{offset + kLeft, kTop, offset + width - kRight, height - kBottom};
  std::vector<std::vector<std::vector<Point>>> runs;
  std::vector<double> xs, ys;
  size_t skipped = 0;
  for (const auto& series : panel.series) {
    runs.push_back(drawableRuns(series, panel.logX, panel.logY));
    skipped += series.x.size();
    for (const auto& run : runs.back()) {
      skipped -= run.size();
      for (const Point& point : run) {
        xs.push_back(point.x);
        ys.push_back(point.y);
      }
    }
  }
  const Axis x{panel.logX, ticksSpanning(xs, panel.logX), frame.left, frame.right};
  const Axis y{panel.logY, ticksSpanning(ys, panel.logY), frame.bottom, frame.top};

  out += "<g class=\"panel\">\n";
  out += text((frame.left + frame.right) / 2, 22, panel.title,
              "text-anchor=\"middle\" font-size=\"14\" font-weight=\"bold\"");
  drawAxis(out, x, frame, false, panel.xLabel);
  drawAxis(out, y, frame, true, panel.yLabel);
  out += "<rect x=\"" + num(frame.left) + "\" y=\"" + num(frame.top) + "\" width=\"" +
         num(frame.right - frame.left) + "\" height=\"" + num(frame.bottom - frame.top) +
         "\" fill=\"none\" stroke=\"black\"/>\n";
  for (size_t k = 0; k < panel.series.size(); ++k) {
    drawSeries(out, k, panel.series[k], runs[k], x, y);
  }
  drawLegend(out, panel.series, frame);
  if (skipped > 0) {
    const std::string caption = std::to_string(skipped) + (skipped == 1 ? " point" : " points") +
                                " not shown (not finite, or <= 0 on a log axis)";
    out += text(offset + 8, height - 8, caption,
                "class=\"caption\" font-size=\"10\" fill=\"#555555\"");
  }
  out += "</g>\n";
}

}  // namespace

std::vector<double> axisTicks(double lo, double hi, bool log) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || !std::isfinite(hi - lo) || lo > hi ||
      (log && lo <= 0)) {
    throw std::invalid_argument("axisTicks: need finite lo <= hi (lo > 0 on a log axis)");
  }
  return log ? logTicks(lo, hi) : linearTicks(lo, hi);
}

std::string formatTick(double v) {
  char buffer[64];
  if (v == 0) return "0";  // also -0
  if (!std::isfinite(v)) {
    return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
  }
  // The exponent after rounding to 6 digits, so 9999.9999 counts as 1e4.
  const std::string scientific(
      buffer,
      std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::scientific, 5).ptr);
  const size_t e = scientific.find('e');
  const int exponent = std::stoi(scientific.substr(e + 1));
  if (exponent >= -2 && exponent <= 3) {
    return std::string(
        buffer,
        std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::general, 6).ptr);
  }
  std::string mantissa = scientific.substr(0, e);  // "2.50000"
  mantissa.erase(mantissa.find_last_not_of('0') + 1);
  if (mantissa.back() == '.') mantissa.pop_back();
  return mantissa + "e" + std::to_string(exponent);
}

std::string svgPlot(const std::vector<PlotPanel>& panels, int panelWidth, int panelHeight) {
  if (panels.empty()) throw std::invalid_argument("svgPlot: no panels");
  if (panelWidth < kMinWidth || panelHeight < kMinHeight) {
    throw std::invalid_argument("svgPlot: a panel must be at least " + std::to_string(kMinWidth) +
                                " x " + std::to_string(kMinHeight) + " pixels");
  }
  for (const auto& panel : panels) {
    for (const auto& series : panel.series) {
      if (series.x.size() != series.y.size()) {
        throw std::invalid_argument("svgPlot: series \"" + series.label + "\" has " +
                                    std::to_string(series.x.size()) + " x values but " +
                                    std::to_string(series.y.size()) + " y values");
      }
    }
  }
  const std::string width = std::to_string(panelWidth * static_cast<int>(panels.size()));
  const std::string height = std::to_string(panelHeight);
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" + width +
         "\" height=\"" + height + "\" viewBox=\"0 0 " + width + " " + height +
         "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  out += "<rect width=\"" + width + "\" height=\"" + height + "\" fill=\"white\"/>\n";
  for (size_t k = 0; k < panels.size(); ++k) {
    drawPanel(out, panels[k], static_cast<double>(k) * panelWidth, panelWidth, panelHeight);
  }
  out += "</svg>\n";
  return out;
}

}  // namespace radiosity::jobs
