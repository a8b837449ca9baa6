#include "io/store/xdmf.h"

#include <hdf5.h>

#include <filesystem>
#include <sstream>
#include <vector>

#include "core/channels.h"
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

// The unit the `units` attribute of dataset `name` states, for its array's name ("area
// [mm^2]"); "" where it states none (a number, an index, a rank), names no unit but says which
// one to use (the light of a scene whose unit of E is not stated) or is missing.
std::string statedUnit(hid_t file, const std::string& path, const std::string& name) {
  if (H5Aexists_by_name(file, name.c_str(), format::attribute::kUnits, H5P_DEFAULT) <= 0) return "";
  const h5::Handle dataset =
      h5::own(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
  const h5::OpenAttribute units = h5::openAttribute(dataset.get(), path, format::attribute::kUnits);
  if (H5Tget_class(units.type.get()) != H5T_STRING) return "";
  const std::string text = h5::readString(units.attribute.get(), units.type.get(), units.what);
  const bool unit = !text.empty() && text != "1" && text != "index" && text != "rank" &&
                    text.find(' ') == std::string::npos && xmlHolds(text);
  return unit ? text : "";
}

// An array's name in ParaView: the dataset's, with its unit where the file states one.
std::string arrayName(const std::string& name, const std::string& unit) {
  return unit.empty() ? name : name + " [" + unit + "]";
}

// The whole dataset, or (channel ≥ 0) column `channel` of an [n,3] one as [n,1]: XDMF 3's
// hyperslab of an HDF5 dataset, "file:dataset|start:stride:count:dataspace" (ParaView's XDMF 3
// reader reads it; its HyperSlab and Function items it skips).
std::string dataItem(const DatasetShape& d, const std::string& reference, int channel = -1) {
  std::ostringstream out;
  out << "<DataItem Dimensions=\"";
  if (channel < 0) {
    for (size_t k = 0; k < d.dims.size(); ++k) out << (k ? " " : "") << d.dims[k];
  } else {
    out << d.dims[0] << " 1";
  }
  out << "\" NumberType=\"" << d.numberType << "\" Precision=\"" << d.precision
      << "\" Format=\"HDF\">" << escapeXml(reference) << ":" << escapeXml(d.name);
  if (channel >= 0)
    out << "|0 " << channel << ":1 1:" << d.dims[0] << " 1:" << d.dims[0] << " " << d.dims[1];
  out << "</DataItem>";
  return out.str();
}

std::string attribute(const std::string& name, const DatasetShape& d, const char* center,
                      const std::string& reference, int channel = -1) {
  const bool vector = channel < 0 && d.dims.size() == 2 && d.dims[1] == 3;
  return "      <Attribute Name=\"" + escapeXml(name) + "\" AttributeType=\"" +
         (vector ? "Vector" : "Scalar") + "\" Center=\"" + center + "\">\n        " +
         dataItem(d, reference, channel) + "\n      </Attribute>\n";
}

// B of the patches or of the display vertices (nothing unless it has `rows` rows): the array
// itself and, for three channels, one scalar array per channel named for it ("radiosity_red"):
// ParaView calls a vector's components X, Y and Z, and XDMF cannot name them.
std::string radiosityAttributes(hid_t file, const std::string& path, const std::string& dataset,
                                const std::string& name, const char* center, hsize_t rows,
                                const std::string& reference) {
  const DatasetShape d = shapeOf(file, path, dataset);
  if (d.dims.empty() || d.dims[0] != rows) return "";
  const std::string unit = statedUnit(file, path, dataset);
  std::string out = attribute(arrayName(name, unit), d, center, reference);
  if (d.dims.size() == 2 && d.dims[1] == 3)
    for (int c = 0; c < 3; ++c)
      out += attribute(arrayName(name + "_" + kChannelNames[c], unit), d, center, reference, c);
  return out;
}

// Field data naming each label of /patches/group: one array "group 3: left" holding 3 per label
// (ParaView lists field data by name; XDMF gives it no text values).
std::string groupNames(hid_t file, const std::string& path) {
  if (!h5::exists(file, format::kGroup) || !h5::exists(file, format::kViewFactors)) return "";
  const h5::Handle factors = h5::own(H5Dopen2(file, format::kViewFactors, H5P_DEFAULT),
                                     std::string("H5Dopen2(") + format::kViewFactors + ")");
  if (H5Aexists(factors.get(), format::attribute::kGroupNames) <= 0) return "";
  const std::vector<std::string> names =
      h5::readStringArrayAttribute(factors.get(), path, format::attribute::kGroupNames);
  std::string out;
  for (size_t g = 0; g < names.size(); ++g) {
    if (!xmlHolds(names[g])) continue;  // (not ours: a label XML cannot hold)
    const std::string index = std::to_string(g);
    out += "      <Attribute Name=\"" + escapeXml("group " + index + ": " + names[g]) +
           "\" AttributeType=\"Scalar\" Center=\"Grid\">\n        <DataItem Dimensions=\"1\" "
           "NumberType=\"Int\" Precision=\"4\" Format=\"XML\">" +
           index + "</DataItem>\n      </Attribute>\n";
  }
  return out;
}

// InputError unless every index of `name` ([n,3] int) names one of `vertices` vertices:
// ParaView would read out of range.
void checkIndices(hid_t file, const std::string& path, const std::string& name, int64_t vertices) {
  int64_t rows = -1;
  const h5::OpenDataset open = h5::openDataset(file, path, name, H5T_NATIVE_INT64, 3, rows);
  std::vector<int64_t> indices(static_cast<size_t>(3 * rows));
  h5::readRows(open, path, name, H5T_NATIVE_INT64, {0, rows}, indices.data(), H5P_DEFAULT);
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
  // What ParaView shows first (it colours by the first scalar of the point data, else of the cell
  // data): the tone-mapped luminance of the smooth B, or a thermal run's one-channel B itself;
  // B next, its channels apart; then every other patch dataset in name order.
  if (sidecar.smooth) {
    if (h5::exists(file, format::kDisplayTonemapped)) {
      const std::string name = format::kDisplayTonemapped;
      const DatasetShape d = shapeOf(file, resultFile, name);
      if (d.dims.size() == 1 && d.dims[0] == vertices.dims[0])
        out << attribute(name.substr(name.rfind('/') + 1), d, "Node", reference);
    }
    out << radiosityAttributes(file, resultFile, format::kDisplayRadiosity,
                               format::kSmoothRadiosity, "Node", vertices.dims[0], reference);
  }
  out << radiosityAttributes(file, resultFile, format::kRadiosity, "radiosity", "Cell",
                             triangles.dims[0], reference);
  for (const std::string& name : datasetsIn(file, format::kPatches)) {
    if (name == format::kRadiosity) continue;
    const DatasetShape d = shapeOf(file, resultFile, name);
    if (d.dims.empty() || d.dims[0] != triangles.dims[0]) continue;  // not one row per patch
    if (!xmlHolds(name)) continue;  // (not ours: a name XML cannot hold, whose data it cannot name)
    out << attribute(
        arrayName(name.substr(name.rfind('/') + 1), statedUnit(file, resultFile, name)), d, "Cell",
        reference);
  }
  out << groupNames(file, resultFile);
  out << "    </Grid>\n  </Domain>\n</Xdmf>\n";
  sidecar.text = out.str();
  return sidecar;
}

}  // namespace radiosity
