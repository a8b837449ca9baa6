// Reads the HDF5 scene file (io/store/scene_file_format.h) on every rank of a communicator with
// parallel HDF5, checks it as the other loaders check theirs, and gives every rank the whole mesh.
//
// Every rank reads a slab of each large dataset (vertices, triangles and the per-triangle
// columns) in one collective read, checks its slab, and the slabs are combined with
// MPI_Allgatherv; the small tables (materials, labels) every rank reads whole. After each step
// the ranks agree, so a rank that found a problem never leaves the others waiting in a
// collective: every rank throws the InputError of the lowest failing rank, which names the file,
// the dataset, the row and the problem (the rows' checks: scene_file_checks.h).
#include <mpi.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.h"
#include "core/mesh.h"
#include "io/scene/scene.h"
#include "io/store/hdf5_parallel.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/mesh_broadcast.h"
#include "io/store/scene_file.h"
#include "io/store/scene_file_checks.h"
#include "io/store/scene_file_format.h"
#include "parallel/collective.h"

namespace radiosity {
namespace {

namespace format = scene_format;
using h5::fail;
using scene_file_checks::checkIndices;
using scene_file_checks::checkMaterials;
using scene_file_checks::checkTriangles;
using scene_file_checks::checkVertices;
using scene_file_checks::rowOf;

static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_standard_layout_v<Vec3>,
              "vertices are read straight into Mesh::vertices");
static_assert(sizeof(Triangle) == 3 * sizeof(int64_t), "triangles are read straight in");
static_assert(sizeof(Rgb) == 3 * sizeof(double), "materials are read straight in");

/// Runs `work` on every rank; if it failed anywhere, every rank throws the error of the lowest
/// failing rank, as an InputError where it was one (runCollectively keeps only the exit code).
/// Collective.
void together(MPI_Comm comm, const std::function<void()>& work) {
  try {
    runCollectively(comm, work);
  } catch (const InputError&) {
    throw;
  } catch (const Error& e) {
    if (e.exitCode() == exit_code::kBadInput) throw InputError(e.what());
    throw;
  }
}

/// `read()`, with HDF5's own failures (a truncated or damaged file) as an InputError naming
/// `what`: the file is the input, so a read that fails is bad input.
template <class Read>
auto guarded(const std::string& path, const std::string& what, Read&& read) {
  try {
    return read();
  } catch (const h5::Failure& e) {
    fail(path, "cannot read " + what + " (" + e.what() + ")");
  }
}

/// This rank's share of `total` rows: consecutive blocks in rank order.
h5::Rows slabOf(int64_t total, int rank, int size) {
  const int64_t first = total * rank / size;
  return h5::Rows{first, total * (rank + 1) / size - first};
}

/// The open file with the collective transfer list, and its datasets (closed before it).
struct OpenScene {
  h5::ParallelFile file;
  h5::OpenDataset vertices, triangles, material, sourceFace, reflectance, emission, label;
  bool withSourceFace = false, withLabels = false;
  int64_t nv = -1, nt = -1, nm = -1, nl = -1;
  std::string lengthUnit;
};

/// Root attributes: kind, format_version, length_unit. InputError unless a scene of a version
/// this program reads.
void readRootAttributes(OpenScene& scene, const std::string& path) {
  const hid_t f = scene.file.file.get();
  const std::string makeOne = "; `radiosity scene SCENE -o FILE.h5` makes one";
  if (h5::check(H5Aexists(f, format::attribute::kKind), "H5Aexists(kind)") <= 0)
    fail(path, std::string("not a scene file (an HDF5 file without the root attribute kind = \"") +
                   format::kKind + "\"" + makeOne + ")");
  const std::string kind = h5::readAttribute<std::string>(f, path, format::attribute::kKind);
  if (kind != format::kKind)
    fail(path, "not a scene file (kind = \"" + kind + "\", not \"" + format::kKind + "\"" +
                   makeOne + ")");
  const int64_t version = h5::readAttribute<int64_t>(f, path, format::attribute::kFormatVersion);
  if (version < 1 || version > format::kFormatVersion)
    fail(path, "scene format_version " + std::to_string(version) +
                   " is not one this program reads (1 to " +
                   std::to_string(format::kFormatVersion) + ")");
  if (h5::check(H5Aexists(f, format::attribute::kLengthUnit), "H5Aexists(length_unit)") > 0)
    scene.lengthUnit = h5::readAttribute<std::string>(f, path, format::attribute::kLengthUnit);
}

/// Opens every dataset and checks its type and shape against the others'.
void openDatasets(OpenScene& scene, const std::string& path) {
  const hid_t f = scene.file.file.get();
  scene.vertices = h5::openDataset(f, path, format::kVertices, H5T_NATIVE_DOUBLE, 3, scene.nv);
  scene.triangles = h5::openDataset(f, path, format::kTriangles, H5T_NATIVE_INT64, 3, scene.nt);
  scene.material = h5::openDataset(f, path, format::kMaterial, H5T_NATIVE_INT32, 0, scene.nt);
  scene.withSourceFace = h5::exists(f, format::kSourceFace);
  if (scene.withSourceFace)
    scene.sourceFace = h5::openDataset(f, path, format::kSourceFace, H5T_NATIVE_INT64, 0, scene.nt);
  scene.reflectance =
      h5::openDataset(f, path, format::kReflectance, H5T_NATIVE_DOUBLE, 3, scene.nm);
  scene.emission = h5::openDataset(f, path, format::kEmission, H5T_NATIVE_DOUBLE, 3, scene.nm);
  scene.withLabels = h5::exists(f, format::kLabel);
  const bool withNames = h5::exists(f, format::kLabelName);
  if (scene.withLabels != withNames)
    fail(path, std::string("dataset ") + (withNames ? format::kLabelName : format::kLabel) +
                   " without " + (withNames ? format::kLabel : format::kLabelName) +
                   " (labels need both)");
  if (scene.withLabels)
    scene.label = h5::openDataset(f, path, format::kLabel, H5T_NATIVE_INT32, 0, scene.nm);
}

/// /labels/name whole: fixed-length or variable-length strings, [nl]. Serial, on this rank.
std::vector<std::string> readLabelNames(hid_t file, const std::string& path) {
  const std::string name = format::kLabelName;
  h5::Handle dataset = h5::own(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
  h5::Handle type = h5::own(H5Dget_type(dataset.get()), "H5Dget_type(" + name + ")");
  h5::Handle space = h5::own(H5Dget_space(dataset.get()), "H5Dget_space(" + name + ")");
  if (H5Tget_class(type.get()) != H5T_STRING)
    fail(path, "dataset " + name + " holds " + h5::typeName(type.get()) + ", expected strings");
  const std::vector<hsize_t> dims = h5::shapeOf(space.get());
  if (dims.size() != 1)
    fail(path, "dataset " + name + " has shape " + h5::shapeText(dims) + ", expected [n]");
  h5::checkStored(dataset.get(), space.get(), path, name);
  const size_t count = dims[0];
  std::vector<std::string> names(count);
  if (count == 0) return names;
  if (h5::check(H5Tis_variable_str(type.get()), "H5Tis_variable_str(" + name + ")") > 0) {
    h5::Handle memory = h5::own(H5Tcopy(H5T_C_S1), "H5Tcopy");
    h5::check(H5Tset_size(memory.get(), H5T_VARIABLE), "H5Tset_size");
    // The file's character set (h5py writes UTF-8): HDF5 converts between none of them.
    h5::check(H5Tset_cset(memory.get(), H5Tget_cset(type.get())), "H5Tset_cset");
    std::vector<char*> values(count, nullptr);
    h5::check(H5Dread(dataset.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
              "H5Dread(" + name + ")");
    for (size_t i = 0; i < count; ++i) names[i] = values[i] != nullptr ? values[i] : "";
    H5Dvlen_reclaim(memory.get(), space.get(), H5P_DEFAULT, values.data());
    return names;
  }
  const size_t width = H5Tget_size(type.get());
  h5::Handle memory = h5::own(H5Tcopy(type.get()), "H5Tcopy");
  std::string buffer(count * width, '\0');
  h5::check(H5Dread(dataset.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()),
            "H5Dread(" + name + ")");
  const bool spacePadded = H5Tget_strpad(type.get()) == H5T_STR_SPACEPAD;
  for (size_t i = 0; i < count; ++i) {
    std::string text = buffer.substr(i * width, width);
    text.resize(std::min(text.size(), text.find('\0')));
    if (spacePadded) text.erase(text.find_last_not_of(' ') + 1);
    names[i] = std::move(text);
  }
  return names;
}

/// MPI's datatype for T.
template <class T>
MPI_Datatype mpiType() {
  if constexpr (std::is_same_v<T, double>) {
    return MPI_DOUBLE;
  } else if constexpr (std::is_same_v<T, int64_t>) {
    return MPI_INT64_T;
  } else {
    static_assert(std::is_same_v<T, int32_t>);
    return MPI_INT32_T;
  }
}

void checkMpi(int status, const std::string& call) {
  if (status == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(status, text, &length);
  throw Error(exit_code::kFailure, call + ": " + std::string(text, length));
}

/// Gives every rank rows [0, rows) of `all` from the ranks' slabs (slabOf) in place. Collective.
void gatherSlabs(MPI_Comm comm, void* all, int64_t rows, int width, MPI_Datatype element) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<int> counts(size), starts(size);
  for (int r = 0; r < size; ++r) {
    const h5::Rows slab = slabOf(rows, r, size);
    counts[r] = static_cast<int>(slab.count);
    starts[r] = static_cast<int>(slab.first);
  }
  MPI_Datatype row;
  checkMpi(MPI_Type_contiguous(width, element, &row), "MPI_Type_contiguous");
  checkMpi(MPI_Type_commit(&row), "MPI_Type_commit");
  const int status = MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, all, counts.data(),
                                    starts.data(), row, comm);
  MPI_Type_free(&row);
  checkMpi(status, "MPI_Allgatherv");
}

/// One of the scene's open datasets to read (`name` in messages), `width` values of `memoryType` a
/// row.
struct DatasetToRead {
  const h5::OpenDataset& open;
  std::string name;
  hid_t memoryType;
  int width = 1;
};

/// Reads `dataset` (`rows` rows of `width` values T) into `all` on every rank and checks it:
/// each rank reads its slab in one collective read and checks it with `check(first, count,
/// slab)`, which throws InputError on a bad row; the ranks agree, then MPI_Allgatherv fills in
/// the other ranks' slabs. (Every rank reading every row collectively, which needs no exchange
/// of its own, was slower: docs/scaling.md.) Collective.
template <class T, class Check>
void readLarge(MPI_Comm comm, const OpenScene& scene, const std::string& path,
               const DatasetToRead& dataset, T* all, Check&& check) {
  const h5::OpenDataset& open = dataset.open;
  const std::string& name = dataset.name;
  const int width = dataset.width;
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int64_t rows = open.rows;
  const h5::Rows mine = slabOf(rows, rank, size);
  // MPI counts and displacements are int (in rows here).
  if (rows > INT_MAX)
    together(comm, [&] { fail(path, "dataset " + name + " has more than 2^31 - 1 rows"); });
  together(comm, [&] {
    guarded(path, "dataset " + name, [&] {
      h5::readRows(open, path, name, dataset.memoryType, {mine.first, mine.count},
                   all + mine.first * width, scene.file.transfer.get());
    });
    check(mine.first, mine.count, all + mine.first * width);
  });
  if (rows > 0) gatherSlabs(comm, all, rows, width, mpiType<T>());
}

/// Reads a small dataset whole on every rank (collectively), then `check` on all its rows.
template <class T, class Check>
void readSmall(MPI_Comm comm, const OpenScene& scene, const std::string& path,
               const DatasetToRead& dataset, T* all, Check&& check) {
  const h5::OpenDataset& open = dataset.open;
  together(comm, [&] {
    guarded(path, "dataset " + dataset.name, [&] {
      h5::readRows(open, path, dataset.name, dataset.memoryType, {0, open.rows}, all,
                   scene.file.transfer.get());
    });
    check(0, open.rows, all);
  });
}

/// Everything read and checked; `scene` is closed on return. Collective.
Mesh readOpenScene(MPI_Comm comm, OpenScene& scene, const std::string& path) {
  Mesh mesh;
  mesh.lengthUnit = scene.lengthUnit;
  mesh.vertices.resize(scene.nv);
  readLarge(comm, scene, path, {scene.vertices, format::kVertices, H5T_NATIVE_DOUBLE, 3},
            reinterpret_cast<double*>(mesh.vertices.data()),
            [&](int64_t first, int64_t count, const double* rows) {
              checkVertices(path, first, count, reinterpret_cast<const Vec3*>(rows));
            });
  mesh.triangles.resize(scene.nt);
  readLarge(comm, scene, path, {scene.triangles, format::kTriangles, H5T_NATIVE_INT64, 3},
            reinterpret_cast<int64_t*>(mesh.triangles.data()),
            [&](int64_t first, int64_t count, const int64_t* rows) {
              checkTriangles(path, first, count, reinterpret_cast<const Triangle*>(rows), scene.nv);
            });
  mesh.sourceFace.resize(scene.nt);
  if (scene.withSourceFace) {
    readLarge(comm, scene, path, {scene.sourceFace, format::kSourceFace, H5T_NATIVE_INT64, 1},
              mesh.sourceFace.data(), [&](int64_t first, int64_t count, const int64_t* rows) {
                for (int64_t i = 0; i < count; ++i)
                  if (rows[i] < 0)
                    fail(path, rowOf(format::kSourceFace, first + i) + " holds " +
                                   std::to_string(rows[i]) + " (must be >= 0)");
              });
  } else {
    for (int64_t t = 0; t < scene.nt; ++t) mesh.sourceFace[t] = t;  // each triangle its own face
  }

  // The material table, then each triangle's row of it.
  std::vector<Rgb> reflectance(scene.nm), emission(scene.nm);
  std::vector<int32_t> labelOf(scene.withLabels ? scene.nm : 0);
  readSmall(comm, scene, path, {scene.reflectance, format::kReflectance, H5T_NATIVE_DOUBLE},
            reinterpret_cast<double*>(reflectance.data()), [](int64_t, int64_t, const double*) {});
  readSmall(comm, scene, path, {scene.emission, format::kEmission, H5T_NATIVE_DOUBLE},
            reinterpret_cast<double*>(emission.data()),
            [&](int64_t, int64_t, const double*) { checkMaterials(path, reflectance, emission); });
  if (scene.withLabels) {
    together(comm, [&] {
      guarded(path, std::string("dataset ") + format::kLabelName,
              [&] { mesh.labelNames = readLabelNames(scene.file.file.get(), path); });
    });
    readSmall(comm, scene, path, {scene.label, format::kLabel, H5T_NATIVE_INT32}, labelOf.data(),
              [&](int64_t first, int64_t count, const int32_t* rows) {
                checkIndices(path, format::kLabel, first, count, rows,
                             static_cast<int64_t>(mesh.labelNames.size()), format::kLabelName);
              });
  }
  std::vector<int32_t> material(scene.nt);
  readLarge(comm, scene, path, {scene.material, format::kMaterial, H5T_NATIVE_INT32, 1},
            material.data(), [&](int64_t first, int64_t count, const int32_t* rows) {
              checkIndices(path, format::kMaterial, first, count, rows, scene.nm,
                           format::kMaterials);
            });

  // Closed before the mesh is built: the file is no longer needed, and closing is collective.
  together(comm, [&] {
    for (h5::OpenDataset* open :
         {&scene.vertices, &scene.triangles, &scene.material, &scene.sourceFace, &scene.reflectance,
          &scene.emission, &scene.label}) {
      open->space.close("H5Sclose");
      open->dataset.close("H5Dclose");
    }
    guarded(path, "the file", [&] { scene.file.file.close("H5Fclose(" + path + ")"); });
  });

  mesh.reflectance.resize(scene.nt);
  mesh.emission.resize(scene.nt);
  if (scene.withLabels) mesh.label.resize(scene.nt);
  for (int64_t t = 0; t < scene.nt; ++t) {
    const int32_t m = material[t];
    mesh.reflectance[t] = reflectance[m];
    mesh.emission[t] = emission[m];
    if (scene.withLabels) mesh.label[t] = labelOf[m];
  }
  return mesh;
}

/// What validateScene does beyond the checks made while reading, split over the ranks: finding
/// degenerate (or too small) triangles, which validateScene itself then drops (with its warning) or
/// refuses on every rank if there are any, and refusing an empty scene. Collective.
void dropDegenerates(MPI_Comm comm, Mesh& mesh, const std::string& path) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const h5::Rows mine = slabOf(mesh.triangleCount(), rank, size);
  int64_t degenerate = 0;
  for (int64_t t = mine.first; t < mine.first + mine.count; ++t)
    if (isDegenerate(mesh, t) || !(mesh.area(t) >= kMinArea)) ++degenerate;
  checkMpi(MPI_Allreduce(MPI_IN_PLACE, &degenerate, 1, MPI_INT64_T, MPI_SUM, comm),
           "MPI_Allreduce");
  double across = 0, distance = 0;  // (every rank holds the whole mesh: one answer on each)
  if (degenerate > 0 || mesh.triangleCount() == 0 ||
      untraceableTriangle(mesh, across, distance) >= 0)
    together(comm, [&] { validateScene(mesh, path); });
}

}  // namespace

