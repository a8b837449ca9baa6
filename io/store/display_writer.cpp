#include "io/store/display_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/channels.h"
#include "core/corner_radiosity.h"
#include "io/store/result_format.h"
#include "partition/owner_queries.h"

namespace radiosity {

namespace {

// Every rank's hidden flags on every rank, in patch order; empty when no rank has any
// (LocalSolution::hidden).
std::vector<uint8_t> gatherHidden(MPI_Comm comm, const LocalSolution& local, int64_t patchCount) {
  int size = 1, any = local.hidden.empty() ? 0 : 1;
  MPI_Comm_size(comm, &size);
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, comm);
  if (!any) return {};
  std::vector<uint8_t> mine = local.hidden;
  mine.resize(local.radiosity.size(), 0);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(size), offsets(size, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < size; ++r) offsets[r] = offsets[r - 1] + counts[r - 1];
  std::vector<uint8_t> all(patchCount);
  MPI_Allgatherv(mine.data(), count, MPI_UINT8_T, all.data(), counts.data(), offsets.data(),
                 MPI_UINT8_T, comm);
  return all;
}

// The patches of the chunks whose first patch this rank owns.
partition::PatchRange chunksOf(partition::PatchRange owned, int64_t patchCount) {
  if (owned.size() == 0) return {0, 0};
  auto firstChunkFrom = [](int64_t p) { return (p + kDisplayChunk - 1) / kDisplayChunk; };
  const int64_t begin = firstChunkFrom(owned.begin) * kDisplayChunk;
  const int64_t end = std::min(patchCount, firstChunkFrom(owned.end) * kDisplayChunk);
  return begin < end ? partition::PatchRange{begin, end} : partition::PatchRange{0, 0};
}

// Per chunk, the sums of the tone map's midpoint: Σ A log Y and Σ A over the patches that reflect
// and do not emit (the walls), then over every patch with light; Y the patch's luminance, hidden
// patches and black ones left out.
constexpr int kMidpointSums = 4;

void addMidpointSums(const Mesh& patches, const PatchValues& radiosity,
                     const std::vector<uint8_t>& hidden, int64_t from, int64_t to, double* sums) {
  for (int64_t p = from; p < to; ++p) {
    if (!hidden.empty() && hidden[p]) continue;
    const double y = luminance(radiosity[p]);
    if (!(y > 0)) continue;
    const double area = patches.area(p), weighted = area * std::log(y);
    sums[2] += weighted;
    sums[3] += area;
    const Rgb& rho = patches.reflectance[p];
    if (patches.emission[p] == Rgb{0, 0, 0} && std::max({rho[0], rho[1], rho[2]}) > 0) {
      sums[0] += weighted;
      sums[1] += area;
    }
  }
}

// The luminance /display/luminance_tonemapped shows as 0.5: the area-weighted geometric mean of
// the walls' luminance (else of every patch with light; 1 in a black scene). `chunkSums` holds
// kMidpointSums per display chunk, zero but for this rank's chunks; the chunks' sums are added in
// chunk order, so the midpoint is the same bits on any number of ranks. Collective.
double tonemapMidpoint(MPI_Comm comm, std::vector<double> chunkSums) {
  MPI_Allreduce(MPI_IN_PLACE, chunkSums.data(), static_cast<int>(chunkSums.size()), MPI_DOUBLE,
                MPI_SUM, comm);  // exact: one rank's value and zeros
  double total[kMidpointSums] = {0, 0, 0, 0};
  for (size_t k = 0; k < chunkSums.size(); ++k) total[k % kMidpointSums] += chunkSums[k];
  if (total[1] > 0) return std::exp(total[0] / total[1]);
  if (total[3] > 0) return std::exp(total[2] / total[3]);
  return 1;
}

// What this rank builds of the display mesh: its chunks (chunksOf); their triangles, the
// vertices numbered from 0 in chunk order; B at each vertex; and with the tone map, the midpoint
// sums of every chunk (kMidpointSums a chunk, zero but for this rank's).
struct RankDisplay {
  partition::PatchRange chunks;
  DisplayMesh mesh;
  std::vector<double> midpointSums;
};

// This rank's part of the display mesh, with B of its chunks' neighbours from the ranks owning
// them. Collective; failures end in `steps`.
RankDisplay buildRankDisplay(h5::CollectiveSteps& steps, MPI_Comm comm, const Mesh& patches,
                             const LocalSolution& local, bool tonemapped) {
  const int64_t np = patches.triangleCount();
  const partition::PatchRange owned{
      local.firstPatch, local.firstPatch + static_cast<int64_t>(local.radiosity.size())};
  RankDisplay part;
  const partition::PatchRange mine = part.chunks = chunksOf(owned, np);
  const std::vector<uint8_t> hidden = gatherHidden(comm, local, np);
  SurfaceIds surfaces;
  std::unique_ptr<CornerAverages> corners;
  std::vector<int64_t> others;  // patches whose B this rank's chunks read from their owners
  steps.run([&] {
    // The renderer's surfaces, so that ParaView shows what `radiosity render` shows.
    surfaces = setApart(materialSurfaces(patches), hidden);
    corners = std::make_unique<CornerAverages>(patches, surfaces, mine.begin, mine.end);
    others = corners->neighboursOutside();
    for (int64_t p = mine.begin; p < mine.end; ++p)
      if (!owned.contains(p)) others.push_back(p);
    others.erase(
        std::remove_if(others.begin(), others.end(), [&](int64_t p) { return owned.contains(p); }),
        others.end());
    std::sort(others.begin(), others.end());
  });
  if (!steps.ok()) return part;
  struct Question {
    int64_t patch;
  };
  std::vector<Question> questions(others.size());
  for (size_t k = 0; k < others.size(); ++k) questions[k].patch = others[k];
  std::vector<Rgb> answers = partition::askOwners<Rgb>(
      comm, partition::RankBlocks(comm, owned), questions,
      [&](const Question& q) { return local.radiosity[q.patch - owned.begin]; });
  questions = {};
  DisplayMesh& display = part.mesh;
  std::vector<double>& chunkSums = part.midpointSums;
  chunkSums.assign(tonemapped ? kMidpointSums * ((np + kDisplayChunk - 1) / kDisplayChunk) : 0,
                   0.0);
  steps.run([&] {
    const PatchValues radiosity(owned.begin, local.radiosity, std::move(others),
                                std::move(answers));
    for (int64_t from = mine.begin; from < mine.end; from += kDisplayChunk) {
      const int64_t to = std::min(mine.end, from + kDisplayChunk);
      if (tonemapped)
        addMidpointSums(patches, radiosity, hidden, from, to,
                        &chunkSums[kMidpointSums * (from / kDisplayChunk)]);
      DisplayMesh chunk = corners->displayMesh(radiosity, from, to);
      const auto shift = static_cast<int64_t>(display.vertices.size());
      for (Triangle& t : chunk.triangles)
        for (int64_t& v : t) v += shift;
      display.vertices.insert(display.vertices.end(), chunk.vertices.begin(), chunk.vertices.end());
      display.radiosity.insert(display.radiosity.end(), chunk.radiosity.begin(),
                               chunk.radiosity.end());
      display.triangles.insert(display.triangles.end(), chunk.triangles.begin(),
                               chunk.triangles.end());
    }
  });
  return part;
}

}  // namespace

