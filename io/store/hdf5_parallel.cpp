#include "io/store/hdf5_parallel.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "io/store/format_names.h"
#include "io/store/space_reservation.h"
#include "parallel/collective.h"

namespace radiosity::h5 {

CollectiveSteps::CollectiveSteps(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm, &rank_);
  MPI_Comm_size(comm, &size_);
}

bool CollectiveSteps::agree(const std::string& localError) {
  const Agreement outcome = agreeOnFailure(comm_, !localError.empty(), 0, localError);
  if (!outcome.failed()) return true;
  error_ = size_ > 1 ? "rank " + std::to_string(outcome.failingRank) + ": " + outcome.message
                     : outcome.message;
  failed_ = true;
  for (const std::string& file : discarded_) discardFurtherWrites(file);
  return false;
}

void broadcast(MPI_Comm comm, std::string& text) {
  uint64_t length = text.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, comm);
  text.resize(length);
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, comm);
}

void broadcast(MPI_Comm comm, std::map<std::string, double>& values) {
  uint64_t count = values.size();
  MPI_Bcast(&count, 1, MPI_UINT64_T, 0, comm);
  std::vector<std::string> names;
  std::vector<double> numbers;
  for (const auto& [name, value] : values) {
    names.push_back(name);
    numbers.push_back(value);
  }
  names.resize(count);
  numbers.resize(count);
  MPI_Bcast(numbers.data(), static_cast<int>(count), MPI_DOUBLE, 0, comm);
  values.clear();
  for (uint64_t i = 0; i < count; ++i) {
    broadcast(comm, names[i]);
    values[names[i]] = numbers[i];
  }
}

void broadcast(MPI_Comm comm, std::map<std::string, std::string>& values) {
  uint64_t count = values.size();
  MPI_Bcast(&count, 1, MPI_UINT64_T, 0, comm);
  std::vector<std::pair<std::string, std::string>> entries(values.begin(), values.end());
  entries.resize(count);
  values.clear();
  for (auto& [name, value] : entries) {
    broadcast(comm, name);
    broadcast(comm, value);
    values[name] = value;
  }
}

void broadcast(MPI_Comm comm, std::vector<int64_t>& values) {
  uint64_t count = values.size();
  MPI_Bcast(&count, 1, MPI_UINT64_T, 0, comm);
  values.resize(count);
  MPI_Bcast(values.data(), static_cast<int>(count), MPI_INT64_T, 0, comm);
}

void broadcast(MPI_Comm comm, SolveHistory& history) {
  uint64_t sizes[4] = {history.channel.size(), history.iteration.size(), history.residual.size(),
                       history.seconds.size()};
  MPI_Bcast(sizes, 4, MPI_UINT64_T, 0, comm);
  history.channel.resize(sizes[0]);
  history.iteration.resize(sizes[1]);
  history.residual.resize(sizes[2]);
  history.seconds.resize(sizes[3]);
  MPI_Bcast(history.channel.data(), static_cast<int>(sizes[0]), MPI_INT, 0, comm);
  MPI_Bcast(history.iteration.data(), static_cast<int>(sizes[1]), MPI_INT64_T, 0, comm);
  MPI_Bcast(history.residual.data(), static_cast<int>(sizes[2]), MPI_DOUBLE, 0, comm);
  MPI_Bcast(history.seconds.data(), static_cast<int>(sizes[3]), MPI_DOUBLE, 0, comm);
}

void checkHistory(const SolveHistory& history) {
  const size_t n = history.size();
  if (history.channel.size() != n || history.iteration.size() != n || history.seconds.size() != n)
    throw std::invalid_argument("solve history has " + std::to_string(history.channel.size()) +
                                " channels, " + std::to_string(history.iteration.size()) +
                                " iterations, " + std::to_string(n) + " residuals and " +
                                std::to_string(history.seconds.size()) + " times");
  constexpr int64_t kLargestExact = int64_t{1} << 53;
  for (size_t i = 0; i < n; ++i) {
    if (history.channel[i] < 0 || history.channel[i] > 2)
      throw std::invalid_argument("solve history entry " + std::to_string(i) + " has channel " +
                                  std::to_string(history.channel[i]) + ", not 0, 1 or 2");
    if (history.iteration[i] < 0 || history.iteration[i] > kLargestExact)
      throw std::invalid_argument("solve history entry " + std::to_string(i) + " has iteration " +
                                  std::to_string(history.iteration[i]) + ", not in [0, 2^53]");
  }
}

