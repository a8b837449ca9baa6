#include "io/store/space_reservation.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace radiosity::h5 {

namespace {

// HDF5's object header, dataspace, datatype, layout and attribute messages of a dataset, with
// the room an object header continuation wastes.
constexpr double kPerDataset = 16 << 10;
constexpr double kPerChunk = 256;  ///< chunk index entry, checksum
constexpr double kPerText = 1 << 10;

std::string megabytes(int64_t bytes) {
  char text[40];
  std::snprintf(text, sizeof text, "%.3g MB", static_cast<double>(bytes) / 1e6);
  return text;
}

}  // namespace

int64_t SpaceEstimate::bytes() const {
  // An eighth more, for what HDF5 allocates that no count above foresees.
  return bytes_ + bytes_ / 8;
}

void SpaceEstimate::add(double bytes) {
  constexpr double kMost = static_cast<double>(std::numeric_limits<int64_t>::max() / 2);
  bytes_ = static_cast<int64_t>(std::min(kMost, static_cast<double>(bytes_) + bytes));
}

void SpaceEstimate::dataset(int64_t total, int columns, size_t elementSize, Layout layout) {
  const double width = static_cast<double>(std::max(columns, 1)) * static_cast<double>(elementSize);
  double rows = static_cast<double>(std::max<int64_t>(total, 0));
  double chunks = 0;
  if (layout == Layout::kChecksummedChunks) {
    // Every chunk is allocated whole, the last one too (as writeDataset chooses them).
    const double perChunk = std::clamp<double>(
        rows, 1, static_cast<double>(std::max<int64_t>(1, kChunkElements / std::max(columns, 1))));
    chunks = std::ceil(std::max(rows, 1.0) / perChunk);
    rows = chunks * perChunk;
  }
  add(rows * width + chunks * kPerChunk + kPerDataset);
}

void SpaceEstimate::text(size_t length, int copies) {
  add(static_cast<double>(length) * std::max(copies, 1) + kPerText);
}

void reserveSpace(const std::string& name, int64_t bytes) {
  const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) throw Failure("cannot create " + name + ": " + std::strerror(errno));
  struct stat status {};
  int error = ::fstat(fd, &status) != 0 ? errno : 0;
  if (error == 0 && (!S_ISREG(status.st_mode) || status.st_size != 0)) {
    ::close(fd);
    throw Failure(name + " is not a new file");
  }
  if (error == 0) {
    do {
      error = ::fallocate(fd, FALLOC_FL_KEEP_SIZE, 0, static_cast<off_t>(bytes)) != 0 ? errno : 0;
    } while (error == EINTR);
    // A file system that cannot allocate ahead (EOPNOTSUPP) is written as before.
    if (error == EOPNOTSUPP || error == ENOSYS) error = 0;
  }
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0)
    throw Failure("cannot reserve " + megabytes(bytes) +
                  " on disk for it: " + std::strerror(error));
}

void discardFurtherWrites(const std::string& name) noexcept {
  struct stat file {};
  if (::stat(name.c_str(), &file) != 0) return;
  DIR* descriptors = ::opendir("/proc/self/fd");
  if (descriptors == nullptr) return;
  const int sink = ::memfd_create("radiosity-discarded", MFD_CLOEXEC);
  while (const dirent* entry = ::readdir(descriptors)) {
    char* end = nullptr;
    const long fd = std::strtol(entry->d_name, &end, 10);
    struct stat held {};
    if (sink < 0 || *end != '\0' || fd == ::dirfd(descriptors) || fd == sink ||
        ::fstat(static_cast<int>(fd), &held) != 0 || held.st_dev != file.st_dev ||
        held.st_ino != file.st_ino)
      continue;
    // dup3 keeps the descriptor's number, which MPI-IO holds, and sets close-on-exec.
    (void)::dup3(sink, static_cast<int>(fd), O_CLOEXEC);
  }
  ::closedir(descriptors);
  if (sink >= 0) ::close(sink);
}

void releaseUnusedSpace(const std::string& name) noexcept {
  struct stat status {};
  if (::stat(name.c_str(), &status) == 0) (void)::truncate(name.c_str(), status.st_size);
}

}  // namespace radiosity::h5
