// View3D's input file (.vs3, NIST/NREL), geometry format F 3: vertices, then surfaces given by
// 3 or 4 vertex numbers, a base and a combination surface, an emissivity and a name. Read so
// that a View3D user's file gives the surfaces and numbering View3D would: surface k is source
// face k − 1, combined surfaces share one label (one output surface), obstructions block light
// from both sides and have no view factors of their own worth reporting; a subsurface (a window)
// is cut out of its base surface, as View3D takes it out of the base's area. docs/view3d.md.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "core/error.h"
#include "core/input_file.h"
#include "core/shown_text.h"
#include "io/scene/scene_internal.h"
#include "io/scene/text_statements.h"

namespace radiosity::detail {
namespace {

/// One line of the file: its words, up to a word that begins a comment ('!' or '/').
struct Line {
  long number = 0;
  std::vector<std::string_view> words;
};

/// The control words View3D 3.2 knows (the C line), each name=value.
const std::set<std::string> kControlWords = {"eps",  "maxu", "maxo", "mino", "row", "col",
                                             "encl", "emit", "out",  "list", "prjd"};

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

class Vs3Reader {
 public:
  explicit Vs3Reader(std::string path) : path_(std::move(path)) {}
  Mesh read();

 private:
  void control(const Line& line);
  void geometry(const Line& line);
  void vertex(const Line& line);
  void surface(const Line& line, char kind);
  int64_t integer(const Line& line, size_t word, const std::string& what);
  double number(const Line& line, size_t word, const std::string& what);
  /// A new label, with the emissivity its surface states (NaN: none).
  int32_t labelOf(const std::string& name, double emissivity);
  /// Checks subsurface n (line) against its base: in its plane, inside it, facing its way.
  void subsurface(const Line& line, int64_t n, int64_t base, const std::vector<int64_t>& corners);
  std::vector<Vec3> outline(const std::vector<int64_t>& corners) const;
  /// The surfaces' triangles, in the file's order, once every subsurface is known.
  void addPolygons();

  /// A polygon of the file, added to the mesh at the end (its subsurfaces come after it).
  struct Polygon {
    std::vector<int64_t> corners;
    long line = 0;
    int64_t surface = 0;
    int32_t label = -1;
    double rho = 0;
  };

