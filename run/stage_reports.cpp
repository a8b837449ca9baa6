// What each stage of `radiosity solve` did, as rank 0 prints it. Collective where the figures
// are summed over ranks.
#include "run/stage_reports.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/channels.h"
#include "io/store/result_format.h"

namespace radiosity::run {

namespace {

/// "row sums of F (patches per bin from its lower edge): 0: 0 | 0.5: 3 | ...", on one line.
std::string histogramLine(const std::vector<int64_t>& counts, const std::vector<double>& edges) {
  std::ostringstream text;
  text.precision(10);  // tells 1 − 1e-9 from 1
  text << "row sums of F (patches per bin from its lower edge):";
  for (size_t k = 0; k < counts.size(); ++k) {
    text << (k == 0 ? " " : " | ");
    if (k < edges.size()) text << edges[k] << ": ";
    text << counts[k];
  }
  return text.str();
}

// "'poster' (face 7, counting from 0)", or "face 7 (counting from 0)" without labels.
std::string faceName(const Mesh& scene, int64_t face, int32_t label) {
  const std::string number = "face " + std::to_string(face) + ", counting from 0";
  if (label < 0 || label >= static_cast<int32_t>(scene.labelNames.size()))
    return number.substr(0, number.find(',')) + " (counting from 0)";
  return "'" + scene.labelNames[label] + "' (" + number + ")";
}

// At most this many covered faces are named, one line each; the rest are counted.
constexpr size_t kCoveredLines = 8;

}  // namespace

void reportCovered(const Console& console, const Mesh& scene,
                   const partition::ContactReport& contacts) {
  if (contacts.covered.empty()) return;
  const std::string unit =
      scene.lengthUnit.empty() ? " (area in the scene's units)" : " " + scene.lengthUnit + "²";
  char line[200];
  std::snprintf(line, sizeof line, "%.4g", contacts.coveredArea);
  console.info("contacts: " + std::to_string(contacts.covered.size()) +
               " faces lie under others laid over them (coplanar, facing the same way): their "
               "covered parts, " +
               line + unit +
               " in all, are left out, as an opening is cut "
               "for a window (rays would hit either face)");
  for (size_t k = 0; k < contacts.covered.size() && k < kCoveredLines; ++k) {
    const partition::CoveredFace& c = contacts.covered[k];
    std::snprintf(line, sizeof line, "%.4g", c.area);
    console.info("  contacts: " + faceName(scene, c.face, c.label) + " is covered by " +
                 faceName(scene, c.by, c.byLabel) + " over " + line);
  }
  if (contacts.covered.size() > kCoveredLines)
    console.info("  contacts: and " + std::to_string(contacts.covered.size() - kCoveredLines) +
                 " more");
}

void reportContacts(const Console& console, const partition::ContactReport& contacts,
                    size_t contactEdges, double seconds) {
  char line[400];
  std::snprintf(line, sizeof line,
                "contacts: %lld triangles cut along where others touch or cross them, into %lld "
                "pieces; %lld edges along contact lines, where patches get a quarter of the area "
                "bound (%lld pairs of touching boxes, %.2f s; --contacts off: as given, uniform)",
                static_cast<long long>(contacts.trianglesCut),
                static_cast<long long>(contacts.pieces), static_cast<long long>(contactEdges),
                static_cast<long long>(contacts.candidatePairs), seconds);
  console.info(line);
}

void reportHidden(const Console& console, const Mesh& patches, const std::vector<uint8_t>& hidden) {
  int64_t count = 0;
  double area = 0, total = 0;
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    total += patches.area(t);
    if (hidden[t]) ++count, area += patches.area(t);
  }
  if (count == 0) return;
  char line[400];
  if (count == patches.triangleCount()) {
    std::snprintf(line, sizeof line,
                  "every patch sees only the backs of faces: is the scene inside out? (a face's "
                  "lit side is the one its vertices run counter-clockwise around)");
    console.warn(line);
    return;
  }
  std::snprintf(line, sizeof line,
                "hidden: %lld patches (%.3g %% of the area) see nothing but the backs of faces "
                "(under objects resting on them, inside solids): left out of the solve (B = E), "
                "marked in /patches/hidden",
                static_cast<long long>(count), 100 * area / total);
  console.info(line);
}

