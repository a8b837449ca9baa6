#include "io/store/mesh_broadcast.h"

#include <algorithm>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "io/store/hdf5_parallel.h"

namespace radiosity {

namespace {

// MPI counts are int: a large array goes in pieces of at most 1 GiB.
void broadcastBytes(MPI_Comm comm, void* data, size_t bytes) {
  constexpr size_t kPiece = size_t{1} << 30;
  char* at = static_cast<char*>(data);
  for (size_t done = 0; done < bytes; done += kPiece) {
    const int count = static_cast<int>(std::min(kPiece, bytes - done));
    MPI_Bcast(at + done, count, MPI_BYTE, 0, comm);
  }
}

template <class T>
void broadcastVector(MPI_Comm comm, std::vector<T>& values) {
  static_assert(std::is_trivially_copyable_v<T>);
  uint64_t count = values.size();
  MPI_Bcast(&count, 1, MPI_UINT64_T, 0, comm);
  values.resize(count);
  broadcastBytes(comm, values.data(), count * sizeof(T));
}

// Packed as their lengths and their bytes: two broadcasts, however many strings.
void broadcastStrings(MPI_Comm comm, std::vector<std::string>& strings) {
  std::vector<uint64_t> lengths;
  std::vector<char> bytes;
  for (const std::string& s : strings) {
    lengths.push_back(s.size());
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  broadcastVector(comm, lengths);
  broadcastVector(comm, bytes);
  strings.clear();
  size_t at = 0;
  for (uint64_t length : lengths) {
    strings.emplace_back(bytes.data() + at, length);
    at += length;
  }
}

}  // namespace

void broadcastMesh(MPI_Comm comm, Mesh& mesh) {
  broadcastVector(comm, mesh.vertices);
  broadcastVector(comm, mesh.triangles);
  broadcastVector(comm, mesh.sourceFace);
  broadcastVector(comm, mesh.reflectance);
  broadcastVector(comm, mesh.emission);
  broadcastVector(comm, mesh.label);
  broadcastVector(comm, mesh.labelEmissivity);
  broadcastStrings(comm, mesh.labelNames);
  broadcastStrings(comm, mesh.warnings);
  broadcastStrings(comm, mesh.sourceFiles);
  h5::broadcast(comm, mesh.lengthUnit);
}

}  // namespace radiosity