std::string temporaryName(MPI_Comm comm, const std::string& path) {
  std::string name;
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) name = temporaryNameFor(path);
  broadcast(comm, name);
  return name;
}

Offsets offsetsInRankOrder(MPI_Comm comm, int64_t count) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Offsets offsets;
  MPI_Exscan(&count, &offsets.before, 1, MPI_INT64_T, MPI_SUM, comm);
  if (rank == 0) offsets.before = 0;  // MPI_Exscan leaves rank 0's result undefined
  MPI_Allreduce(&count, &offsets.total, 1, MPI_INT64_T, MPI_SUM, comm);
  return offsets;
}

std::vector<int64_t> globalRowStarts(MPI_Comm comm, const std::vector<int64_t>& localRowStart,
                                     int64_t nonzerosBefore) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  std::vector<int64_t> starts(localRowStart.begin(),
                              localRowStart.end() - (rank == size - 1 ? 0 : 1));
  for (int64_t& start : starts) start += nonzerosBefore;
  return starts;
}

ParallelFile createParallelFile(CollectiveSteps& steps, MPI_Comm comm, const std::string& name,
                                bool checksummedMetadata, int64_t reserveBytes) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  ParallelFile result;
  Handle access;
  steps.discardOnFailure(name);
  steps.run([&] {
    if (rank == 0) reserveSpace(name, reserveBytes);
  });
  // A step of its own: H5Pset_fapl_mpio duplicates the communicator, a collective call.
  steps.run([&] {
    access = own(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate");
    check(H5Pset_fapl_mpio(access.get(), comm, MPI_INFO_NULL), "H5Pset_fapl_mpio");
    // Metadata written by rank 0 alone, into the space it reserved: HDF5 flushes metadata inside
    // collective calls, and a rank whose share of that write failed would leave the others
    // waiting in them. (Raw data writes fail cleanly on one rank: the next step agrees.)
    check(H5Pset_coll_metadata_write(access.get(), false), "H5Pset_coll_metadata_write");
    H5AC_cache_config_t cache{};
    cache.version = H5AC__CURR_CACHE_CONFIG_VERSION;
    check(H5Pget_mdc_config(access.get(), &cache), "H5Pget_mdc_config");
    cache.metadata_write_strategy = H5AC_METADATA_WRITE_STRATEGY__PROCESS_0_ONLY;
    check(H5Pset_mdc_config(access.get(), &cache), "H5Pset_mdc_config");
    check(H5Pset_libver_bounds(access.get(), checksummedMetadata ? H5F_LIBVER_V110 : H5F_LIBVER_V18,
                               H5F_LIBVER_LATEST),
          "H5Pset_libver_bounds");
    result.transfer = own(H5Pcreate(H5P_DATASET_XFER), "H5Pcreate");
    check(H5Pset_dxpl_mpio(result.transfer.get(), H5FD_MPIO_COLLECTIVE), "H5Pset_dxpl_mpio");
  });
  steps.run([&] {
    // TRUNC of the empty file rank 0 made: MPI-IO truncates only a file of some size, so the
    // reserved blocks stay.
    result.file = own(H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()),
                      "H5Fcreate(" + name + ")");
  });
  return result;
}

void releaseUnusedSpace(const CollectiveSteps& steps, MPI_Comm comm, const std::string& name) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0 && steps.ok()) releaseUnusedSpace(name);
}

