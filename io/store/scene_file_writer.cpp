// Writes the HDF5 scene file (io/store/scene_file_format.h) with parallel HDF5: every rank holds
// the whole mesh and writes one slab of each dataset. The file is written under a temporary name
// and renamed once complete, so `path` holds a whole scene or is left alone.
#include <climits>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "io/store/collective_outputs.h"
#include "io/store/hdf5_parallel.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/result_labels.h"
#include "io/store/scene_file.h"
#include "io/store/scene_file_format.h"
#include "io/store/space_reservation.h"

namespace radiosity {
namespace {

namespace format = scene_format;
using h5::CollectiveSteps;
using h5::Rows;

/// The distinct (ρ, E, label) of the mesh in order of first use, and each triangle's row.
struct MaterialTable {
  std::vector<Rgb> reflectance, emission;
  std::vector<int32_t> label;       ///< empty when the mesh has no labels
  std::vector<int32_t> ofTriangle;  ///< [nt]
};

/// A material by its bits, so that -0 and 0 stay apart and the file gives back what was written.
struct MaterialKey {
  uint64_t bits[6];
  int32_t label;
  bool operator==(const MaterialKey& other) const {
    return label == other.label && std::memcmp(bits, other.bits, sizeof bits) == 0;
  }
};

struct MaterialKeyHash {
  size_t operator()(const MaterialKey& key) const {
    uint64_t h = 0x9E3779B97F4A7C15ULL ^ static_cast<uint32_t>(key.label);
    for (uint64_t b : key.bits) h = (h ^ b) * 0x100000001B3ULL + (h >> 29);
    return static_cast<size_t>(h);
  }
};

/// Throws std::invalid_argument (a mesh no loader makes) when the per-triangle arrays differ in
/// size or a label is out of range.
MaterialTable materialTable(const Mesh& mesh) {
  const size_t nt = mesh.triangles.size();
  if (mesh.sourceFace.size() != nt || mesh.reflectance.size() != nt || mesh.emission.size() != nt)
    throw std::invalid_argument("mesh has " + std::to_string(nt) + " triangles but " +
                                std::to_string(mesh.sourceFace.size()) + " source faces, " +
                                std::to_string(mesh.reflectance.size()) + " reflectances and " +
                                std::to_string(mesh.emission.size()) + " emissions");
  const bool labelled = mesh.hasLabels();
  MaterialTable table;
  table.ofTriangle.resize(nt);
  std::unordered_map<MaterialKey, int32_t, MaterialKeyHash> rowOf;
  for (size_t t = 0; t < nt; ++t) {
    MaterialKey key{};
    std::memcpy(&key.bits[0], mesh.reflectance[t].data(), 3 * sizeof(double));
    std::memcpy(&key.bits[3], mesh.emission[t].data(), 3 * sizeof(double));
    key.label = labelled ? mesh.label[t] : -1;
    if (labelled && (key.label < 0 || static_cast<size_t>(key.label) >= mesh.labelNames.size()))
      throw std::invalid_argument("triangle " + std::to_string(t) + " has label " +
                                  std::to_string(key.label) + " of " +
                                  std::to_string(mesh.labelNames.size()));
    auto [it, added] = rowOf.emplace(key, static_cast<int32_t>(table.reflectance.size()));
    if (added) {
      if (table.reflectance.size() == static_cast<size_t>(INT32_MAX))
        throw std::invalid_argument("more than 2^31 - 1 distinct materials");
      table.reflectance.push_back(mesh.reflectance[t]);
      table.emission.push_back(mesh.emission[t]);
      if (labelled) table.label.push_back(key.label);
    }
    table.ofTriangle[t] = it->second;
  }
  return table;
}

/// This rank's share of `total` rows: the ranks take consecutive blocks in rank order.
Rows slabOf(int64_t total, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int64_t first = total * rank / size;
  return Rows{first, total * (rank + 1) / size - first};
}

/// The `units` and `description` of every dataset, so that the file explains itself.
struct DatasetLabel {
  const char* name;
  const char* units;  ///< nullptr: the length unit
  const char* description;
};

constexpr DatasetLabel kLabels[] = {
    {format::kVertices, nullptr, "vertex positions x, y, z"},
    {format::kTriangles, "index",
     "the three vertices of each triangle (0-based rows of /mesh/vertices), counter-clockwise "
     "seen from the lit side"},
    {format::kMaterial, "index", "the material of each triangle: a row of /materials"},
    {format::kSourceFace, "index",
     "0-based index of the face of the original scene (file order) the triangle came from"},
    {format::kReflectance, "1", "diffuse reflectance rho per channel (red, green, blue)"},
    {format::kEmission, "the scene's unit of exitance (e.g. W/m^2)",
     "emitted exitance E per channel"},
    {format::kLabel, "index", "the label of each material: a row of /labels/name"},
    {format::kLabelName, "text",
     "what a surface is called in messages: material and group, or the built-in scene's surface"},
};

void labelDatasets(CollectiveSteps& steps, hid_t file, const std::string& lengthUnit) {
  const std::string length =
      lengthUnit.empty() ? std::string("the scene's length unit (not stated)") : lengthUnit;
  for (const DatasetLabel& label : kLabels) {
    const std::string units = label.units != nullptr ? label.units : length;
    steps.run([&] { labelDataset(file, label.name, units, label.description); });
  }
}

void writeRootAttributes(hid_t file, const Mesh& mesh, const SceneFileAttributes& attributes) {
  namespace attribute = scene_format::attribute;
  const int formatVersion = format::kFormatVersion;
  h5::writeStringAttribute(file, attribute::kKind, format::kKind);
  h5::writeAttribute(file, attribute::kFormatVersion, H5T_STD_I32LE, H5T_NATIVE_INT,
                     &formatVersion);
  if (!mesh.lengthUnit.empty())
    h5::writeStringAttribute(file, attribute::kLengthUnit, mesh.lengthUnit);
  h5::writeStringAttribute(file, attribute::kSource, attributes.source);
  for (const auto& [name, version] : attributes.software)
    h5::writeStringAttribute(file, (attribute::kSoftwarePrefix + name).c_str(), version);
}

/// /labels/name: fixed-length UTF-8 strings as wide as the longest name. Collective.
void writeLabelNames(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                     const std::vector<std::string>& names) {
  size_t width = 1;
  for (const std::string& name : names) width = std::max(width, name.size());
  const auto count = static_cast<int64_t>(names.size());
  const Rows mine = slabOf(count, comm);
  std::string buffer;
  for (int64_t i = mine.first; i < mine.first + mine.count; ++i) {
    buffer += names[i];
    buffer.append(width - names[i].size(), '\0');
  }
  h5::Handle type;
  steps.run([&] {
    type = h5::own(H5Tcopy(H5T_C_S1), "H5Tcopy");
    h5::check(H5Tset_size(type.get(), width), "H5Tset_size");
    h5::check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "H5Tset_strpad");
    h5::check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "H5Tset_cset");
  });
  if (!steps.ok()) return;
  h5::writeDataset(steps, file, transfer, {format::kLabelName, type.get(), type.get(), count, 0},
                   mine, buffer.data());
}

