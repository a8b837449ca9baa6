#include "io/store/hdf5_read.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include "core/input_file.h"
#include "io/store/format_names.h"

namespace radiosity::h5 {

void fail(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

void checkHdf5File(const std::string& path, const std::string& kind) {
  requireRegularFile(path, kind);  // H5Fis_hdf5 opens it: a FIFO would block there
  const htri_t isHdf5 = H5Fis_hdf5(path.c_str());
  if (isHdf5 < 0) fail(path, "cannot read: " + takeErrorText());
  if (isHdf5 == 0) fail(path, "not an HDF5 file");
}

namespace {

// H5Lvisit's callback: the first link that leads out of the file, as "what it is (where)".
herr_t findOutsideData(hid_t group, const char* name, const H5L_info_t* info, void* found) {
  std::string& problem = *static_cast<std::string*>(found);
  if (info->type == H5L_TYPE_EXTERNAL) {
    problem = std::string("/") + name + " is an external link (to another file)";
    return 1;
  }
  if (info->type != H5L_TYPE_HARD) return 0;
  H5O_info_t object{};
  if (H5Oget_info_by_name(group, name, &object, H5P_DEFAULT) < 0 || object.type != H5O_TYPE_DATASET)
    return 0;
  const hid_t dataset = H5Dopen2(group, name, H5P_DEFAULT);
  if (dataset < 0) return 0;  // the reader that needs it reports the damage
  const Handle owner(dataset);
  const hid_t plist = H5Dget_create_plist(dataset);
  if (plist < 0) return 0;
  const Handle creation(plist);
  if (H5Pget_layout(plist) == H5D_VIRTUAL) {
    problem = std::string("dataset /") + name + " is virtual (its data are in other files)";
    return 1;
  }
  if (H5Pget_external_count(plist) > 0) {
    char file[256] = "";
    off_t offset = 0;
    hsize_t size = 0;
    H5Pget_external(plist, 0, sizeof file, file, &offset, &size);
    problem = std::string("dataset /") + name + " is stored in the external file '" + file + "'";
    return 1;
  }
  return 0;
}

}  // namespace

void requireSelfContained(hid_t file, const std::string& path) {
  std::string problem;
  if (H5Lvisit(file, H5_INDEX_NAME, H5_ITER_NATIVE, findOutsideData, &problem) < 0) {
    H5Eclear2(H5E_DEFAULT);  // a damaged link table: the readers say what they cannot find
    return;
  }
  if (!problem.empty())
    fail(path, problem + ": only data inside the file are read (h5repack can copy them in)");
}

Handle openFile(const std::string& path, const std::string& kind) {
  checkHdf5File(path, kind);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) fail(path, "cannot open: " + takeErrorText());
  Handle handle(file);
  requireSelfContained(file, path);
  return handle;
}

bool exists(hid_t file, const std::string& name) {
  for (size_t slash = name.find('/', 1); slash != std::string::npos;
       slash = name.find('/', slash + 1)) {
    const std::string group = name.substr(0, slash);
    if (check(H5Lexists(file, group.c_str(), H5P_DEFAULT), "H5Lexists(" + group + ")") <= 0)
      return false;
  }
  return check(H5Lexists(file, name.c_str(), H5P_DEFAULT), "H5Lexists(" + name + ")") > 0;
}

std::string typeName(hid_t type) {
  const std::string bits = std::to_string(8 * H5Tget_size(type));
  switch (H5Tget_class(type)) {
    case H5T_INTEGER:
      return (H5Tget_sign(type) == H5T_SGN_NONE ? "uint" : "int") + bits;
    case H5T_FLOAT:
      return "float" + bits;
    case H5T_STRING:
      return "string";
    case H5T_COMPOUND:
      return "compound";
    case H5T_ARRAY:
      return "array";
    case H5T_ENUM:
      return "enum";
    default:
      return "other";
  }
}

std::vector<hsize_t> shapeOf(hid_t space) {
  const int rank = check(H5Sget_simple_extent_ndims(space), "H5Sget_simple_extent_ndims");
  std::vector<hsize_t> dims(rank);
  check(H5Sget_simple_extent_dims(space, dims.data(), nullptr), "H5Sget_simple_extent_dims");
  return dims;
}

std::string shapeText(const std::vector<hsize_t>& dims) {
  std::string text = "[";
  for (size_t i = 0; i < dims.size(); ++i) text += (i ? ", " : "") + std::to_string(dims[i]);
  return text + "]";
}

std::string exact(double value) {
  char text[32];
  auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end);
}

