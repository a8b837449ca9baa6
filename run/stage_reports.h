// What each stage of `radiosity solve` did, printed by rank 0: one line per stage, warnings
// where a figure looks wrong, and the progress of the form-factor stage.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "formfactor/formfactor.h"
#include "io/store/checkpoint.h"
#include "partition/partition.h"
#include "run/console.h"
#include "solve/discretisation_error.h"
#include "solve/error_calibration.h"
#include "solve/solve.h"

namespace radiosity::run {

// Prints patches done, rays per second and time left, at most every two seconds.
class ProgressReporter {
 public:
  /// `workPerRow` of `unit` (rays, pair factors) per row; `what`: the work's name in the line.
  ProgressReporter(const Console& console, int64_t rows, int64_t workPerRow,
                   const char* unit = "rays", const char* what = "form factors")
      : console_(console),
        rows_(rows),
        workPerRow_(workPerRow),
        unit_(unit),
        what_(what),
        start_(MPI_Wtime()),
        last_(start_) {}
  void operator()(int64_t done) {
    double now = MPI_Wtime();
    if (now - last_ < 2.0 || done == rows_) return;
    last_ = now;
    double elapsed = now - start_;
    // Every rank has the same number of rows (±1), so rank 0's pace is the job's.
    double perSecond = done * workPerRow_ * console_.ranks() / elapsed;
    double left = elapsed * (rows_ - done) / done;
    char line[160];
    std::snprintf(
        line, sizeof line, "  %s: %lld/%lld patches on rank 0, %.3g %s/s, about %.0f s left", what_,
        static_cast<long long>(done), static_cast<long long>(rows_), perSecond, unit_, left);
    console_.info(line);
  }

 private:
  const Console& console_;
  int64_t rows_, workPerRow_;
  const char* unit_;
  const char* what_;
  double start_, last_;
};

/// The contacts line: triangles cut along contacts, and what it cost.
void reportContacts(const Console& console, const partition::ContactReport& contacts,
                    size_t contactEdges, double seconds);

/// The faces lying under others, whose covered parts contact cutting left out: how much, and
/// which faces (by label and number), a line each for the first few. Nothing when none.
void reportCovered(const Console& console, const Mesh& scene,
                   const partition::ContactReport& contacts);

/// The hidden-patches line, when there are any: how many and how much area see nothing; a
/// warning when every patch does (a scene inside out).
void reportHidden(const Console& console, const Mesh& patches, const std::vector<uint8_t>& hidden);

/// The mesh line: counts, the area bound (chosen by --patches when patchesAsked > 0), quality.
void reportMeshing(const Console& console, const partition::MeshingReport& meshing,
                   int64_t patchesAsked, double maxArea);

/// The form-factor line (rays, rays/s, nonzeros, bytes per patch with F's values of
/// `valueBytes` each, row sums, escapes, back faces), the row-sum histogram and the winding
/// warning (windingWarning). Collective. Returns the histogram summed over ranks.
std::vector<int64_t> reportFormFactors(const Console& console, const Mesh& patches,
                                       const std::vector<double>& rowSums, int64_t nonzeros,
                                       const formfactor::Statistics& statistics, double seconds,
                                       int valueBytes);

/// The warning, or "" for none, when more than kWindingWarningShare of the form-factor rays hit
/// the back of a face with no front coincident with it (trace::SceneTracer: the two faces
/// of a thin surface do not count), naming the labels (`byLabel` counts per one of
/// `labelNames`) most hit: faces wound the wrong way round, or an inside-out or leaky model.
std::string windingWarning(int64_t rays, int64_t backFaceHits, const std::vector<int64_t>& byLabel,
                           const std::vector<std::string>& labelNames);
/// A notable share, above what correct scenes show: on builtin:rooms, whose tables and shelves
/// have no bottoms, the floor beneath them casts a few rays into their insides; the Cornell box
/// and builtin:city, none.
inline constexpr double kWindingWarningShare = 0.02;

/// The warning, or "" for none, when more than kEscapeWarningShare of the form-factor rays left
/// the scene without hitting anything: then hardly any patch sees another and B is nearly E
/// everywhere, which is what a room or enclosure wound inside out (every face facing away from
/// the inside) gives, with no back face hit to say so.
std::string escapeWarning(int64_t rays, int64_t escapedRays);
/// Far above what scenes worth solving show: builtin:city's open sky lets about half the rays
/// out, a lone floor under a lamp all of them (and the warning is then true: nothing reflects
/// onto anything).
inline constexpr double kEscapeWarningShare = 0.99;

/// The repair line and its warnings (CG not converged, emptied rows, negative entries).
void reportRepair(const Console& console, const solve::RepairReport& repair, double seconds);
/// The thermal balance of F (solve::balanceColumns): sweeps, defects, time.
void reportBalance(const Console& console, const solve::BalanceReport& balance, double seconds);

/// The checkpoint line: file, stage, rows finished of all, file size (`staged`: renamed with the
/// result, not at `path` yet), time. Collective.
void reportCheckpoint(const Console& console, const std::string& path, const char* stage,
                      const std::vector<int64_t>& rowSamples, double seconds, bool staged = false);

/// What a restart takes from its checkpoint: rows as they are, rows given more samples, rows to
/// sample, channels done. Collective.
void reportRestart(const Console& console, const std::string& path, const Checkpoint& saved,
                   int64_t patchCount, int64_t raysPerPatch);

/// The solve lines: solver, iterations, residual, error bound, condition estimate, the work
/// done (unknowns, products with F) and what was left out.
void reportSolve(const Console& console, const solve::Report& report, double seconds);
/// The estimated error of B and H per channel (sampling and discretisation), how the sampling
/// model was scaled, and where the adaptive tolerance stopped.
void reportCalibration(const Console& console, const solve::CalibrationReport& calibration,
                       const solve::DiscretisationReport& discretisation,
                       const solve::Report& report);

}  // namespace radiosity::run
