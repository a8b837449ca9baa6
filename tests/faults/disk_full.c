// LD_PRELOAD shim for the reliability tests: a disk that fills up on one MPI rank. Writes to
// files under RADIOSITY_FAULT_DIR by the rank RADIOSITY_FAULT_RANK (OMPI_COMM_WORLD_RANK or
// PMIX_RANK; every rank if unset) fail with ENOSPC once RADIOSITY_FAULT_BYTES bytes have been
// written, as do allocations ahead (fallocate, posix_fallocate) that do not fit in what is left.
// A write into space allocated ahead succeeds, as on a real file system. With
// RADIOSITY_FAULT_KIND=io the device fails instead: allocations succeed and every write counts,
// failing with EIO past the limit. Covers what Open MPI's MPI-IO (fbtl posix: pwrite, pwritev)
// and the C library use.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static long long budget = -1;  // -1: not this process
static long long used = 0;
static int failure = ENOSPC;
static char directory[PATH_MAX];

// Space allocated ahead, per file (device, inode): writes below `end` cost nothing.
enum { kFiles = 64 };
static struct {
  dev_t dev;
  ino_t ino;
  long long end;
} reserved[kFiles];

static void setUp(void) {
  static int done = 0;
  if (done) return;
  done = 1;
  const char* dir = getenv("RADIOSITY_FAULT_DIR");
  const char* bytes = getenv("RADIOSITY_FAULT_BYTES");
  if (dir == NULL || bytes == NULL) return;
  const char* want = getenv("RADIOSITY_FAULT_RANK");
  const char* rank = getenv("OMPI_COMM_WORLD_RANK");
  if (rank == NULL) rank = getenv("PMIX_RANK");
  if (want != NULL && (rank == NULL || strcmp(want, rank) != 0)) return;
  snprintf(directory, sizeof directory, "%s/", dir);
  budget = atoll(bytes);
  const char* kind = getenv("RADIOSITY_FAULT_KIND");
  if (kind != NULL && strcmp(kind, "io") == 0) failure = EIO;
}

// Whether `fd` is a regular file under the directory; its identity in *st.
static int watched(int fd, struct stat* st) {
  char link[64], target[PATH_MAX];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, target, sizeof target - 1);
  if (n <= 0) return 0;
  target[n] = '\0';
  if (strncmp(target, directory, strlen(directory)) != 0) return 0;
  return fstat(fd, st) == 0 && S_ISREG(st->st_mode);
}

static long long* reservedEnd(const struct stat* st, int add) {
  for (int i = 0; i < kFiles; ++i)
    if (reserved[i].end > 0 && reserved[i].dev == st->st_dev && reserved[i].ino == st->st_ino)
      return &reserved[i].end;
  if (!add) return NULL;
  for (int i = 0; i < kFiles; ++i)
    if (reserved[i].end == 0) {
      reserved[i].dev = st->st_dev;
      reserved[i].ino = st->st_ino;
      return &reserved[i].end;
    }
  return NULL;
}

// 0 if `count` bytes at `offset` (-1: the file position) of `fd` may be written, else ENOSPC.
static int charge(int fd, long long offset, long long count) {
  pthread_mutex_lock(&lock);
  setUp();
  int error = 0;
  struct stat st;
  if (budget >= 0 && count > 0 && watched(fd, &st)) {
    if (offset < 0) offset = lseek(fd, 0, SEEK_CUR);
    const long long* end = failure == EIO ? NULL : reservedEnd(&st, 0);
    if (end == NULL || offset < 0 || offset + count > *end) {
      if (used + count > budget)
        error = failure;
      else
        used += count;
    }
  }
  pthread_mutex_unlock(&lock);
  return error;
}

static int reserve(int fd, long long offset, long long length) {
  pthread_mutex_lock(&lock);
  setUp();
  int error = 0;
  struct stat st;
  if (budget >= 0 && failure == ENOSPC && watched(fd, &st)) {
    if (used + length > budget) {
      error = ENOSPC;
    } else {
      used += length;
      long long* end = reservedEnd(&st, 1);
      if (end != NULL && offset + length > *end) *end = offset + length;
    }
  }
  pthread_mutex_unlock(&lock);
  return error;
}

