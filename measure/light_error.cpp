#include "measure/light_error.h"

#include <algorithm>
#include <cmath>

namespace radiosity {

std::array<double, 3> reflectingMean(MPI_Comm comm, const std::vector<double>& area,
                                     const std::vector<Rgb>& reflectance,
                                     const std::vector<Rgb>& value) {
  // Sums of values and areas scaled by their largest magnitudes, so that scenes at 1e±150 and
  // emission near the largest double neither overflow nor underflow.
  double largest[4] = {0, 0, 0, 0};  // |value| per channel, area
  for (size_t i = 0; i < area.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (reflectance[i][c] <= 0 || value[i][c] == 0) continue;
      largest[c] = std::max(largest[c], std::abs(value[i][c]));
      largest[3] = std::max(largest[3], area[i]);
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, largest, 4, MPI_DOUBLE, MPI_MAX, comm);
  double sums[6] = {0, 0, 0, 0, 0, 0};  // Σ A B and Σ A per channel, scaled
  for (size_t i = 0; i < area.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (reflectance[i][c] <= 0 || value[i][c] == 0 || !(largest[3] > 0)) continue;
      const double a = area[i] / largest[3];
      sums[c] += largest[c] > 0 ? a * (value[i][c] / largest[c]) : 0.0;
      sums[3 + c] += a;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 6, MPI_DOUBLE, MPI_SUM, comm);
  std::array<double, 3> mean{};
  for (int c = 0; c < 3; ++c)
    mean[c] = sums[3 + c] > 0 ? largest[c] * (sums[c] / sums[3 + c]) : 0.0;
  return mean;
}

std::array<double, 3> relativeLightError(MPI_Comm comm, const std::vector<double>& area,
                                         const std::vector<Rgb>& reflectance,
                                         const std::vector<Rgb>& value,
                                         const std::vector<Rgb>& error) {
  const std::array<double, 3> mean = reflectingMean(comm, area, reflectance, value);
  double largestArea = 0;
  for (double a : area) largestArea = std::max(largestArea, a);
  MPI_Allreduce(MPI_IN_PLACE, &largestArea, 1, MPI_DOUBLE, MPI_MAX, comm);
  if (!(largestArea > 0)) largestArea = 1;
  double sums[6] = {0, 0, 0, 0, 0, 0};  // Σ A (e/B)² and Σ A per channel (areas scaled)
  for (size_t i = 0; i < area.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      if (reflectance[i][c] <= 0 || (value[i][c] == 0 && error[i][c] == 0)) continue;
      const double relative =
          relativeToFloor(std::abs(error[i][c]), value[i][c], kLightErrorFloorShare * mean[c]);
      sums[c] += area[i] / largestArea * relative * relative;
      sums[3 + c] += area[i] / largestArea;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sums, 6, MPI_DOUBLE, MPI_SUM, comm);
  std::array<double, 3> rms{};
  for (int c = 0; c < 3; ++c) rms[c] = sums[3 + c] > 0 ? std::sqrt(sums[c] / sums[3 + c]) : 0.0;
  return rms;
}

}  // namespace radiosity