void writeDisplayMesh(h5::CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                      const Mesh& patches, const LocalSolution& local, int channels) {
  const int64_t np = patches.triangleCount();
  // Beyond MPI's int counts there is no display mesh (the sidecar then shows cell data); the
  // result itself is not lost for it.
  if (np > INT32_MAX) return;
  const bool tonemapped = channels == 3;  // (a thermal run's one channel is shown as it is)
  RankDisplay part = buildRankDisplay(steps, comm, patches, local, tonemapped);
  if (!steps.ok()) return;
  const partition::PatchRange mine = part.chunks;
  DisplayMesh& display = part.mesh;
  const double midpoint = tonemapped ? tonemapMidpoint(comm, std::move(part.midpointSums)) : 0;
  // The ranks' vertices one after another, in chunk order.
  const auto count = static_cast<int64_t>(display.vertices.size());
  int64_t first = 0, nd = 0;
  MPI_Exscan(&count, &first, 1, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(&count, &nd, 1, MPI_INT64_T, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) first = 0;  // (MPI_Exscan leaves rank 0's undefined)
  for (Triangle& t : display.triangles)
    for (int64_t& v : t) v += first;
  h5::Handle group;
  steps.run([&] { group = h5::createGroup(file, result_format::kDisplay); });
  const h5::Rows vertexRows{first, count}, patchRows{mine.begin, mine.size()};
  // (the arrays in place, without copies: the end of a run is near its memory peak)
  h5::writeDataset(steps, file, transfer,
                   {result_format::kDisplayVertices, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nd, 3},
                   vertexRows,
                   h5::rowsInPlace<double>(std::span<const Vec3>(display.vertices), {0, count}));
  h5::writeDataset(
      steps, file, transfer,
      {result_format::kDisplayTriangles, H5T_STD_I64LE, H5T_NATIVE_INT64, np, 3}, patchRows,
      h5::rowsInPlace<int64_t>(std::span<const Triangle>(display.triangles), {0, mine.size()}));
  if (steps.ok()) {
    const std::vector<double> values = h5::flattenColumns(display.radiosity, {0, count}, channels);
    h5::writeDataset(
        steps, file, transfer,
        {result_format::kDisplayRadiosity, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nd, channels},
        vertexRows, values.data());
  }
  // One number per vertex that a colour map shows well: the light, often a hundred times the
  // walls, would leave the walls one colour on a linear scale of B or Y.
  if (steps.ok() && tonemapped) {
    std::vector<double> values(count);
    for (int64_t v = 0; v < count; ++v) {
      const double y = std::max(0.0, luminance(display.radiosity[v]));
      values[v] = y / (y + midpoint);
    }
    h5::writeDataset(steps, file, transfer,
                     {result_format::kDisplayTonemapped, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nd, 0},
                     vertexRows, values.data());
    steps.run([&] {  // (metadata: every rank writes the same)
      const h5::Handle dataset =
          h5::own(H5Dopen2(file, result_format::kDisplayTonemapped, H5P_DEFAULT),
                  std::string("H5Dopen2(") + result_format::kDisplayTonemapped + ")");
      h5::writeAttribute(dataset.get(), result_format::attribute::kMidpoint, H5T_IEEE_F64LE,
                         H5T_NATIVE_DOUBLE, &midpoint);
    });
  }
  steps.run([&] { group.close(std::string("H5Gclose(") + result_format::kDisplay + ")"); });
}

}  // namespace radiosity