static long long total(const struct iovec* iov, int count) {
  long long sum = 0;
  for (int i = 0; i < count; ++i) sum += (long long)iov[i].iov_len;
  return sum;
}

#define NEXT(type, name) ((type)dlsym(RTLD_NEXT, name))
#define FAIL_WITH(error) \
  do {                   \
    errno = (error);     \
    return -1;           \
  } while (0)

ssize_t write(int fd, const void* buffer, size_t count) {
  const int error = charge(fd, -1, (long long)count);
  if (error) FAIL_WITH(error);
  return NEXT(ssize_t(*)(int, const void*, size_t), "write")(fd, buffer, count);
}

ssize_t pwrite(int fd, const void* buffer, size_t count, off_t offset) {
  const int error = charge(fd, offset, (long long)count);
  if (error) FAIL_WITH(error);
  return NEXT(ssize_t(*)(int, const void*, size_t, off_t), "pwrite")(fd, buffer, count, offset);
}

ssize_t pwrite64(int fd, const void* buffer, size_t count, off64_t offset) {
  const int error = charge(fd, offset, (long long)count);
  if (error) FAIL_WITH(error);
  return NEXT(ssize_t(*)(int, const void*, size_t, off64_t), "pwrite64")(fd, buffer, count, offset);
}

ssize_t writev(int fd, const struct iovec* iov, int count) {
  const int error = charge(fd, -1, total(iov, count));
  if (error) FAIL_WITH(error);
  return NEXT(ssize_t(*)(int, const struct iovec*, int), "writev")(fd, iov, count);
}

ssize_t pwritev(int fd, const struct iovec* iov, int count, off_t offset) {
  const int error = charge(fd, offset, total(iov, count));
  if (error) FAIL_WITH(error);
  return NEXT(ssize_t(*)(int, const struct iovec*, int, off_t), "pwritev")(fd, iov, count, offset);
}

ssize_t pwritev64(int fd, const struct iovec* iov, int count, off64_t offset) {
  const int error = charge(fd, offset, total(iov, count));
  if (error) FAIL_WITH(error);
  return NEXT(ssize_t(*)(int, const struct iovec*, int, off64_t), "pwritev64")(fd, iov, count,
                                                                               offset);
}

ssize_t pwritev2(int fd, const struct iovec* iov, int count, off_t offset, int flags) {
  const int error = charge(fd, offset, total(iov, count));
  if (error) FAIL_WITH(error);
  return NEXT(ssize_t(*)(int, const struct iovec*, int, off_t, int), "pwritev2")(fd, iov, count,
                                                                                 offset, flags);
}

int fallocate(int fd, int mode, off_t offset, off_t length) {
  const int error = reserve(fd, offset, length);
  if (error) FAIL_WITH(error);
  return NEXT(int (*)(int, int, off_t, off_t), "fallocate")(fd, mode, offset, length);
}

int fallocate64(int fd, int mode, off64_t offset, off64_t length) {
  const int error = reserve(fd, offset, length);
  if (error) FAIL_WITH(error);
  return NEXT(int (*)(int, int, off64_t, off64_t), "fallocate64")(fd, mode, offset, length);
}

// posix_fallocate returns the error instead of setting errno.
int posix_fallocate(int fd, off_t offset, off_t length) {
  const int error = reserve(fd, offset, length);
  if (error) return error;
  return NEXT(int (*)(int, off_t, off_t), "posix_fallocate")(fd, offset, length);
}

int posix_fallocate64(int fd, off64_t offset, off64_t length) {
  const int error = reserve(fd, offset, length);
  if (error) return error;
  return NEXT(int (*)(int, off64_t, off64_t), "posix_fallocate64")(fd, offset, length);
}
