// Reads a result file and prints what bench/stability.sh tabulates, as one line of
// tab-separated numbers:
//   iterations  solve-seconds  residual  error  error-bound  matrix-products
// where error is
//   --exact V:        max over patches and channels of |B − V| / |V|
//   --reference REF:  max over patches and channels of |B − B_ref| / max |B_ref|
//                     (REF a result file of the same scene and mesh)
//   --power-balance R: |Σ A_i B_i / (Σ A_i E_i / (1 − R)) − 1| over each channel (largest):
//                     exact for a closed scene of uniform ρ = R with a reciprocal F
// and the other figures are the result's attributes (time_solve, solve_error_bound,
// solve_matrix_products). Serial; needs no MPI launcher.
// Usage: build/bench/result_error RESULT.h5 (--exact VALUE | --reference REF.h5 |
//                                            --power-balance RHO)
// Exit codes: 0 ok, 2 usage, 3 unreadable or mismatched files.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "core/vec3.h"
#include "io/store/result.h"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: result_error RESULT.h5 (--exact VALUE | --reference REF.h5 | "
               "--power-balance RHO)\n");
  return 2;
}

double figure(const std::map<std::string, double>& figures, const std::string& key) {
  const auto it = figures.find(key);
  return it == figures.end() ? std::nan("") : it->second;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace radiosity;
  if (argc != 4) return usage();
  const std::string path = argv[1], mode = argv[2], value = argv[3];
  if (mode != "--exact" && mode != "--reference" && mode != "--power-balance") return usage();
  try {
    const Result result = readResult(path);
    double error = 0;
    if (mode == "--exact") {
      char* end = nullptr;
      const double exact = std::strtod(value.c_str(), &end);
      if (end == value.c_str() || *end != '\0' || !std::isfinite(exact) || exact == 0) {
        std::fprintf(stderr, "result_error: --exact needs a finite nonzero number, not '%s'\n",
                     value.c_str());
        return 2;
      }
      for (const Rgb& b : result.radiosity) {
        for (double c : b) {
          const double e = std::abs(c - exact) / std::abs(exact);
          error = std::isnan(e) ? e : std::max(error, e);
          if (std::isnan(error)) break;
        }
      }
    } else if (mode == "--power-balance") {
      const double rho = std::strtod(value.c_str(), nullptr);
      if (!(rho >= 0 && rho < 1)) return usage();
      for (int c = 0; c < 3; ++c) {
        double reflected = 0, emitted = 0;
        for (size_t i = 0; i < result.area.size(); ++i) {
          reflected += result.area[i] * result.radiosity[i][c];
          emitted += result.area[i] * result.mesh.emission[i][c];
        }
        if (emitted > 0) error = std::max(error, std::abs(reflected / (emitted / (1 - rho)) - 1));
      }
    } else {
      const Result reference = readResult(value);
      if (reference.radiosity.size() != result.radiosity.size()) {
        std::fprintf(stderr, "result_error: %s has %zu patches, the reference %s has %zu\n",
                     path.c_str(), result.radiosity.size(), value.c_str(),
                     reference.radiosity.size());
        return 3;
      }
      double scale = 0, difference = 0;
      for (size_t i = 0; i < reference.radiosity.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
          scale = std::max(scale, std::abs(reference.radiosity[i][c]));
          const double d = std::abs(result.radiosity[i][c] - reference.radiosity[i][c]);
          difference = std::isnan(d) ? d : std::max(difference, d);
        }
      }
      error = difference / scale;
    }
    const ResultAttributes& a = result.attributes;
    std::printf("%lld\t%.6g\t%.6g\t%.6g\t%.6g\t%.0f\n", static_cast<long long>(a.iterations),
                figure(a.stageSeconds, "solve"), a.residual, error,
                figure(a.solveFigures, "error_bound"), figure(a.solveFigures, "matrix_products"));
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "result_error: %s\n", e.what());
    return 3;
  }
}
