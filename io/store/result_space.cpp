#include "io/store/result_space.h"

#include <algorithm>
#include <string>

#include "io/store/space_reservation.h"

namespace radiosity {

int64_t resultSpace(MPI_Comm comm, const Mesh& patches, const ResultAttributes& a,
                    const FormFactorOutput& formFactors) {
  const int64_t np = patches.triangleCount();
  const int64_t nv = static_cast<int64_t>(patches.vertices.size());
  int64_t nonzeros = formFactors.rows != nullptr ? formFactors.rows->nonzeros() : 0;
  if (formFactors.store != nullptr) nonzeros = formFactors.store->tallyRowStart().back();
  MPI_Allreduce(MPI_IN_PLACE, &nonzeros, 1, MPI_INT64_T, MPI_SUM, comm);
  h5::SpaceEstimate space;
  space.dataset(nv, 3, 8);
  // /mesh/triangles, /patches/{normal, reflectance, emission, radiosity, irradiance, stderr,
  // discretisation}, /display/triangles: [np, 3] of 8 bytes
  for (int k = 0; k < 9; ++k) space.dataset(np, 3, 8);
  // /patches/{area, hidden, source_face, group, rank}
  for (int k = 0; k < 5; ++k) space.dataset(np, 0, 8);
  // /display/{vertices, radiosity}: at most three per patch; luminance_tonemapped, one value each
  for (int k = 0; k < 2; ++k) space.dataset(3 * np, 3, 8);
  space.dataset(3 * np, 0, 8);
  space.dataset(np + 1, 0, 8);
  space.dataset(nonzeros, 0, 8);
  space.dataset(nonzeros, 0, 8);
  space.dataset(static_cast<int64_t>(formFactors.rowSumHistogram.size()), 0, 8);
  space.dataset(static_cast<int64_t>(formFactors.rowSumBinEdges.size()), 0, 8);
  const auto groups = static_cast<int64_t>(formFactors.groups.names.size());
  space.dataset(groups, 0, 8);
  space.dataset(groups, static_cast<int>(groups), 8);
  if (!formFactors.groups.factorError.empty()) space.dataset(groups, static_cast<int>(groups), 8);
  size_t width = 1;
  for (const std::string& name : formFactors.groups.names) width = std::max(width, name.size());
  space.text(width * static_cast<size_t>(groups));
  space.dataset(static_cast<int64_t>(a.history.size()), 4, 8);
  // Every dataset's units and description; the length unit is in several of them.
  space.text(a.lengthUnit.size() + 64, 8);
  space.text(4096, 32);
  for (const std::string* text : {&a.solver, &a.leftOut, &a.scene, &a.options, &a.solverChoice})
    space.text(text->size());
  for (const auto& [name, version] : a.software) space.text(name.size() + version.size());
  space.text(64, static_cast<int>(a.stageSeconds.size() + a.solveFigures.size()));
  int64_t bytes = space.bytes();
  MPI_Bcast(&bytes, 1, MPI_INT64_T, 0, comm);
  return bytes;
}

}  // namespace radiosity