std::vector<std::string> attributeNames(hid_t object) {
  // Listed in a child process: HDF5 builds a table of an object's attributes to list them, and
  // where one is damaged (a byte flipped in a result) it crashes freeing the half-built table
  // (`info` segfaulted in H5Aiterate2); a child that dies is an error here instead.
  int ends[2];
  if (pipe(ends) != 0) throw Failure("pipe: cannot list the attributes");
  std::fflush(nullptr);
  const pid_t child = fork();
  if (child < 0) throw Failure("fork: cannot list the attributes");
  if (child == 0) {
    // Crash plainly: PETSc's handlers would call MPI_Abort, which hangs in a forked child.
    for (int signal : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL}) std::signal(signal, SIG_DFL);
    close(ends[0]);
    std::string listed;
    auto collect = [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
      static_cast<std::string*>(data)->append(name).push_back('\0');
      return 0;
    };
    hsize_t index = 0;
    const bool ok = H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, &index, collect, &listed) >= 0;
    for (size_t at = 0; ok && at < listed.size();) {
      const ssize_t n = write(ends[1], listed.data() + at, listed.size() - at);
      if (n <= 0) _exit(1);
      at += static_cast<size_t>(n);
    }
    _exit(ok ? 0 : 1);
  }
  close(ends[1]);
  std::string listed;
  char buffer[4096];
  for (ssize_t n; (n = read(ends[0], buffer, sizeof buffer)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    listed.append(buffer, static_cast<size_t>(n));
  }
  close(ends[0]);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw Failure("H5Aiterate2: the attributes are damaged");
  std::vector<std::string> names;
  for (size_t at = 0; at < listed.size();) {
    const size_t end = listed.find('\0', at);
    names.push_back(listed.substr(at, end - at));
    at = end + 1;
  }
  return names;
}

std::string readString(hid_t attribute, hid_t type, const std::string& what) {
  if (check(H5Tis_variable_str(type), "H5Tis_variable_str(" + what + ")") > 0) {
    Handle memory = own(H5Tcopy(H5T_C_S1), "H5Tcopy");
    check(H5Tset_size(memory.get(), H5T_VARIABLE), "H5Tset_size");
    // The file's character set (h5py writes UTF-8): HDF5 converts between none of them.
    check(H5Tset_cset(memory.get(), H5Tget_cset(type)), "H5Tset_cset");
    char* value = nullptr;
    check(H5Aread(attribute, memory.get(), &value), "H5Aread(" + what + ")");
    std::string text = value != nullptr ? value : "";
    H5free_memory(value);
    return text;
  }
  Handle memory = own(H5Tcopy(type), "H5Tcopy");
  std::string text(H5Tget_size(type), '\0');
  check(H5Aread(attribute, memory.get(), text.data()), "H5Aread(" + what + ")");
  text.resize(std::min(text.size(), text.find('\0')));
  if (H5Tget_strpad(type) == H5T_STR_SPACEPAD) text.erase(text.find_last_not_of(' ') + 1);
  return text;
}

std::vector<std::string> readStringArrayAttribute(hid_t object, const std::string& path,
                                                  const std::string& name) {
  const OpenAttribute a = openAttribute(object, path, name);
  if (H5Tget_class(a.type.get()) != H5T_STRING ||
      check(H5Tis_variable_str(a.type.get()), "H5Tis_variable_str(" + a.what + ")") > 0)
    fail(path, a.what + " is " + typeName(a.type.get()) + ", not fixed-length text");
  const hssize_t count = H5Sget_simple_extent_npoints(a.space.get());
  const size_t width = H5Tget_size(a.type.get());
  if (count < 0 || width == 0) fail(path, a.what + " has no readable shape");
  Handle memory = own(H5Tcopy(a.type.get()), "H5Tcopy");
  std::string buffer(static_cast<size_t>(count) * width, '\0');
  check(H5Aread(a.attribute.get(), memory.get(), buffer.data()), "H5Aread(" + a.what + ")");
  std::vector<std::string> values;
  for (hssize_t k = 0; k < count; ++k) {
    std::string value = buffer.substr(static_cast<size_t>(k) * width, width);
    value.resize(std::min(value.size(), value.find('\0')));
    values.push_back(std::move(value));
  }
  return values;
}

