#include "jobs/study/study_plot.h"

#include <algorithm>

#include "core/channels.h"
#include "solve/solver.h"

namespace radiosity::jobs {

void StudyPlot::Curves::add(const std::string& label, double x, double y, bool dashed) {
  PlotSeries& series = byLabel[label];
  series.label = label;
  series.dashed = dashed;
  series.x.push_back(x);
  series.y.push_back(y);
}

std::vector<PlotSeries> StudyPlot::Curves::list() const {
  std::vector<PlotSeries> all;
  for (const auto& [label, series] : byLabel) all.push_back(series);
  return all;
}

void StudyPlot::add(double maxArea, const SettingResult& result) {
  const solve::Report& report = result.report;
  std::string label = formfactor::estimatorName(result.estimator);
  if (settings_.rtols.size() > 1) label += ", rtol " + number(result.rtol);
  if (maxAreas_.size() > 1) label += ", max area " + number(maxArea);
  errorAgainstTime_.add(label + ": B measured", result.seconds, worst(result.b.rms));
  errorAgainstTime_.add(label + ": B estimated", result.seconds, report.relativeStderr, true);

  // The solver's curves are those of the most rays of the first estimator and mesh.
  const bool solverSetting = maxArea == maxAreas_.front() &&
                             result.estimator == settings_.estimators.front() &&
                             result.rays == settings_.rays.back();
  // The error where the solver stopped, at each --rtol: the solver's error against its
  // iterations and time.
  if (solverSetting) {
    solverError_.x.push_back(
        std::max(1.0, static_cast<double>(report.iterations) / std::max(1, report.channelsSolved)));
    solverError_.y.push_back(worst(result.b.rms));
    solverErrorByTime_.x.push_back(result.solveSeconds);
    solverErrorByTime_.y.push_back(worst(result.b.rms));
  }
  // The solver's own curve: the most accurate setting (the smallest --rtol).
  if (solverSetting &&
      result.rtol == *std::min_element(settings_.rtols.begin(), settings_.rtols.end())) {
    addResiduals(report.history);
  }
}

std::string StudyPlot::svg() const {
  std::vector<PlotSeries> solverCurves = solverCurves_, solverTimeCurves = solverTimeCurves_;
  solverCurves.push_back(solverError_);
  solverTimeCurves.push_back(solverErrorByTime_);
  PlotPanel accuracy{"Error against run time: " + settings_.scene,
                     "wall time: mesh + form factors + solve (s)",
                     "RMS relative error of B over reflecting patches (estimate dashed)",
                     true,
                     true,
                     errorAgainstTime_.list()};
  PlotPanel iterations{std::string("The solver (") + solve::solverName(settings_.solver) +
                           "), most accurate setting",
                       "iteration",
                       "relative residual; error of B",
                       true,
                       true,
                       solverCurves};
  PlotPanel time{
      "The solver against time", "solve time (s)", "relative residual; error of B", true, true,
      solverTimeCurves};
  return svgPlot({accuracy, iterations, time});
}

void StudyPlot::addResiduals(const SolveHistory& history) {
  for (int c = 0; c < 3; ++c) {
    PlotSeries byIteration{std::string("residual, ") + kChannelNames[c], {}, {}};
    PlotSeries byTime = byIteration;
    for (size_t k = 0; k < history.size(); ++k) {
      if (history.channel[k] != c) continue;
      byIteration.x.push_back(static_cast<double>(history.iteration[k] + 1));
      byIteration.y.push_back(history.residual[k]);
      byTime.x.push_back(history.seconds[k]);
      byTime.y.push_back(history.residual[k]);
    }
    if (!byIteration.x.empty()) {
      solverCurves_.push_back(byIteration);
      solverTimeCurves_.push_back(byTime);
    }
  }
}

}  // namespace radiosity::jobs
