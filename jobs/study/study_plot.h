// The plot of `radiosity study` (SVG): the error of B against run time of every setting, and the
// solver's residuals and errors against iterations and time for the most rays of the first
// estimator and mesh.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/run_state.h"
#include "jobs/commands.h"
#include "jobs/study/setting_result.h"
#include "jobs/study/svg_plot.h"

namespace radiosity::jobs {

class StudyPlot {
 public:
  StudyPlot(const StudySettings& settings, const std::vector<double>& maxAreas)
      : settings_(settings), maxAreas_(maxAreas) {}

  /// A setting on the mesh of area bound `maxArea`.
  void add(double maxArea, const SettingResult& result);
  /// The three panels: error against run time, and the solver against iterations and time.
  std::string svg() const;

 private:
  // One curve per estimator (and per tolerance or mesh when they are swept too).
  struct Curves {
    std::map<std::string, PlotSeries> byLabel;
    void add(const std::string& label, double x, double y, bool dashed = false);
    std::vector<PlotSeries> list() const;
  };

  // Each channel's residual against the iterations and against time.
  void addResiduals(const SolveHistory& history);

  const StudySettings& settings_;
  const std::vector<double>& maxAreas_;
  Curves errorAgainstTime_;
  std::vector<PlotSeries> solverCurves_, solverTimeCurves_;
  // (against the iterations per channel solved, like the residuals)
  PlotSeries solverError_{"error of B where it stopped (each --rtol)", {}, {}, true};
  PlotSeries solverErrorByTime_ = solverError_;
};

}  // namespace radiosity::jobs