/// At most the bytes of the file writeFile writes (io/store/space_reservation.h); every rank
/// holds the whole mesh, so it is the same on every rank.
int64_t sceneSpace(const Mesh& mesh, const MaterialTable& table,
                   const SceneFileAttributes& attributes) {
  const int64_t nt = mesh.triangleCount();
  const auto nm = static_cast<int64_t>(table.reflectance.size());
  h5::SpaceEstimate space;
  space.dataset(static_cast<int64_t>(mesh.vertices.size()), 3, 8);
  space.dataset(nt, 3, 8);
  space.dataset(nt, 0, 4);
  space.dataset(nt, 0, 8);
  space.dataset(nm, 3, 8);
  space.dataset(nm, 3, 8);
  space.dataset(nm, 0, 4);
  size_t width = 1;
  for (const std::string& name : mesh.labelNames) width = std::max(width, name.size());
  space.dataset(static_cast<int64_t>(mesh.labelNames.size()), 0, width);
  space.text(mesh.lengthUnit.size() + 64, 4);
  space.text(4096, 16);
  space.text(attributes.source.size());
  for (const auto& [name, version] : attributes.software) space.text(name.size() + version.size());
  return space.bytes();
}

/// Creates `temporary` and writes everything into it; every HDF5 handle is closed on return.
/// Collective.
void writeFile(CollectiveSteps& steps, MPI_Comm comm, const std::string& temporary,
               const Mesh& mesh, const MaterialTable& table, const SceneFileAttributes& attributes,
               int64_t reserveBytes) {
  const int64_t nv = static_cast<int64_t>(mesh.vertices.size());
  const int64_t nt = mesh.triangleCount();
  const int64_t nm = static_cast<int64_t>(table.reflectance.size());
  const Rows vertexRows = slabOf(nv, comm), triangleRows = slabOf(nt, comm),
             materialRows = slabOf(nm, comm);

  // Declared first so that it is closed last: an MPI-IO file refuses to close with objects open.
  h5::ParallelFile parallel =
      h5::createParallelFile(steps, comm, temporary, /*checksummedMetadata=*/false, reserveBytes);
  const hid_t f = parallel.file.get(), x = parallel.transfer.get();
  {
    h5::Handle groups[3];
    const bool labelled = !table.label.empty();
    steps.run([&] {
      const char* names[3] = {format::kMesh, format::kMaterials, format::kLabels};
      for (int g = 0; g < (labelled ? 3 : 2); ++g)
        groups[g] = h5::own(H5Gcreate2(f, names[g], H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                            std::string("H5Gcreate2(") + names[g] + ")");
    });
    // Each buffer lives only while its dataset is written, to keep the peak memory low.
    if (steps.ok()) {
      const std::vector<double> flat = h5::flattenRows(mesh.vertices, vertexRows);
      h5::writeDataset(steps, f, x, {format::kVertices, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nv, 3},
                       vertexRows, flat.data());
    }
    if (steps.ok()) {
      const std::vector<int64_t> flat = h5::flattenRows<int64_t>(mesh.triangles, triangleRows);
      h5::writeDataset(steps, f, x, {format::kTriangles, H5T_STD_I64LE, H5T_NATIVE_INT64, nt, 3},
                       triangleRows, flat.data());
    }
    if (steps.ok())
      h5::writeDataset(steps, f, x, {format::kMaterial, H5T_STD_I32LE, H5T_NATIVE_INT32, nt, 0},
                       triangleRows, table.ofTriangle.data() + triangleRows.first);
    if (steps.ok())
      h5::writeDataset(steps, f, x, {format::kSourceFace, H5T_STD_I64LE, H5T_NATIVE_INT64, nt, 0},
                       triangleRows, mesh.sourceFace.data() + triangleRows.first);
    if (steps.ok()) {
      const std::vector<double> flat = h5::flattenRows(table.reflectance, materialRows);
      h5::writeDataset(steps, f, x,
                       {format::kReflectance, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nm, 3},
                       materialRows, flat.data());
    }
    if (steps.ok()) {
      const std::vector<double> flat = h5::flattenRows(table.emission, materialRows);
      h5::writeDataset(steps, f, x, {format::kEmission, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, nm, 3},
                       materialRows, flat.data());
    }
    if (labelled) {
      if (steps.ok())
        h5::writeDataset(steps, f, x, {format::kLabel, H5T_STD_I32LE, H5T_NATIVE_INT32, nm, 0},
                         materialRows, table.label.data() + materialRows.first);
      if (steps.ok()) writeLabelNames(steps, comm, f, x, mesh.labelNames);
    }
    steps.run([&] { writeRootAttributes(f, mesh, attributes); });
    labelDatasets(steps, f, mesh.lengthUnit);
    steps.run([&] {
      for (h5::Handle& group : groups) group.close("H5Gclose");
    });
  }
  // Closing is where the remaining metadata reach the disk, so its failure counts.
  steps.run([&] { parallel.file.close("H5Fclose(" + temporary + ")"); });
  h5::releaseUnusedSpace(steps, comm, temporary);
}

/// The same sizes on every rank, or std::invalid_argument on all. Collective.
void checkSameEverywhere(CollectiveSteps& steps, MPI_Comm comm, const Mesh& mesh,
                         const MaterialTable& table) {
  int64_t mine[4] = {static_cast<int64_t>(mesh.vertices.size()), mesh.triangleCount(),
                     static_cast<int64_t>(table.reflectance.size()),
                     static_cast<int64_t>(mesh.labelNames.size())};
  int64_t low[4], high[4];
  MPI_Allreduce(mine, low, 4, MPI_INT64_T, MPI_MIN, comm);
  MPI_Allreduce(mine, high, 4, MPI_INT64_T, MPI_MAX, comm);
  steps.run([&] {
    for (int k = 0; k < 4; ++k)
      if (low[k] != high[k])
        throw std::invalid_argument(
            "the ranks hold different meshes (vertices, triangles, materials or labels)");
  });
}

}  // namespace

void writeSceneFile(MPI_Comm comm, const std::string& path, const Mesh& mesh,
                    const SceneFileAttributes& attributes) {
  h5::QuietErrors quiet;
  CollectiveSteps steps(comm);
  const std::string cannot = "cannot write scene file " + path + ": ";
  MaterialTable table;
  steps.run([&] { table = materialTable(mesh); });
  if (!steps.ok()) throw Error(exit_code::kFailure, cannot + steps.error());
  checkSameEverywhere(steps, comm, mesh, table);
  if (!steps.ok()) throw Error(exit_code::kFailure, cannot + steps.error());
  // HDF5 needs the same attributes on every rank: rank 0's are written.
  SceneFileAttributes shared = attributes;
  h5::broadcast(comm, shared.source);
  h5::broadcast(comm, shared.software);

  CollectiveOutputs outputs(comm);
  const int64_t reserveBytes = sceneSpace(mesh, table, shared);
  const std::string temporary = outputs.stage(path);
  writeFile(steps, comm, temporary, mesh, table, shared, reserveBytes);
  if (!steps.ok()) {
    outputs.unstage(path);
    throw Error(exit_code::kFailure, cannot + steps.error());
  }
  outputs.commit();
}

}  // namespace radiosity