void reportMeshing(const Console& console, const partition::MeshingReport& meshing,
                   int64_t patchesAsked, double maxArea) {
  char bound[120];
  if (patchesAsked > 0) {
    std::snprintf(bound, sizeof bound, "--patches %lld: area bound %.4g%s",
                  static_cast<long long>(patchesAsked), meshing.areaBound,
                  meshing.areaBound > 0 ? ", largest split first" : " (none: enough triangles)");
  } else {
    std::snprintf(bound, sizeof bound, "area bound %.4g", maxArea);
  }
  char line[300];
  std::snprintf(line, sizeof line,
                "mesh: %lld input triangles -> %lld patches (%s; max area %.4g, worst aspect "
                "%.2f)",
                static_cast<long long>(meshing.inputTriangles),
                static_cast<long long>(meshing.patches), bound, meshing.maxPatchArea,
                meshing.worstAspectRatio);
  console.info(line);
}

// At most this share of the rays from rows that see only backs is taken for hidden patches.
constexpr double kBlindShare = 0.1;

std::string windingWarning(int64_t rays, int64_t backFaceHits, const std::vector<int64_t>& byLabel,
                           const std::vector<std::string>& labelNames) {
  if (!(static_cast<double>(backFaceHits) > kWindingWarningShare * static_cast<double>(rays))) {
    return "";
  }
  std::string culprits;
  std::vector<size_t> order(byLabel.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return byLabel[a] > byLabel[b]; });
  for (size_t k = 0; k < std::min<size_t>(order.size(), 5) && byLabel[order[k]] > 0; ++k) {
    culprits += std::string(k == 0 ? " most hit: " : ", ") + "'" + labelNames[order[k]] + "' " +
                std::to_string(static_cast<int>(
                    std::lround(100.0 * byLabel[order[k]] / static_cast<double>(backFaceHits)))) +
                "%";
  }
  char share[32];
  std::snprintf(share, sizeof share, "%.1f%%", 100.0 * backFaceHits / static_cast<double>(rays));
  return std::string(share) +
         " of the rays hit the back of a face with no front coincident with it: wrong winding, "
         "or an inside-out or leaky model?" +
         culprits;
}

std::string escapeWarning(int64_t rays, int64_t escapedRays) {
  if (rays <= 0 || !(escapedRays > kEscapeWarningShare * static_cast<double>(rays))) return "";
  char share[32];
  std::snprintf(share, sizeof share, "%.1f%%", 100.0 * escapedRays / static_cast<double>(rays));
  return std::string(share) +
         " of the rays left the scene without hitting anything: hardly any patch sees another, "
         "so B is nearly E everywhere. If the scene is a room or an enclosure, its faces face "
         "outward: the lit side of a face is the one its vertices run counter-clockwise around "
         "(reverse each face's vertex order)";
}