std::string kindAttribute(hid_t file) {
  const char* kind = format_names::attribute::kKind;
  if (check(H5Aexists(file, kind), "H5Aexists(kind)") <= 0) return "";
  Handle attribute = own(H5Aopen(file, kind, H5P_DEFAULT), "H5Aopen(kind)");
  Handle type = own(H5Aget_type(attribute.get()), "H5Aget_type(kind)");
  if (H5Tget_class(type.get()) != H5T_STRING) return "";
  return readString(attribute.get(), type.get(), "attribute kind");
}

std::string fileKind(const std::string& path) {
  QuietErrors quiet;
  try {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error) || H5Fis_hdf5(path.c_str()) <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return "";
    }
    const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (id < 0) {
      H5Eclear2(H5E_DEFAULT);
      return "";
    }
    Handle file(id);
    return kindAttribute(id);
  } catch (const std::exception&) {
    H5Eclear2(H5E_DEFAULT);
    return "";
  }
}

std::string attributeLabel(hid_t object, const std::string& name) {
  if (H5Iget_type(object) == H5I_FILE) return "root attribute " + name;
  std::string objectName(256, '\0');
  const ssize_t length = H5Iget_name(object, objectName.data(), objectName.size());
  if (length <= 0) return "attribute " + name;
  if (static_cast<size_t>(length) >= objectName.size()) {
    objectName.resize(length + 1);
    H5Iget_name(object, objectName.data(), objectName.size());
  }
  objectName.resize(length);
  return "attribute " + name + " of " + objectName;
}

OpenAttribute openAttribute(hid_t object, const std::string& path, const std::string& name) {
  OpenAttribute a;
  a.what = attributeLabel(object, name);
  if (check(H5Aexists(object, name.c_str()), "H5Aexists(" + name + ")") <= 0)
    fail(path, "missing " + a.what);
  a.attribute = own(H5Aopen(object, name.c_str(), H5P_DEFAULT), "H5Aopen(" + name + ")");
  a.type = own(H5Aget_type(a.attribute.get()), "H5Aget_type(" + name + ")");
  a.space = own(H5Aget_space(a.attribute.get()), "H5Aget_space(" + name + ")");
  return a;
}

void checkStored(hid_t dataset, hid_t space, const std::string& path, const std::string& name) {
  const hssize_t points = H5Sget_simple_extent_npoints(space);
  Handle type = own(H5Dget_type(dataset), "H5Dget_type(" + name + ")");
  const double claimed = static_cast<double>(points) * static_cast<double>(H5Tget_size(type.get()));
  const auto stored = static_cast<double>(H5Dget_storage_size(dataset));
  if (points < 0 || claimed > kMostCompression * stored + 4096) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "claims %lld values (%.3g bytes) but the file stores %.0f bytes of them, less "
                  "than any compression explains: damaged, or never written",
                  static_cast<long long>(points), claimed, stored);
    fail(path, "dataset " + name + " " + text);
  }
}