  std::string path_;
  Mesh mesh_;
  bool formatSeen_ = false;
  int64_t surfaces_ = 0;          ///< surfaces so far (S, O): the numbering they share
  bool obstructionSeen_ = false;  ///< obstructions come after every radiating surface
  std::vector<int32_t> labelOfSurface_;
  std::vector<int64_t> combinedInto_;  ///< per surface, the surface it combines with (0: none)
  std::vector<int64_t> baseOf_;        ///< per surface, its base surface (0: none)
  std::vector<std::vector<int64_t>> cornersOf_;      ///< per surface, its vertex indices
  std::vector<long> lineOf_;                         ///< per surface, its line
  std::map<int64_t, std::vector<int64_t>> holesOf_;  ///< per base surface, its subsurfaces
  std::vector<Polygon> polygons_;
  std::map<std::string, std::vector<int64_t>> surfacesNamed_;
  int64_t ignoredTransforms_ = 0;
  AddedVertices added_;  ///< points triangulation adds inside polygons: after the file's own
};

/// The lines of `content` split into words; a control byte other than tab or CR is refused
/// (a binary file given as .vs3).
std::vector<Line> splitLines(const std::string& path, const std::string& content) {
  std::vector<Line> lines;
  long number = 0;
  for (size_t pos = 0; pos < content.size();) {
    size_t end = content.find('\n', pos);
    if (end == std::string::npos) end = content.size();
    const std::string_view text(content.data() + pos, end - pos);
    pos = end + 1;
    ++number;
    Line line{number, {}};
    for (const char c : text)
      if ((static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\r') || c == 0x7f)
        throw InputError(path, number, "control byte in the text: not a View3D input file");
    for (size_t i = 0; i < text.size();) {
      const char c = text[i];
      if (c == ' ' || c == '\t' || c == '\r' || c == ',') {
        ++i;
        continue;
      }
      if (c == '!' || c == '/') break;  // a comment to the end of the line
      size_t j = i;
      while (j < text.size() && text[j] != ' ' && text[j] != '\t' && text[j] != '\r' &&
             text[j] != ',')
        ++j;
      line.words.push_back(text.substr(i, j - i));
      i = j;
    }
    if (!line.words.empty()) lines.push_back(std::move(line));
  }
  return lines;
}

Mesh Vs3Reader::read() {
  std::string content;
  if (!readWholeFile(path_, content)) throw InputError(path_ + ": cannot read file");
  const std::vector<Line> lines = splitLines(path_, content);
  for (const Line& line : lines) {
    const char kind = static_cast<char>(std::toupper(static_cast<unsigned char>(line.words[0][0])));
    if (kind == 'E' || kind == '*') break;  // end of data: anything after it is not read
    if (kind == 'T') continue;              // the title, echoed in View3D's reports only
    if (kind == 'C') {
      control(line);
    } else if (kind == 'F') {
      geometry(line);
    } else if (kind == 'X') {
      ++ignoredTransforms_;  // View3D 3.2 reads past these as well
    } else if (line.words[0].size() == 1 &&
               (kind == 'V' || kind == 'S' || kind == 'O' || kind == 'M' || kind == 'N')) {
      if (!formatSeen_)
        throw InputError(path_, line.number,
                         "vertices and surfaces come after the geometry line 'F 3'");
      kind == 'V' ? vertex(line) : surface(line, kind);
    } else {
      throw InputError(path_, line.number,
                       "unknown line '" + shownText(line.words[0], 40) +
                           "' (View3D input lines begin with T, C, F, V, S, O, or E for the "
                           "end; '!' or '/' begins a comment)");
    }
  }
  if (surfaces_ == 0)
    throw InputError(path_ + ": no surfaces (S lines): nothing to compute view factors for");
  for (const auto& [name, numbers] : surfacesNamed_) {
    if (numbers.size() < 2) continue;
    mesh_.warnings.push_back(path_ + ": surfaces " + std::to_string(numbers[0]) + " and " +
                             std::to_string(numbers[1]) + " are both named '" +
                             shownText(name, 60) +
                             "': they stay two surfaces, but a thermal condition for that name "
                             "applies to both");
  }
  if (ignoredTransforms_ > 0)
    mesh_.warnings.push_back(path_ + ": ignored " + std::to_string(ignoredTransforms_) +
                             " coordinate-transformation line(s) (X), as View3D 3.2 does");
  addPolygons();
  added_.appendTo(mesh_);
  return std::move(mesh_);
}

void Vs3Reader::control(const Line& line) {
  for (size_t w = 1; w < line.words.size(); ++w) {
    // name=value, name = value or name value: View3D splits at '=', blanks and commas.
    std::string_view word = line.words[w];
    std::string_view name = word, value;
    const size_t eq = word.find('=');
    if (eq != std::string_view::npos) {
      name = word.substr(0, eq);
      value = word.substr(eq + 1);
    }
    if (value.empty() && w + 1 < line.words.size()) {
      value = line.words[++w];
      if (value.starts_with('=')) value.remove_prefix(1);
      if (value.empty() && w + 1 < line.words.size()) value = line.words[++w];
    }
    const std::string key = lower(name);
    if (!kControlWords.contains(key))
      throw InputError(path_, line.number,
                       "unknown control word '" + shownText(name, 40) +
                           "' (View3D's are eps, maxU, maxO, minO, row, col, encl, emit, out, "
                           "list, prjD)");
    double parsed = 0;
    if (value.empty() || parseNumber(value, parsed) != NumberStatus::kOk || !std::isfinite(parsed))
      throw InputError(path_, line.number,
                       "control word '" + shownText(name, 40) + "' needs a number, found '" +
                           shownText(value, 40) + "'");
    // eps, maxU, maxO, minO steer View3D's own integration, and list, out its reports: ours is
    // set by the solver's options. Two would change what is computed, so they are said.
    if (key == "emit" && parsed != 0)
      mesh_.warnings.push_back(path_ + ":" + std::to_string(line.number) +
                               ": emit=1 asks View3D for script-F factors (with reflections); "
                               "the view factors computed here are black-body factors, and a "
                               "thermal run (--thermal) takes the reflections into account");
    if ((key == "row" || key == "col") && parsed != 0)
      mesh_.warnings.push_back(path_ + ":" + std::to_string(line.number) + ": " +
                               std::string(name) + "=" + std::string(value) +
                               " is ignored: every row is computed");
  }
}

void Vs3Reader::geometry(const Line& line) {
  const std::string format = line.words.size() == 2 ? lower(line.words[1]) : "";
  if (format == "3a")
    throw InputError(path_, line.number,
                     "geometry format 3a (BLAST surfaces: R, Q, T shapes by origin, azimuth and "
                     "tilt) is not read; give vertices and surfaces (F 3)");
  if (format != "3")
    throw InputError(path_, line.number,
                     "geometry line must be 'F 3' (vertices and surfaces), found '" +
                         shownText(line.words.size() > 1 ? line.words[1] : "", 40) + "'");
  formatSeen_ = true;
}

int64_t Vs3Reader::integer(const Line& line, size_t word, const std::string& what) {
  long long value = 0;
  if (word >= line.words.size() || parseInteger(line.words[word], value) != NumberStatus::kOk)
    throw InputError(path_, line.number,
                     what + ": expected a whole number, found '" +
                         shownText(word < line.words.size() ? line.words[word] : "", 40) + "'");
  return value;
}

double Vs3Reader::number(const Line& line, size_t word, const std::string& what) {
  double value = 0;
  if (word >= line.words.size() || parseNumber(line.words[word], value) != NumberStatus::kOk)
    throw InputError(path_, line.number,
                     what + ": expected a number, found '" +
                         shownText(word < line.words.size() ? line.words[word] : "", 40) + "'");
  if (!std::isfinite(value)) throw InputError(path_, line.number, what + " is not finite");
  return value;
}

void Vs3Reader::vertex(const Line& line) {
  if (line.words.size() != 5) throw InputError(path_, line.number, "a vertex line is 'V n x y z'");
  const int64_t n = integer(line, 1, "vertex number");
  if (n != static_cast<int64_t>(mesh_.vertices.size()) + 1)
    throw InputError(path_, line.number,
                     "vertex " + std::to_string(n) + " out of sequence (expected " +
                         std::to_string(mesh_.vertices.size() + 1) + ")");
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    p[k] = number(line, 2 + static_cast<size_t>(k), "coordinate");
    if (std::abs(p[k]) > kMaxCoordinate)
      throw InputError(path_, line.number,
                       "coordinate " + std::string(line.words[2 + k]) + " exceeds 1e30");
  }
  mesh_.vertices.push_back(p);
}

int32_t Vs3Reader::labelOf(const std::string& name, double emissivity) {
  mesh_.labelNames.push_back(name);
  mesh_.labelEmissivity.push_back(emissivity);
  return static_cast<int32_t>(mesh_.labelNames.size()) - 1;
}

void Vs3Reader::surface(const Line& line, char kind) {
  const std::string at = "surface " + std::to_string(surfaces_ + 1);
  if (kind == 'M' || kind == 'N')
    throw InputError(path_, line.number,
                     std::string(kind == 'M' ? "masking" : "null") +
                         " surfaces (M, N) are not read: cut the covered part out of the base "
                         "surface and give what remains as surfaces of their own");
  const bool obstruction = kind == 'O';
  const size_t words = obstruction ? 6 : 10;
  if (line.words.size() != words)
    throw InputError(
        path_, line.number,
        obstruction
            ? "an obstruction line is 'O n v1 v2 v3 v4' (v4 = 0 for a triangle)"
            : std::string("a surface line is 'S n v1 v2 v3 v4 base cmb emit name' (v4 = 0 for a "
                          "triangle; a name has no blanks), found ") +
                  std::to_string(line.words.size()) + " words");
  const int64_t n = integer(line, 1, "surface number");
  if (n != surfaces_ + 1)
    throw InputError(path_, line.number,
                     "surface " + std::to_string(n) + " out of sequence (expected " +
                         std::to_string(surfaces_ + 1) + ")");
  if (!obstruction && obstructionSeen_)
    throw InputError(path_, line.number,
                     "radiating surface " + std::to_string(n) +
                         " after an obstruction (O): obstructions are numbered last");
  std::vector<int64_t> corners;
  const auto vertices = static_cast<int64_t>(mesh_.vertices.size());
  for (size_t k = 2; k < 6; ++k) {
    const int64_t v = integer(line, k, at + " vertex");
    if (k == 5 && v == 0) break;  // a triangle
    if (v < 1 || v > vertices)
      throw InputError(path_, line.number,
                       at + ": vertex " + std::to_string(v) + " does not exist (" +
                           std::to_string(vertices) + " vertices so far)");
    corners.push_back(v - 1);
  }
  if (corners.size() == 4 && crossesItself(outline(corners)))
    throw InputError(path_, line.number,
                     at + ": its outline crosses itself (a bowtie); list the vertices "
                          "counter-clockwise seen from the front");
  ++surfaces_;
  cornersOf_.push_back(corners);
  lineOf_.push_back(line.number);
  if (obstruction) {
    obstructionSeen_ = true;
    // No view factors of its own: black, on both sides (two faces back to back are one
    // two-sided surface to the tracer), so that it only takes the light it blocks.
    const int32_t label = labelOf("obstruction " + std::to_string(n), std::nan(""));
    polygons_.push_back({corners, line.number, n, label, 0});
    std::reverse(corners.begin(), corners.end());
    polygons_.push_back({corners, line.number, n, label, 0});
    labelOfSurface_.push_back(label);
    combinedInto_.push_back(0);
    baseOf_.push_back(0);
    return;
  }
  const int64_t base = integer(line, 6, at + " base");
  if (base != 0) subsurface(line, n, base, corners);
  baseOf_.push_back(base);
  const int64_t combine = integer(line, 7, at + " cmb");
  const double emissivity = number(line, 8, at + " emissivity");
  if (!(emissivity > 0 && emissivity <= 1))
    throw InputError(path_, line.number,
                     at + ": emissivity " + std::string(line.words[8]) + " is not in (0, 1]");
  const std::string name(line.words[9]);
  int32_t label = -1;
  if (combine != 0) {
    if (combine < 1 || combine >= n || combinedInto_[combine - 1] != 0 ||
        mesh_.labelNames[labelOfSurface_[combine - 1]].starts_with("obstruction "))
      throw InputError(path_, line.number,
                       at + ": cmb " + std::to_string(combine) +
                           " must name an earlier radiating surface that is itself combined "
                           "with none (combine every part with the lowest-numbered one)");
    label = labelOfSurface_[combine - 1];
    // Parts of one output surface with other emissivities leave it without one.
    if (mesh_.labelEmissivity[label] != emissivity) mesh_.labelEmissivity[label] = std::nan("");
  } else {
    label = labelOf(name, emissivity);
    surfacesNamed_[name].push_back(n);
  }
  labelOfSurface_.push_back(label);
  combinedInto_.push_back(combine);
  polygons_.push_back({corners, line.number, n, label, 1 - emissivity});
}

std::vector<Vec3> Vs3Reader::outline(const std::vector<int64_t>& corners) const {
  std::vector<Vec3> polygon;
  for (int64_t v : corners) polygon.push_back(mesh_.vertices[v]);
  return polygon;
}

/// How far a subsurface's corner may lie off its base's plane or outside its outline, relative
/// to the base's size: the round-off of coordinates written with a few digits, well below any
/// real offset.
constexpr double kSubsurfaceTolerance = 1e-6;

void Vs3Reader::subsurface(const Line& line, int64_t n, int64_t base,
                           const std::vector<int64_t>& corners) {
  const std::string at =
      "surface " + std::to_string(n) + " (a subsurface of surface " + std::to_string(base) + ")";
  if (base < 1 || base >= n || baseOf_[base - 1] != 0)
    throw InputError(path_, line.number,
                     at + ": its base must be an earlier radiating surface that is not itself "
                          "a subsurface");
  const std::vector<Vec3> wall = outline(cornersOf_[base - 1]);
  const std::vector<Vec3> window = outline(corners);
  const Vec3 wallNormal = newellNormal(wall), windowNormal = newellNormal(window);
  Vec3 centre;
  for (const Vec3& p : wall) centre = centre + (1.0 / static_cast<double>(wall.size())) * p;
  double size = 0;
  for (const Vec3& p : wall) size = std::max(size, length(p - centre));
  const double tolerance = kSubsurfaceTolerance * size;
  if (!(length(wallNormal) > 0 && length(windowNormal) > 0))
    throw InputError(path_, line.number,
                     at + ": it or its base has no area (its corners on one line)");
  const Vec3 unit = normalize(wallNormal);
  for (const Vec3& p : window)
    if (!(std::abs(dot(p - centre, unit)) <= tolerance))
      throw InputError(path_, line.number,
                       at + ": a corner lies off its base's plane: a subsurface lies in "
                            "its base");
  if (!(dot(windowNormal, wallNormal) > 0))
    throw InputError(path_, line.number,
                     at + ": it faces the other way from its base; list its vertices "
                          "counter-clockwise seen from the base's front");
  for (size_t k = 0; k < window.size(); ++k)
    if (!insidePolygon(wall, window[k], tolerance))
      throw InputError(path_, line.number,
                       at + ": its vertex " + std::to_string(corners[k] + 1) +
                           " lies outside its base: a subsurface lies within its base");
  holesOf_[base].push_back(n);
}

void Vs3Reader::addPolygons() {
  for (const Polygon& polygon : polygons_) {
    PolygonTriangulation triangles;
    std::vector<int64_t> corners = polygon.corners;
    const auto holes = holesOf_.find(polygon.surface);
    if (holes == holesOf_.end()) {
      triangles = triangulatePolygon(outline(corners));
    } else {
      std::vector<std::vector<Vec3>> cut;
      for (int64_t hole : holes->second) {
        cut.push_back(outline(cornersOf_[hole - 1]));
        corners.insert(corners.end(), cornersOf_[hole - 1].begin(), cornersOf_[hole - 1].end());
      }
      std::optional<PolygonTriangulation> region =
          triangulateWithHoles(outline(polygon.corners), cut);
      if (!region) {
        // The subsurface that does not fit alone, else the last one (it overlaps another).
        int64_t culprit = holes->second.back();
        for (int64_t hole : holes->second)
          if (!triangulateWithHoles(outline(polygon.corners), {outline(cornersOf_[hole - 1])})) {
            culprit = hole;
            break;
          }
        throw InputError(path_, lineOf_[culprit - 1],
                         "surface " + std::to_string(culprit) + " (a subsurface of surface " +
                             std::to_string(polygon.surface) +
                             "): its outline crosses its base's or another subsurface's, or it "
                             "overlaps another subsurface: subsurfaces lie within their base, "
                             "apart");
      }
      triangles = std::move(*region);
    }
    for (const Triangle& t : added_.triangles(triangles, corners)) {
      mesh_.triangles.push_back(t);
      mesh_.sourceFace.push_back(polygon.surface - 1);
      mesh_.reflectance.push_back(Rgb{polygon.rho, polygon.rho, polygon.rho});
      mesh_.emission.push_back(Rgb{0, 0, 0});
      mesh_.label.push_back(polygon.label);
    }
  }
}

}  // namespace

Mesh readVs3(const std::string& path) { return Vs3Reader(path).read(); }

}  // namespace radiosity::detail
