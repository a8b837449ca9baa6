// Private to io/: what the collective HDF5 writers (the result file and the checkpoint) share.
// Writing a file with parallel HDF5 so that it appears whole or not at all, every rank writing
// its own slab, the ranks agreeing after each step so that none is left waiting in a collective.
#pragma once

#include <hdf5.h>
#include <mpi.h>

// CMakeLists.txt refuses a serial HDF5; this catches a serial hdf5.h reached through some other
// include path, which would otherwise fail later on H5Pset_fapl_mpio.
#ifndef H5_HAVE_PARALLEL
#error "radiosity needs parallel HDF5 (H5_HAVE_PARALLEL): hdf5.h here is a serial build"
#endif

#include <algorithm>
#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "io/store/hdf5_util.h"
#include "io/store/result.h"

namespace radiosity::h5 {

/// Runs a collective write as a sequence of steps; after each one the ranks agree whether all of
/// them succeeded. A rank that failed thus never leaves the others waiting in a collective HDF5
/// call: once a step failed anywhere, every rank skips the rest and holds the same message.
class CollectiveSteps {
 public:
  explicit CollectiveSteps(MPI_Comm comm);

  /// Runs `work` on this rank unless an earlier step failed; true if it succeeded on all ranks.
  /// Collective.
  template <class Work>
  bool run(Work&& work) {
    if (failed_) return false;
    std::string error;
    try {
      work();
    } catch (const std::exception& e) {
      error = e.what()[0] != '\0' ? e.what() : "unknown error";
    }
    return agree(error);
  }

  bool ok() const { return !failed_; }

  /// Once a step fails, further writes to `file` are thrown away on every rank
  /// (discardFurtherWrites, io/store/space_reservation.h): the file is lost, and closing it
  /// must not wait for ever on a rank whose disk fails.
  void discardOnFailure(const std::string& file) { discarded_.push_back(file); }
  /// The lowest failing rank's message, prefixed with "rank N: " when there are several ranks.
  const std::string& error() const { return error_; }

 private:
  bool agree(const std::string& localError);

