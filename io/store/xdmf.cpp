#include "io/store/xdmf.h"

#include <hdf5.h>

#include <filesystem>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/xml_text.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"
#include "io/store/result_format.h"

namespace radiosity {

namespace {

namespace format = result_format;

// One dataset as an XDMF DataItem needs it.
struct DatasetShape {
  std::string name;  ///< full HDF5 path
  std::vector<hsize_t> dims;
  std::string numberType;  ///< Float, Int or UInt
  size_t precision = 8;
};

DatasetShape shapeOf(hid_t file, const std::string& path, const std::string& name) {
  h5::Handle dataset = h5::own(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
  h5::Handle type = h5::own(H5Dget_type(dataset.get()), "H5Dget_type(" + name + ")");
  h5::Handle space = h5::own(H5Dget_space(dataset.get()), "H5Dget_space(" + name + ")");
  DatasetShape shape{name, h5::shapeOf(space.get()), "", H5Tget_size(type.get())};
  const H5T_class_t typeClass = H5Tget_class(type.get());
  if (typeClass == H5T_FLOAT)
    shape.numberType = "Float";
  else if (typeClass == H5T_INTEGER && shape.precision == 1)  // XDMF names bytes apart
    shape.numberType = H5Tget_sign(type.get()) == H5T_SGN_NONE ? "UChar" : "Char";
  else if (typeClass == H5T_INTEGER)
    shape.numberType = H5Tget_sign(type.get()) == H5T_SGN_NONE ? "UInt" : "Int";
  else
    h5::fail(path, "dataset " + name + " holds " + h5::typeName(type.get()) + ", not numbers");
  return shape;
}

// The datasets directly in `group`, in name order.
std::vector<std::string> datasetsIn(hid_t file, const std::string& group) {
  h5::Handle handle =
      h5::own(H5Gopen2(file, group.c_str(), H5P_DEFAULT), "H5Gopen2(" + group + ")");
  H5G_info_t info;
  h5::check(H5Gget_info(handle.get(), &info), "H5Gget_info(" + group + ")");
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t length = H5Lget_name_by_idx(handle.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i,
                                              nullptr, 0, H5P_DEFAULT);
    std::string name(static_cast<size_t>(h5::check(length, "H5Lget_name_by_idx")), '\0');
    H5Lget_name_by_idx(handle.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(),
                       name.size() + 1, H5P_DEFAULT);
    H5O_info_t object;
    h5::check(
        H5Oget_info_by_name2(handle.get(), name.c_str(), &object, H5O_INFO_BASIC, H5P_DEFAULT),
        "H5Oget_info_by_name(" + name + ")");
    if (object.type == H5O_TYPE_DATASET) names.push_back(group + "/" + name);
  }
  return names;
}

std::string dataItem(const DatasetShape& d, const std::string& reference) {
  std::ostringstream out;
  out << "<DataItem Dimensions=\"";
  for (size_t k = 0; k < d.dims.size(); ++k) out << (k ? " " : "") << d.dims[k];
  out << "\" NumberType=\"" << d.numberType << "\" Precision=\"" << d.precision
      << "\" Format=\"HDF\">" << escapeXml(reference) << ":" << escapeXml(d.name) << "</DataItem>";
  return out.str();
}

std::string attribute(const std::string& name, const DatasetShape& d, const char* center,
                      const std::string& reference) {
  const bool vector = d.dims.size() == 2 && d.dims[1] == 3;
  return "      <Attribute Name=\"" + escapeXml(name) + "\" AttributeType=\"" +
         (vector ? "Vector" : "Scalar") + "\" Center=\"" + center + "\">\n        " +
         dataItem(d, reference) + "\n      </Attribute>\n";
}

// InputError unless every index of `name` ([n,3] int) names one of `vertices` vertices:
// ParaView would read out of range.
void checkIndices(hid_t file, const std::string& path, const std::string& name, int64_t vertices) {
  int64_t rows = -1;
  const h5::OpenDataset open = h5::openDataset(file, path, name, H5T_NATIVE_INT64, 3, rows);
  std::vector<int64_t> indices(static_cast<size_t>(3 * rows));
  h5::readRows(open, path, name, H5T_NATIVE_INT64, 0, rows, indices.data(), H5P_DEFAULT);
  for (size_t k = 0; k < indices.size(); ++k) {
    if (indices[k] < 0 || indices[k] >= vertices)
      h5::fail(path, "dataset " + name + " row " + std::to_string(k / 3) + " refers to vertex " +
                         std::to_string(indices[k]) + " (" + std::to_string(vertices) +
                         " vertices)");
  }
}

}  // namespace

std::string xdmfPathFor(const std::string& resultPath) {
  return std::filesystem::path(resultPath).replace_extension(".xmf").string();
}

XdmfSidecar xdmfFor(const std::string& resultFile, const std::string& reference) {
  h5::QuietErrors quiet;
  h5::Handle handle = h5::openFile(resultFile, "result file");
  const hid_t file = handle.get();
  for (const char* name : {format::kVertices, format::kTriangles, format::kRadiosity})
    if (!h5::exists(file, name)) h5::fail(resultFile, std::string("not a result file: no ") + name);
  XdmfSidecar sidecar;
  sidecar.smooth = h5::exists(file, format::kDisplayTriangles);
  // The display mesh where the file has one, else the patches themselves.
  const std::string trianglesName = sidecar.smooth ? format::kDisplayTriangles : format::kTriangles;
  const std::string verticesName = sidecar.smooth ? format::kDisplayVertices : format::kVertices;
  const DatasetShape triangles = shapeOf(file, resultFile, trianglesName);
  const DatasetShape vertices = shapeOf(file, resultFile, verticesName);
  if (triangles.dims.size() != 2 || triangles.dims[1] != 3 || vertices.dims.size() != 2 ||
      vertices.dims[1] != 3)
    h5::fail(resultFile, trianglesName + " or " + verticesName + " is not [n,3]");
  checkIndices(file, resultFile, trianglesName, static_cast<int64_t>(vertices.dims[0]));
  // The sidecar names the result: a name XML cannot hold would name another file.
  if (!xmlHolds(reference))
    h5::fail(resultFile, "its name is not UTF-8 text XML can hold (" + escapeXml(reference) +
                             "), so no XDMF sidecar can name it: rename the file");
  std::string comment = escapeXml(reference);  // (no "--" inside a comment)
  for (size_t at; (at = comment.find("--")) != std::string::npos;) comment.replace(at, 2, "- -");
  std::ostringstream out;
  out << "<?xml version=\"1.0\" ?>\n"
      << "<!-- ParaView/VisIt view of " << comment
      << " (radiosity); open this file, not the .h5 -->\n"
      << "<Xdmf Version=\"3.0\">\n  <Domain>\n    <Grid Name=\"radiosity\" GridType=\"Uniform\">\n"
      << "      <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << triangles.dims[0]
      << "\">\n        " << dataItem(triangles, reference) << "\n      </Topology>\n"
      << "      <Geometry GeometryType=\"XYZ\">\n        " << dataItem(vertices, reference)
      << "\n      </Geometry>\n";
  for (const std::string& name : datasetsIn(file, format::kPatches)) {
    const DatasetShape d = shapeOf(file, resultFile, name);
    if (d.dims.empty() || d.dims[0] != triangles.dims[0]) continue;  // not one row per patch
    if (!xmlHolds(name)) continue;  // (not ours: a name XML cannot hold, whose data it cannot name)
    out << attribute(name.substr(name.rfind('/') + 1), d, "Cell", reference);
  }
  if (sidecar.smooth) {
    out << attribute(format::kSmoothRadiosity, shapeOf(file, resultFile, format::kDisplayRadiosity),
                     "Node", reference);
  }
  out << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  sidecar.text = out.str();
  return sidecar;
}

}  // namespace radiosity
