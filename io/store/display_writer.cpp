#include "io/store/display_writer.h"

#include <cstdint>
#include <string>
#include <vector>

#include "core/corner_radiosity.h"
#include "io/store/result_format.h"

namespace radiosity {

namespace {

// Every rank's B on rank 0, in patch order (ranks own consecutive blocks); empty elsewhere.
std::vector<Rgb> gatherRadiosity(MPI_Comm comm, const LocalSolution& local, int64_t patchCount) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  // Counted in whole patches (three doubles each), so MPI's int counts reach 2^31 patches.
  MPI_Datatype rgb;
  MPI_Type_contiguous(3, MPI_DOUBLE, &rgb);
  MPI_Type_commit(&rgb);
  const int mine = static_cast<int>(local.radiosity.size());
  std::vector<int> counts(size), offsets(size, 0);
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int r = 1; r < size; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<Rgb> all(rank == 0 ? patchCount : 0);
  MPI_Gatherv(local.radiosity.data(), mine, rgb, all.data(), counts.data(), offsets.data(), rgb, 0,
              comm);
  MPI_Type_free(&rgb);
  return all;
}

// Every rank's hidden flags on rank 0, in patch order; empty elsewhere, and empty when no rank
// has any (LocalSolution::hidden).
std::vector<uint8_t> gatherHidden(MPI_Comm comm, const LocalSolution& local, int64_t patchCount) {
  int rank = 0, size = 1, any = local.hidden.empty() ? 0 : 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, comm);
  if (!any) return {};
  std::vector<uint8_t> mine = local.hidden;
  mine.resize(local.radiosity.size(), 0);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(size), offsets(size, 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int r = 1; r < size; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<uint8_t> all(rank == 0 ? patchCount : 0);
  MPI_Gatherv(mine.data(), count, MPI_UINT8_T, all.data(), counts.data(), offsets.data(),
              MPI_UINT8_T, 0, comm);
  return all;
}

}  // namespace

void writeDisplayMesh(h5::CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                      const Mesh& patches, const LocalSolution& local) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const int64_t np = patches.triangleCount();
  // Beyond MPI's int counts there is no display mesh (the sidecar then shows cell data); the
  // result itself is not lost for it.
  if (np > INT32_MAX) return;
  const std::vector<Rgb> radiosity = gatherRadiosity(comm, local, np);
  const std::vector<uint8_t> hidden = gatherHidden(comm, local, np);
  DisplayMesh display;
  steps.run([&] {
    if (rank != 0) return;
    CornerRadiosity corners;
    {  // (the normals and areas go before the display mesh is built)
      std::vector<Vec3> normal(np);
      std::vector<double> area(np);
      for (int64_t t = 0; t < np; ++t) {
        normal[t] = patches.normal(t);
        area[t] = patches.area(t);
      }
      // The renderer's surfaces, so that ParaView shows what `radiosity render` shows.
      corners = cornerRadiosity(patches, normal, area, radiosity,
                                setApart(materialSurfaces(patches), hidden));
    }
    display = displayMesh(patches, corners);
  });
  if (!steps.ok()) return;
  int64_t nd = static_cast<int64_t>(display.vertices.size());
  MPI_Bcast(&nd, 1, MPI_INT64_T, 0, comm);
  h5::Handle group;
  steps.run([&] { group = h5::createGroup(file, result_format::kDisplay); });
  const h5::Rows vertexRows{0, rank == 0 ? nd : 0}, patchRows{0, rank == 0 ? np : 0};
  if (steps.ok()) {
    const std::vector<double> values = h5::flattenRows(display.vertices, vertexRows);
    h5::writeDataset(steps, file, transfer, result_format::kDisplayVertices, H5T_IEEE_F64LE,
                     H5T_NATIVE_DOUBLE, nd, 3, vertexRows, values.data());
  }
  if (steps.ok()) {
    const std::vector<int64_t> values = h5::flattenRows<int64_t>(display.triangles, patchRows);
    h5::writeDataset(steps, file, transfer, result_format::kDisplayTriangles, H5T_STD_I64LE,
                     H5T_NATIVE_INT64, np, 3, patchRows, values.data());
  }
  if (steps.ok()) {
    const std::vector<double> values = h5::flattenRows(display.radiosity, vertexRows);
    h5::writeDataset(steps, file, transfer, result_format::kDisplayRadiosity, H5T_IEEE_F64LE,
                     H5T_NATIVE_DOUBLE, nd, 3, vertexRows, values.data());
  }
  steps.run([&] { group.close(std::string("H5Gclose(") + result_format::kDisplay + ")"); });
}

}  // namespace radiosity