void writeDataset(CollectiveSteps& steps, hid_t file, hid_t transfer, const DatasetSpec& spec,
                  Rows rows, const void* data) {
  Handle fileSpace, memorySpace, creation, dataset;
  steps.run([&] {
    const int rank = spec.columns == 0 ? 1 : 2;
    const hsize_t dims[2] = {static_cast<hsize_t>(spec.total), static_cast<hsize_t>(spec.columns)};
    // A chunked dataset needs chunks of at least one row, which an empty one of fixed size
    // cannot hold: it is made extensible instead (the same layout, so read the same way).
    const hsize_t maxDims[2] = {
        spec.layout == Layout::kChecksummedChunks && spec.total == 0 ? H5S_UNLIMITED : dims[0],
        dims[1]};
    fileSpace = own(H5Screate_simple(rank, dims, maxDims), "H5Screate_simple(" + spec.name + ")");
    // A rank without rows still takes part in the collective write, selecting nothing.
    const hsize_t memoryDims[2] = {static_cast<hsize_t>(std::max<int64_t>(rows.count, 1)),
                                   static_cast<hsize_t>(spec.columns)};
    memorySpace =
        own(H5Screate_simple(rank, memoryDims, nullptr), "H5Screate_simple(" + spec.name + ")");
    if (rows.count == 0) {
      check(H5Sselect_none(fileSpace.get()), "H5Sselect_none(" + spec.name + ")");
      check(H5Sselect_none(memorySpace.get()), "H5Sselect_none(" + spec.name + ")");
    } else {
      const hsize_t start[2] = {static_cast<hsize_t>(rows.first), 0};
      check(
          H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, start, nullptr, memoryDims, nullptr),
          "H5Sselect_hyperslab(" + spec.name + ")");
    }
    creation = own(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate(" + spec.name + ")");
    // Every element is written, so filling the dataset first would only double the I/O.
    check(H5Pset_fill_time(creation.get(), H5D_FILL_TIME_NEVER),
          "H5Pset_fill_time(" + spec.name + ")");
    if (spec.layout == Layout::kChecksummedChunks) {
      const int64_t rowsPerChunk = std::max<int64_t>(1, kChunkElements / std::max(spec.columns, 1));
      const hsize_t chunk[2] = {
          static_cast<hsize_t>(std::clamp<int64_t>(spec.total, 1, rowsPerChunk)),
          static_cast<hsize_t>(spec.columns)};
      check(H5Pset_chunk(creation.get(), rank, chunk), "H5Pset_chunk(" + spec.name + ")");
      check(H5Pset_fletcher32(creation.get()), "H5Pset_fletcher32(" + spec.name + ")");
    }
  });
  steps.run([&] {
    dataset = own(H5Dcreate2(file, spec.name.c_str(), spec.fileType, fileSpace.get(), H5P_DEFAULT,
                             creation.get(), H5P_DEFAULT),
                  "H5Dcreate2(" + spec.name + ")");
  });
  steps.run([&] {
    static const double kNothing[3] = {};
    // An empty dataset has no storage to write to (the same decision on every rank).
    if (spec.total > 0)
      check(H5Dwrite(dataset.get(), spec.memoryType, memorySpace.get(), fileSpace.get(), transfer,
                     data != nullptr ? data : kNothing),
            "H5Dwrite(" + spec.name + ")");
    dataset.close("H5Dclose(" + spec.name + ")");
  });
}

Handle createVectorDataset(hid_t file, const std::string& name, hid_t fileType, int64_t total,
                           Layout layout) {
  const hsize_t dims = static_cast<hsize_t>(total);
  const hsize_t maxDims = layout == Layout::kChecksummedChunks && total == 0 ? H5S_UNLIMITED : dims;
  Handle space = own(H5Screate_simple(1, &dims, &maxDims), "H5Screate_simple(" + name + ")");
  Handle creation = own(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate(" + name + ")");
  check(H5Pset_fill_time(creation.get(), H5D_FILL_TIME_NEVER), "H5Pset_fill_time(" + name + ")");
  if (layout == Layout::kChecksummedChunks) {
    const hsize_t chunk = static_cast<hsize_t>(std::clamp<int64_t>(total, 1, kChunkElements));
    check(H5Pset_chunk(creation.get(), 1, &chunk), "H5Pset_chunk(" + name + ")");
    check(H5Pset_fletcher32(creation.get()), "H5Pset_fletcher32(" + name + ")");
  }
  return own(H5Dcreate2(file, name.c_str(), fileType, space.get(), H5P_DEFAULT, creation.get(),
                        H5P_DEFAULT),
             "H5Dcreate2(" + name + ")");
}

void writeSlab(hid_t dataset, const std::string& name, hid_t transfer, hid_t memoryType,
               int64_t first, int64_t count, const void* data) {
  Handle fileSpace = own(H5Dget_space(dataset), "H5Dget_space(" + name + ")");
  const hsize_t n = static_cast<hsize_t>(std::max<int64_t>(count, 1));
  Handle memorySpace = own(H5Screate_simple(1, &n, nullptr), "H5Screate_simple(" + name + ")");
  if (count == 0) {
    check(H5Sselect_none(fileSpace.get()), "H5Sselect_none(" + name + ")");
    check(H5Sselect_none(memorySpace.get()), "H5Sselect_none(" + name + ")");
  } else {
    const hsize_t start = static_cast<hsize_t>(first);
    check(H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, &start, nullptr, &n, nullptr),
          "H5Sselect_hyperslab(" + name + ")");
  }
  static const int64_t kNothing = 0;  // (8 bytes: a double or an int64 selecting nothing)
  check(H5Dwrite(dataset, memoryType, memorySpace.get(), fileSpace.get(), transfer,
                 count > 0 ? data : &kNothing),
        "H5Dwrite(" + name + ")");
}