std::vector<int64_t> reportFormFactors(const Console& console, const Mesh& patches,
                                       const std::vector<double>& rowSums, int64_t nonzeros,
                                       const formfactor::Statistics& statistics, double seconds,
                                       int valueBytes) {
  const MPI_Comm comm = console.comm();
  const int64_t patchCount = patches.triangleCount();
  std::vector<int64_t> rowSumHistogram;
  int64_t counts[5] = {statistics.raysCast, statistics.backFaceHits, statistics.escapedRays,
                       nonzeros, statistics.blindBackFaceHits};
  MPI_Allreduce(MPI_IN_PLACE, counts, 5, MPI_INT64_T, MPI_SUM, comm);
  double sums[1] = {statistics.sumRowSums}, lows[1] = {statistics.minRowSum},
         highs[1] = {statistics.maxRowSum};
  if (rowSums.empty()) lows[0] = 2.0;
  MPI_Allreduce(MPI_IN_PLACE, sums, 1, MPI_DOUBLE, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, lows, 1, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, highs, 1, MPI_DOUBLE, MPI_MAX, comm);
  char line[300];
  int64_t exact[2] = {statistics.pairFactors, statistics.rowsOffTheirSum};
  MPI_Allreduce(MPI_IN_PLACE, exact, 2, MPI_INT64_T, MPI_SUM, comm);
  if (exact[0] > 0) {
    std::snprintf(line, sizeof line,
                  "form factors: %lld pair factors by closed forms in %.2f s (%.3g/s)",
                  static_cast<long long>(exact[0]), seconds, exact[0] / std::max(seconds, 1e-9));
    console.info(line);
  }
  if (exact[1] > 0) {
    std::snprintf(line, sizeof line,
                  "form factors: %lld exact rows are off their sum by up to 2^-24 of it: stored "
                  "as floats, they have too few entries below 2^-8 to take the rounding (few "
                  "patches); --formfactor-precision double keeps every row's sum",
                  static_cast<long long>(exact[1]));
    console.warn(line);
  }
  std::snprintf(line, sizeof line,
                "form factors: %lld rays in %.2f s (%.3g rays/s), %lld nonzeros (%.1f per "
                "row, %.0f bytes per patch in the solver's matrix), row sums min %.4f mean %.4f "
                "max %.4f, %lld rays escaped, %lld hit back faces",
                static_cast<long long>(counts[0]), seconds, counts[0] / std::max(seconds, 1e-9),
                static_cast<long long>(counts[3]), double(counts[3]) / patchCount,
                // F's store: a 4-byte column index and a value per nonzero, a row pointer per
                // row.
                ((4.0 + valueBytes) * counts[3] + 4.0 * (patchCount + 1)) / patchCount, lows[0],
                sums[0] / patchCount, highs[0], static_cast<long long>(counts[2]),
                static_cast<long long>(counts[1]));
  console.info(line);
  // The row sums binned (closed scenes: all in the bin around 1), on every rank.
  rowSumHistogram = formfactor::rowSumHistogram(rowSums);
  MPI_Allreduce(MPI_IN_PLACE, rowSumHistogram.data(), static_cast<int>(rowSumHistogram.size()),
                MPI_INT64_T, MPI_SUM, comm);
  console.info(histogramLine(rowSumHistogram, formfactor::rowSumBinEdges()));
  // Back-face hits per label (material/group), to name the faces whose winding looks wrong.
  std::vector<int64_t> byLabel = statistics.backFaceHitsByLabel;
  byLabel.resize(patches.hasLabels() ? patches.labelNames.size() : 0, 0);
  if (!byLabel.empty()) {
    MPI_Allreduce(MPI_IN_PLACE, byLabel.data(), static_cast<int>(byLabel.size()), MPI_INT64_T,
                  MPI_SUM, comm);
  }
  // Rows that see only backs are hidden patches (under objects, left out of the solve), not
  // wrong winding, while they are a small part of the scene (as on the published Cornell box);
  // a large part seeing only backs is a model inside out around them (a lamp in a
  // room wound outward), and is warned about with them.
  const bool blindAreHidden = counts[4] <= kBlindShare * counts[0];
  const int64_t blind = blindAreHidden ? counts[4] : 0;
  const std::string warning =
      windingWarning(counts[0] - blind, counts[1] - blind, byLabel, patches.labelNames);
  if (!warning.empty()) console.warn(warning);
  // (the hidden rows' rays too are left out of the share: they say nothing of the scene's
  // winding, and a lamp meshed finely would otherwise hide a room wound inside out)
  const std::string escaped = escapeWarning(counts[0] - blind, counts[2]);
  if (!escaped.empty()) console.warn(escaped);
  return rowSumHistogram;
}