  MPI_Comm comm_;
  int rank_ = 0;
  int size_ = 1;
  bool failed_ = false;
  std::string error_;
  std::vector<std::string> discarded_;
};

/// Rank 0's value on every rank. Collective.
void broadcast(MPI_Comm comm, std::string& text);
void broadcast(MPI_Comm comm, std::map<std::string, double>& values);
void broadcast(MPI_Comm comm, std::map<std::string, std::string>& values);
/// Rank 0's history, each column at its own length (check it afterwards with checkHistory).
void broadcast(MPI_Comm comm, SolveHistory& history);
void broadcast(MPI_Comm comm, std::vector<int64_t>& values);

/// Throws std::invalid_argument unless `history` can be stored as /solve/history and read back
/// the same: columns of one length, channels 0 to 2, iterations exact in float64.
void checkHistory(const SolveHistory& history);

/// Where this rank's part of a dataset that the ranks fill in rank order goes: the elements of
/// the ranks before it and the total over all ranks (MPI_Exscan and MPI_Allreduce). Collective.
struct Offsets {
  int64_t before = 0;
  int64_t total = 0;
};
Offsets offsetsInRankOrder(MPI_Comm comm, int64_t count);

/// This rank's part of the global CSR row_start array [np + 1] of rows that the ranks hold in
/// rank order: the local starts shifted by `nonzerosBefore`, without the last one except on the
/// last rank (which thus writes row_start[np]).
std::vector<int64_t> globalRowStarts(MPI_Comm comm, const std::vector<int64_t>& localRowStart,
                                     int64_t nonzerosBefore);

/// Rows [rows.first, rows.first + rows.count) of three-value rows (Vec3, Rgb, Triangle) as one
/// row-major array, as writeDataset takes them; rows past the end of `values` are zeros (a part
/// not computed yet, such as B before the solve).
template <class T = double, class Row>
std::vector<T> flattenRows(std::span<const Row> values, Rows rows) {
  std::vector<T> flat(3 * rows.count, T{0});
  const int64_t end = std::min<int64_t>(rows.first + rows.count, values.size());
  for (int64_t i = rows.first; i < end; ++i)
    for (int k = 0; k < 3; ++k) flat[3 * (i - rows.first) + k] = static_cast<T>(values[i][k]);
  return flat;
}
template <class T = double, class Row>
std::vector<T> flattenRows(const std::vector<Row>& values, Rows rows) {
  return flattenRows<T>(std::span<const Row>(values), rows);
}

/// The same rows, all present, as the array's own memory rather than a flattened copy (a row of
/// Vec3, Rgb or Triangle is its three values of type T, without padding): for the large arrays
/// written at the end of a run, whose copies would be its memory peak.
template <class T, class Row>
const void* rowsInPlace(std::span<const Row> values, Rows rows) {
  static_assert(sizeof(Row) == 3 * sizeof(T) && std::is_standard_layout_v<Row>);
  if (rows.first + rows.count > static_cast<int64_t>(values.size()))
    throw std::out_of_range("rowsInPlace: rows past the array");
  return values.data() + rows.first;
}

/// The same with only the first `columns` (1 to 3) values of each row: a thermal run's one
/// channel of its Rgb rows.
template <class Row>
std::vector<double> flattenColumns(const std::vector<Row>& values, Rows rows, int columns) {
  std::vector<double> flat(columns * rows.count, 0.0);
  const int64_t end = std::min<int64_t>(rows.first + rows.count, values.size());
  for (int64_t i = rows.first; i < end; ++i)
    for (int k = 0; k < columns; ++k) flat[columns * (i - rows.first) + k] = values[i][k];
  return flat;
}

/// How a dataset is stored.
enum class Layout {
  kContiguous,  ///< plain, no filter
  /// Chunks of at most kChunkElements values with HDF5's Fletcher32 checksum, which HDF5
  /// verifies on every read of a chunk (a reader reads, and verifies, whole chunks).
  kChecksummedChunks,
};
inline constexpr int64_t kChunkElements = int64_t{1} << 20;

/// A file being written collectively: the file and the collective transfer list for its
/// datasets. `file` is declared first so that it is closed last (an MPI-IO file refuses to close
/// with objects open).
struct ParallelFile {
  Handle file;
  Handle transfer;
};

/// Creates `name`, a fresh temporary, with the MPI-IO driver and a collective transfer list,
/// after rank 0 has reserved `reserveBytes` of disk for it (io/store/space_reservation.h: a full
/// disk or quota fails here, on every rank together, and not inside a collective HDF5 call).
/// HDF5's metadata is written by rank 0 alone, into that space. The file format is HDF5 1.8's
/// at least, whose attributes may be of any size (the older one limits each to 64 kB: long
/// labels or length units). `checksummedMetadata`: the HDF5 1.10 file format, whose superblock,
/// object headers and chunk indexes carry checksums of their own. Once a step fails, the
/// file's further writes are thrown away (CollectiveSteps::discardOnFailure). Collective.
ParallelFile createParallelFile(CollectiveSteps& steps, MPI_Comm comm, const std::string& name,
                                bool checksummedMetadata, int64_t reserveBytes);

/// Once `name` is closed on every rank (steps ok): rank 0 frees the reserved space it did not
/// use. Collective in name only (no communication).
void releaseUnusedSpace(const CollectiveSteps& steps, MPI_Comm comm, const std::string& name);

/// A dataset as writeDataset makes it, the same on every rank: `total` rows of `columns` values
/// (0: a 1-D dataset) stored as `fileType`, written from values of `memoryType`.
struct DatasetSpec {
  std::string name;
  hid_t fileType;
  hid_t memoryType;
  int64_t total;
  int columns;
  Layout layout = Layout::kContiguous;
};

/// Writes the dataset `spec`, of which this rank writes `rows` from `data` (row-major).
/// Collective: every rank calls it with the same spec, and each step ends with the ranks agreeing
/// on success.
void writeDataset(CollectiveSteps& steps, hid_t file, hid_t transfer, const DatasetSpec& spec,
                  Rows rows, const void* data);

/// A 1-D dataset of `total` values, laid out as writeDataset lays them (an empty chunked one
/// extensible), to be written in slabs by writeSlab: for arrays written a piece at a time.
/// Throws Failure.
Handle createVectorDataset(hid_t file, const std::string& name, hid_t fileType, int64_t total,
                           Layout layout);
/// Writes data[0, count) at [first, first + count) of the 1-D `dataset` named `name` (count 0:
/// this rank takes part selecting nothing). Collective. Throws Failure.
void writeSlab(hid_t dataset, const std::string& name, hid_t transfer, hid_t memoryType,
               int64_t first, int64_t count, const void* data);

/// Rows with CSR starts `rowStart` (rowStart[0] = 0) cut into pieces of about `perPiece`
/// entries: the first row of piece p (rows whose first entry is at or after p · perPiece; every
/// row once that is past the last entry). For writes a piece at a time.
int64_t firstRowOfPiece(const std::vector<int64_t>& rowStart, int64_t p, int64_t perPiece);
/// The pieces of `entries` entries at `perPiece` each (at least 1), the most of any rank: the
/// number of collective writes every rank makes. Collective.
int64_t piecesOnEveryRank(MPI_Comm comm, int64_t entries, int64_t perPiece);

/// This rank's rows (CSR starts `rowStart`) a piece of about `perPiece` entries at a time:
/// `write(from, to)` for each piece's rows [from, to), run as a step of `steps`, as many times on
/// every rank (the writes inside are collective); not at all where `total`, the entries of all
/// ranks, is 0. Collective.
template <class Write>
void writePieces(CollectiveSteps& steps, MPI_Comm comm, const std::vector<int64_t>& rowStart,
                 int64_t total, int64_t perPiece, const Write& write) {
  const int64_t pieces = piecesOnEveryRank(comm, rowStart.back(), perPiece);
  for (int64_t p = 0; p < pieces && total > 0; ++p) {
    const int64_t from = firstRowOfPiece(rowStart, p, perPiece),
                  to = firstRowOfPiece(rowStart, p + 1, perPiece);
    steps.run([&] { write(from, to); });
  }
}

/// An attribute of `object` holding `count` values (1: a scalar). Throws Failure.
void writeAttribute(hid_t object, const char* name, hid_t fileType, hid_t memoryType,
                    const void* value, size_t count = 1);
/// A fixed-length UTF-8 string attribute (h5py decodes it to text). Throws Failure.
void writeStringAttribute(hid_t object, const char* name, const std::string& value);
/// A 1-D attribute of fixed-length UTF-8 strings. Throws Failure.
void writeStringArrayAttribute(hid_t object, const char* name,
                               const std::vector<std::string>& values);

/// Creates the group `name` (its parent must exist). Throws Failure.
Handle createGroup(hid_t file, const std::string& name);

/// Writes the dataset `name` (float64 [n, 4]: channel, iteration, residual, seconds) from rank 0's
/// copy, which every rank holds, with its `columns` attribute; its group must exist. Collective.
void writeSolveHistory(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                       const std::string& name, const SolveHistory& history,
                       Layout layout = Layout::kContiguous);

}  // namespace radiosity::h5
