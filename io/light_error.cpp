#include "io/light_error.h"

#include <cmath>

namespace radiosity {

std::array<double, 3> reflectingMean(MPI_Comm comm, const std::vector<double>& area,
                                     const std::vector<Rgb>& reflectance,
                                     const std::vector<Rgb>& value) {
  double sums[6] = {0, 0, 0, 0, 0, 0};  // Σ A B and Σ A per channel
  for (size_t i = 0; i < area.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (reflectance[i][c] <= 0) continue;
      sums[c] += area[i] * value[i][c];
      sums[3 + c] += area[i];
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 6, MPI_DOUBLE, MPI_SUM, comm);
  std::array<double, 3> mean{};
  for (int c = 0; c < 3; ++c) mean[c] = sums[3 + c] > 0 ? sums[c] / sums[3 + c] : 0.0;
  return mean;
}

std::array<double, 3> relativeLightError(MPI_Comm comm, const std::vector<double>& area,
                                         const std::vector<Rgb>& reflectance,
                                         const std::vector<Rgb>& value,
                                         const std::vector<Rgb>& error) {
  const std::array<double, 3> mean = reflectingMean(comm, area, reflectance, value);
  double sums[6] = {0, 0, 0, 0, 0, 0};  // Σ A (e/B)² and Σ A per channel
  for (size_t i = 0; i < area.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (reflectance[i][c] <= 0) continue;
      const double relative =
          relativeToFloor(std::abs(error[i][c]), value[i][c], kLightErrorFloorShare * mean[c]);
      sums[c] += area[i] * relative * relative;
      sums[3 + c] += area[i];
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 6, MPI_DOUBLE, MPI_SUM, comm);
  std::array<double, 3> rms{};
  for (int c = 0; c < 3; ++c) rms[c] = sums[3 + c] > 0 ? std::sqrt(sums[c] / sums[3 + c]) : 0.0;
  return rms;
}

}  // namespace radiosity