void reportRepair(const Console& console, const solve::RepairReport& repair, double seconds) {
  char line[400];
  std::snprintf(line, sizeof line,
                "repair: reciprocity defect %.3g (max pair %.3g, %.0f%% one-sided) -> %.2g; "
                "dropped %.1f%% of nonzeros (%.2g%% of the weight); change %.3g; closure "
                "%.2g -> %.2g in %lld CG iterations; %lld -> %lld nonzeros (%.0f -> %.0f "
                "bytes per patch); %.2f s",
                repair.reciprocityDefect, repair.maxPairDefect, 100 * repair.oneSidedShare,
                repair.defectAfter, 100 * repair.droppedNonzeroShare,
                100 * repair.droppedWeightShare, repair.change, repair.closureBefore,
                repair.closureAfter, static_cast<long long>(repair.iterations),
                static_cast<long long>(repair.nonzerosBefore),
                static_cast<long long>(repair.nonzerosAfter), repair.bytesPerPatchBefore,
                repair.bytesPerPatchAfter, seconds);
  console.info(line);
  if (!repair.converged) {
    console.warn("the closure repair's CG did not converge: row sums are off by up to " +
                 std::to_string(repair.closureAfter));
  }
  if (repair.emptyRows > 0) {
    console.warn(std::to_string(repair.emptyRows) +
                 " rows lost every entry to --drop-threshold and cannot be closed: lower it");
  }
  if (repair.negativeKept > 0) {
    console.warn("the closure repair made " + std::to_string(repair.negativeKept) +
                 " form factors negative (" + std::to_string(repair.negativeClipped) +
                 " tiny ones clipped to 0): lower --drop-threshold");
  }
}

void reportBalance(const Console& console, const solve::BalanceReport& balance, double seconds) {
  char line[300];
  std::snprintf(line, sizeof line,
                "thermal balance: columns scaled to what reciprocity says they carry (off by "
                "up to %.2g as sampled), rows kept to %.2g of their sums, in %d sweeps; %.2f s",
                balance.columnDefectBefore, balance.rowDefectAfter, balance.iterations, seconds);
  console.info(line);
  if (!balance.converged)
    console.warn("the thermal balance of F did not converge: rows are off their sums by up to " +
                 std::to_string(balance.rowDefectAfter) + " (the heat rates still balance)");
}

void reportSolve(const Console& console, const solve::Report& report, double seconds) {
  char line[600], bound[200];
  // q = 1 (a closed scene that loses nothing, or rows of heat flux) gives no finite bound: said
  // in words, not as "<= inf".
  if (std::isfinite(report.errorBound))
    std::snprintf(bound, sizeof bound, "error bound |B* - B|/|B| <= %.3g (max norm; q = %.6g)",
                  report.errorBound, report.contraction);
  else
    std::snprintf(bound, sizeof bound,
                  "no error bound from the residual (q = %.6g: some light is never lost, so the "
                  "residual does not bound the error; the estimated error below does)",
                  report.contraction);
  std::snprintf(line, sizeof line,
                "solve: %s, %lld iterations over %d %s solved, relative residual %.3g, %s, "
                "condition ~ %.3g; %lld unknowns, %lld products with F (%.3g nonzeros); %.2f s",
                report.solver.c_str(), static_cast<long long>(report.iterations),
                report.channelsSolved, report.channelsSolved == 1 ? "channel" : "channels",
                report.residual, bound, report.conditionEstimate,
                static_cast<long long>(report.unknowns),
                static_cast<long long>(report.matrixProducts),
                static_cast<double>(report.nonzeroProducts), seconds);
  console.info(line);
  if (!report.conditionSource.empty())
    console.detail("solve: the condition estimate from " + report.conditionSource);
  if (report.leftOut != "none") console.info("solve: left out: " + report.leftOut);
}