OpenDataset openDataset(hid_t file, const std::string& path, const std::string& name,
                        hid_t memoryType, int columns, int64_t& rows) {
  if (!exists(file, name)) fail(path, "missing dataset " + name);
  OpenDataset open;
  open.dataset = own(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
  Handle type = own(H5Dget_type(open.dataset.get()), "H5Dget_type(" + name + ")");
  open.space = own(H5Dget_space(open.dataset.get()), "H5Dget_space(" + name + ")");
  const bool wantFloat = H5Tget_class(memoryType) == H5T_FLOAT;
  const std::string wanted =
      (wantFloat ? "float" : "int") + std::to_string(8 * H5Tget_size(memoryType));
  if (H5Tget_class(type.get()) != (wantFloat ? H5T_FLOAT : H5T_INTEGER))
    fail(path, "dataset " + name + " holds " + typeName(type.get()) + ", expected " + wanted);
  const std::vector<hsize_t> dims = shapeOf(open.space.get());
  std::string expected = "[";
  expected += rows < 0 ? std::string("n") : std::to_string(rows);
  if (columns != 0) expected.append(", ").append(std::to_string(columns));
  expected += "]";
  if (dims.size() != (columns == 0 ? 1u : 2u) || (columns != 0 && dims[1] != hsize_t(columns)) ||
      (rows >= 0 && dims[0] != hsize_t(rows)))
    fail(path, "dataset " + name + " has shape " + shapeText(dims) + ", expected " + expected);
  checkStored(open.dataset.get(), open.space.get(), path, name);
  rows = static_cast<int64_t>(dims[0]);
  open.rows = rows;
  open.columns = columns;
  return open;
}

void checkRowRange(const OpenDataset& open, const std::string& path, const std::string& name,
                   Rows part) {
  const auto [first, count] = part;
  if (first < 0 || count < 0 || first > open.rows || count > open.rows - first)
    fail(path, "dataset " + name + " has " + std::to_string(open.rows) + " rows, not rows " +
                   std::to_string(first) + " to " + std::to_string(first + count));
}

void readRows(const OpenDataset& open, const std::string& path, const std::string& name,
              hid_t memoryType, Rows part, void* destination, hid_t transfer) {
  checkRowRange(open, path, name, part);
  const auto [first, count] = part;
  const bool collective = transfer != H5P_DEFAULT;
  // Alone, an empty read is no read; in a collective one every rank must take part, unless the
  // dataset is empty (which every rank sees): it may have no storage to read from.
  if (open.rows == 0 || (count == 0 && !collective)) return;
  if (first == 0 && count == open.rows && count > 0) {
    check(H5Dread(open.dataset.get(), memoryType, H5S_ALL, H5S_ALL, transfer, destination),
          "H5Dread(" + name + ")");
    return;
  }
  const int dimensions = open.columns == 0 ? 1 : 2;
  const hsize_t width = static_cast<hsize_t>(std::max(open.columns, 1));
  const hsize_t start[2] = {static_cast<hsize_t>(first), 0};
  const hsize_t block[2] = {static_cast<hsize_t>(count), width};
  const hsize_t one[2] = {1, width};  // a dataspace needs an extent even when nothing is selected
  Handle space = own(H5Scopy(open.space.get()), "H5Scopy(" + name + ")");
  Handle memory = own(H5Screate_simple(dimensions, count > 0 ? block : one, nullptr),
                      "H5Screate_simple(" + name + ")");
  if (count > 0) {
    check(H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, block, nullptr),
          "H5Sselect_hyperslab(" + name + ")");
  } else {
    check(H5Sselect_none(space.get()), "H5Sselect_none(" + name + ")");
    check(H5Sselect_none(memory.get()), "H5Sselect_none(" + name + ")");
  }
  static double nothing[3];  // a read of nothing still wants a buffer
  check(H5Dread(open.dataset.get(), memoryType, memory.get(), space.get(), transfer,
                destination != nullptr ? destination : nothing),
        "H5Dread(" + name + ")");
}

SolveHistory readSolveHistory(hid_t file, const std::string& path, const std::string& name) {
  SolveHistory history;
  int64_t n = -1;
  const std::vector<double> rows = readDataset<double>(file, path, name, H5T_NATIVE_DOUBLE, 4, n);
  constexpr double kLargestExact = 9007199254740992.0;  // 2^53
  for (int64_t i = 0; i < n; ++i) {
    const double channel = rows[4 * i], iteration = rows[4 * i + 1];
    if (channel != 0 && channel != 1 && channel != 2)
      fail(path, "dataset " + name + ": row " + std::to_string(i) + " has channel " +
                     exact(channel) + ", not 0, 1 or 2");
    if (!(iteration >= 0 && iteration <= kLargestExact) || iteration != std::floor(iteration))
      fail(path, "dataset " + name + ": row " + std::to_string(i) + " has iteration " +
                     exact(iteration) + ", not a whole number from 0 to 2^53");
    history.channel.push_back(static_cast<int>(channel));
    history.iteration.push_back(static_cast<int64_t>(iteration));
    history.residual.push_back(rows[4 * i + 2]);
    history.seconds.push_back(rows[4 * i + 3]);
  }
  return history;
}

}  // namespace radiosity::h5
