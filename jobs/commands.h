// The subcommands of the `radiosity` program and the settings each reads. Options are declared
// and validated in one place (command_line.cpp); each command is a function of its settings.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "formfactor/estimator.h"
#include "render/render.h"
#include "run/console.h"
#include "run/run.h"
#include "solve/solver.h"

namespace radiosity::jobs {

struct RenderSettings {
  std::string input;
  std::string output;
  int width = 512, height = 512;
  std::vector<double> eye, lookAt, up;  ///< empty, or x,y,z
  double fov = 40;
  double exposure = 0;
  bool flat = false;
  render::FalseColour falseColour = render::FalseColour::kNone;
  render::Scale scale = render::Scale::kAuto;
};

/// `radiosity study`: the error of B and H against a reference, and the run time, over a sweep
/// of settings (jobs/study/study_command.cpp).
struct StudySettings {
  std::string scene;
  std::string output;     ///< CSV, a row per setting
  std::string plot;       ///< SVG; empty: none
  std::string reference;  ///< a result file of the same scene and mesh; empty: exact
  std::vector<int64_t> rays{16, 32, 64, 128, 256, 512, 1024};
  std::vector<formfactor::Estimator> estimators = valuesIn(formfactor::kEstimatorNames);
  std::vector<double> rtols{1e-10};
  std::vector<double> maxAreas;  ///< empty: the solve's automatic bound
  solve::Solver solver = solve::Solver::kGmres;
  uint64_t seed = 1;
  int threads = 1;
  bool quiet = false;
};

/// `radiosity verify`: an independent path-traced reference of patch-averaged B on a random
/// sample of a result's patches, and the measured error of the result (jobs/verify_command.cpp).
struct VerifySettings {
  std::string input;           ///< result file (HDF5)
  int64_t patches = 200;       ///< patches sampled (reflecting ones), at most all of them
  int64_t paths = 16384;       ///< paths per sampled patch
  double tol = 0.05;           ///< exit 1 when the measured RMS relative error of B exceeds this
  int64_t maxBounces = 10000;  ///< a reference path is cut after this many bounces (counted)
  uint64_t seed = 1;
  int threads = 1;
  std::string csv;  ///< per sampled patch: the result's and the reference's B and their errors
};

/// `radiosity xdmf`: the XDMF sidecar of a result file (io/store/xdmf.h).
struct XdmfSettings {
  std::string input;   ///< result file (HDF5)
  std::string output;  ///< default: the result's name with .xmf
};

struct SceneSettings {
  std::string name;
  std::string output;
};

/// `radiosity export`: a result's group view factors and groups as text for other tools
/// (io/store/result_tables.h); at least one output.
struct ExportSettings {
  std::string input;            ///< result file (HDF5)
  std::string viewFactors;      ///< View3D's text layout, or CSV when the name ends in .csv
  std::string groupsCsv;        ///< a row per group
  std::string exchangeFactors;  ///< a thermal result's Gebhart factors, CSV, a row per pair
};

int runRender(const RenderSettings& settings, const run::Console& console);
int runInfo(const std::string& path, const run::Console& console);
int runScene(const SceneSettings& settings, const run::Console& console);
int runStudy(const StudySettings& settings, const run::Console& console);
int runXdmf(const XdmfSettings& settings, const run::Console& console);
int runVerify(const VerifySettings& settings, const run::Console& console);
int runExport(const ExportSettings& settings, const run::Console& console);

/// Parses the program's own arguments (PETSc's were taken out before) and runs the chosen
/// command. Returns the exit code; every rank returns the same.
/// `petscWords`: the words main() set aside for PETSc (one dash and a letter); one that spells
/// an option of ours with one dash (`-rays 16`) is refused (exit 2), as PETSc would ignore it.
int runCommandLine(const std::vector<std::string>& arguments, const run::Console& console,
                   const std::vector<std::string>& petscWords = {});

}  // namespace radiosity::jobs