Mesh readSceneFile(MPI_Comm comm, const std::string& path) {
  h5::QuietErrors quiet;
  together(comm, [&] { h5::checkHdf5File(path, "scene file"); });
  OpenScene scene;
  h5::Handle access;
  together(comm, [&] {
    guarded(path, "the file", [&] {
      access = h5::own(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate");
      h5::check(H5Pset_fapl_mpio(access.get(), comm, MPI_INFO_NULL), "H5Pset_fapl_mpio");
      scene.file.transfer = h5::own(H5Pcreate(H5P_DATASET_XFER), "H5Pcreate");
      h5::check(H5Pset_dxpl_mpio(scene.file.transfer.get(), H5FD_MPIO_COLLECTIVE),
                "H5Pset_dxpl_mpio");
    });
  });
  // Opening is collective: every rank got here.
  together(comm, [&] {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, access.get());
    if (file < 0) fail(path, "cannot open (" + h5::takeErrorText() + ")");
    scene.file.file = h5::Handle(file);
    h5::requireSelfContained(file, path);
  });
  together(comm, [&] {
    guarded(path, "the root attributes", [&] { readRootAttributes(scene, path); });
    guarded(path, "the datasets", [&] { openDatasets(scene, path); });
  });
  Mesh mesh = readOpenScene(comm, scene, path);
  dropDegenerates(comm, mesh, path);
  mesh.sourceFiles = {path};
  return mesh;
}

Mesh loadScene(const std::string& spec, MPI_Comm comm) {
  if (isHdf5Scene(spec)) return readSceneFile(comm, spec);
  Mesh mesh;
  int size = 1, rank = 0;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  if (size == 1 || spec.starts_with("builtin:")) {  // built alike on every rank
    together(comm, [&] { mesh = loadScene(spec); });
    return mesh;
  }
  // A text scene is read by rank 0 alone and broadcast: ranks reading it each on their own could
  // read different files (one replaced meanwhile) and then wait in different collectives.
  together(comm, [&] {
    if (rank == 0) mesh = loadScene(spec);
  });
  broadcastMesh(comm, mesh);
  return mesh;
}

}  // namespace radiosity