void reportCalibration(const Console& console, const solve::CalibrationReport& calibration,
                       const solve::DiscretisationReport& discretisation,
                       const solve::Report& report) {
  if (!report.toleranceNote.empty()) console.info("solve: " + report.toleranceNote);
  if (calibration.replicates == 0) return;
  const auto& k = report.calibration;
  char line[800];
  // Where every channel is alike (a grey scene, a thermal run's one channel), one figure each.
  const bool alike = [&] {
    for (const auto* v : {&report.errorB, &report.samplingErrorB, &report.discretisationErrorB,
                          &report.errorH, &k.indirect, &k.direct})
      if ((*v)[0] != (*v)[1] || (*v)[0] != (*v)[2]) return false;
    return true;
  }();
  auto triple = [alike](const std::array<double, 3>& v) {
    char text[64];
    if (alike) {
      std::snprintf(text, sizeof text, "%.2g", v[0]);
    } else {
      std::snprintf(text, sizeof text, "%.2g / %.2g / %.2g", v[0], v[1], v[2]);
    }
    return std::string(text);
  };
  std::snprintf(line, sizeof line,
                "solve: estimated error of B (%s; RMS over the reflecting patches of "
                "each patch's error relative to its own B): %s (sampling %s, discretisation %s); "
                "of H: %s",
                alike ? "every channel alike" : "red/green/blue", triple(report.errorB).c_str(),
                triple(report.samplingErrorB).c_str(), triple(report.discretisationErrorB).c_str(),
                triple(report.errorH).c_str());
  console.info(line);
  std::snprintf(line, sizeof line,
                "solve: per patch in %s (sampling) and %s; the sampling model's indirect part "
                "scaled by %.3g / %.3g / %.3g, its direct part by %.3g / %.3g / %.3g, measured by "
                "%d independent gathers of %lld patches (%lld rays, %.2f s); discretisation from "
                "%lld rays (%.2f s)",
                result_format::kRadiosityStderr, result_format::kRadiosityDiscretisation,
                std::sqrt(k.indirect[0]), std::sqrt(k.indirect[1]), std::sqrt(k.indirect[2]),
                std::sqrt(k.direct[0]), std::sqrt(k.direct[1]), std::sqrt(k.direct[2]),
                calibration.replicates, static_cast<long long>(calibration.patches),
                static_cast<long long>(calibration.rays), calibration.seconds,
                static_cast<long long>(discretisation.rays), discretisation.seconds);
  console.detail(line);  // (the model's inner figures: -v)
}

void reportCheckpoint(const Console& console, const std::string& path, const char* stage,
                      const std::vector<int64_t>& rowSamples, double seconds, bool staged) {
  int64_t finished = 0;
  for (int64_t samples : rowSamples) finished += samples > 0 ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &finished, 1, MPI_INT64_T, MPI_SUM, console.comm());
  if (!console.isRoot()) return;
  // A checkpoint staged with the result is not at `path` yet: its size is not known there.
  std::error_code error;
  const auto bytes = staged ? 0 : std::filesystem::file_size(path, error);
  char size[64] = "renamed with the result";
  if (!staged) std::snprintf(size, sizeof size, "%.3g MB", error ? 0.0 : bytes / 1e6);
  char line[400];
  std::snprintf(line, sizeof line, "checkpoint: wrote %s (stage %s, %lld rows sampled, %s, %.2f s)",
                path.c_str(), stage, static_cast<long long>(finished), size, seconds);
  console.info(line);
}

void reportRestart(const Console& console, const std::string& path, const Checkpoint& saved,
                   int64_t patchCount, int64_t raysPerPatch) {
  int64_t counts[2] = {0, 0};  // rows complete, rows to extend
  for (int64_t samples : saved.rows.rowSamples) {
    if (samples == raysPerPatch) ++counts[0];
    if (samples > 0 && samples < raysPerPatch) ++counts[1];
  }
  MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_INT64_T, MPI_SUM, console.comm());
  const char* states[3] = {"not started", "in progress", "done"};
  std::string channels;
  for (int c = 0; c < 3; ++c)
    channels += std::string(c ? ", " : "") + kChannelNames[c] + " " +
                states[saved.progress.channelState[c]];
  char line[500];
  std::snprintf(line, sizeof line,
                "restart: %s (stage %s): %lld of %lld rows taken as they are, %lld given more "
                "samples, %lld to sample; solve: %s",
                path.c_str(), saved.stage.c_str(), static_cast<long long>(counts[0]),
                static_cast<long long>(patchCount), static_cast<long long>(counts[1]),
                static_cast<long long>(patchCount - counts[0] - counts[1]), channels.c_str());
  console.info(line);
}

}  // namespace radiosity::run
