// A small SVG line-plot writer for the plots of `radiosity study` (error against run time, error
// and residual against iteration): standalone SVG 1.1 text, no dependencies, so a plot can be
// read without the CSV it was drawn from.
#pragma once

#include <string>
#include <vector>

namespace radiosity::jobs {

/// One curve: the points (x[k], y[k]) joined in the given order.
struct PlotSeries {
  std::string label;
  std::vector<double> x, y;  ///< the same length
  bool dashed = false;
};

/// One set of axes.
struct PlotPanel {
  std::string title, xLabel, yLabel;  ///< labels include units, e.g. "wall time (s)"
  bool logX = true, logY = true;
  std::vector<PlotSeries> series;
};

/// One SVG document with the panels side by side, each panelWidth × panelHeight pixels, with
/// axes, grid lines, tick labels (axisTicks, formatTick), a legend naming each series with its
/// colour (Okabe–Ito palette) and marker, and a marker at each data point. A point is not drawn
/// when a coordinate is not finite or is ≤ 0 on a log axis; the line breaks there and a caption
/// gives the number of such points. Same input, same bytes.
/// Throws std::invalid_argument for no panels, a series whose x and y differ in length, or a
/// panel smaller than 200 × 150.
std::string svgPlot(const std::vector<PlotPanel>& panels, int panelWidth = 560,
                    int panelHeight = 420);

/// The ticks of an axis showing [lo, hi], first and last at or beyond the ends to within
/// rounding (the axis range).
/// Log: each power of ten from the decade at or below lo to the one at or above hi, at least
/// two. Linear: 4 to 8 evenly spaced multiples of 1, 2 or 5 × 10^k (lo == hi is widened).
/// Throws std::invalid_argument unless lo ≤ hi are finite (and lo > 0 on a log axis).
std::vector<double> axisTicks(double lo, double hi, bool log);

/// A tick label, short: "0.01", "10", "1000", "2.5" in plain notation; "1e-3", "1e4", "2.5e-7"
/// outside 0.01 ≤ |v| < 10000. Six significant digits at most, so 0.1 + 0.2 gives "0.3".
std::string formatTick(double v);

}  // namespace radiosity::jobs