int64_t firstRowOfPiece(const std::vector<int64_t>& rowStart, int64_t p, int64_t perPiece) {
  const int64_t rows = static_cast<int64_t>(rowStart.size()) - 1;
  const int64_t at = p * perPiece;
  if (at >= rowStart.back()) return p == 0 ? 0 : rows;
  return std::lower_bound(rowStart.begin(), rowStart.end() - 1, at) - rowStart.begin();
}

int64_t piecesOnEveryRank(MPI_Comm comm, int64_t entries, int64_t perPiece) {
  int64_t pieces = std::max<int64_t>(1, (entries + perPiece - 1) / perPiece);
  MPI_Allreduce(MPI_IN_PLACE, &pieces, 1, MPI_INT64_T, MPI_MAX, comm);
  return pieces;
}

void writeAttribute(hid_t object, const char* name, hid_t fileType, hid_t memoryType,
                    const void* value, size_t count) {
  const std::string what = std::string("attribute ") + name;
  const hsize_t dims = count;
  Handle space = count == 1 ? own(H5Screate(H5S_SCALAR), "H5Screate(" + what + ")")
                            : own(H5Screate_simple(1, &dims, nullptr), "H5Screate(" + what + ")");
  Handle attribute = own(H5Acreate2(object, name, fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                         "H5Acreate2(" + what + ")");
  check(H5Awrite(attribute.get(), memoryType, value), "H5Awrite(" + what + ")");
  attribute.close("H5Aclose(" + what + ")");
}

void writeStringAttribute(hid_t object, const char* name, const std::string& value) {
  // Fixed length (HDF5 refuses size 0), UTF-8 so that readers such as h5py decode it to text.
  Handle type = own(H5Tcopy(H5T_C_S1), "H5Tcopy");
  check(H5Tset_size(type.get(), std::max<size_t>(value.size(), 1)), "H5Tset_size");
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "H5Tset_strpad");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "H5Tset_cset");
  std::string padded = value;
  padded.resize(std::max<size_t>(value.size(), 1), '\0');
  writeAttribute(object, name, type.get(), type.get(), padded.data());
}

void writeStringArrayAttribute(hid_t object, const char* name,
                               const std::vector<std::string>& values) {
  const std::string what = std::string("attribute ") + name;
  size_t width = 1;
  for (const std::string& value : values) width = std::max(width, value.size());
  std::string buffer;
  for (const std::string& value : values) {
    buffer += value;
    buffer.append(width - value.size(), '\0');
  }
  Handle type = own(H5Tcopy(H5T_C_S1), "H5Tcopy");
  check(H5Tset_size(type.get(), width), "H5Tset_size");
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "H5Tset_strpad");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "H5Tset_cset");
  const hsize_t count = values.size();
  Handle space = own(H5Screate_simple(1, &count, nullptr), "H5Screate_simple(" + what + ")");
  Handle attribute =
      own(H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
          "H5Acreate2(" + what + ")");
  check(H5Awrite(attribute.get(), type.get(), buffer.data()), "H5Awrite(" + what + ")");
  attribute.close("H5Aclose(" + what + ")");
}

Handle createGroup(hid_t file, const std::string& name) {
  return own(H5Gcreate2(file, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             "H5Gcreate2(" + name + ")");
}

void writeSolveHistory(CollectiveSteps& steps, MPI_Comm comm, hid_t file, hid_t transfer,
                       const std::string& name, const SolveHistory& history, Layout layout) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const auto n = static_cast<int64_t>(history.size());
  if (steps.ok()) {
    std::vector<double> rows;
    rows.reserve(4 * history.size());
    for (size_t i = 0; i < history.size(); ++i)
      rows.insert(rows.end(), {static_cast<double>(history.channel[i]),
                               static_cast<double>(history.iteration[i]), history.residual[i],
                               history.seconds[i]});
    writeDataset(steps, file, transfer, {name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, n, 4, layout},
                 Rows{0, rank == 0 ? n : 0}, rows.data());
  }
  Handle dataset;
  steps.run([&] {
    dataset = own(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
    writeStringArrayAttribute(
        dataset.get(), format_names::attribute::kColumns,
        {format_names::kHistoryColumns.begin(), format_names::kHistoryColumns.end()});
    dataset.close("H5Dclose(" + name + ")");
  });
}

}  // namespace radiosity::h5
