// builtin:rooms: a floor plan of rooms joined by doors, with a table, a shelf and a ceiling light
// in each, at any size from 10³ to 10⁷ triangles. Built for speed: every surface is an
// axis-aligned rectangle tessellated into a grid, and vertices are welded once at the end by
// sorting, with no allocation per triangle.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "io/scene/grid_rectangles.h"
#include "io/scene/scene_internal.h"

namespace radiosity::detail {
namespace {

// Dimensions in metres. Rooms repeat with pitch kPitch; walls are kWall thick, so a room is
// 3.9 m square inside. Doors are centred in every wall between two rooms; the light is centred
// in the ceiling. Its edges and the door's are grid lines of the floor, ceiling and walls.
constexpr double kPitch = 4.0, kWall = 0.1, kHeight = 2.5;
constexpr double kDoorWidth = 0.9, kDoorHeight = 2.1, kLightSize = 1.5;
constexpr double kTableX = 1.2, kTableZ = 0.8, kTableHeight = 0.75;
constexpr double kShelfWidth = 0.9, kShelfDepth = 0.35, kShelfHeight = 2.0, kShelfGap = 0.05;

/// Triangles per room aimed at; the tessellation then makes up the difference.
constexpr double kTrianglesPerRoom = 2000;

const Rgb kFloor = {0.55, 0.45, 0.35}, kWallColour = {0.75, 0.75, 0.72}, kCeiling = {0.8, 0.8, 0.8};
const Rgb kTable = {0.5, 0.35, 0.2}, kShelf = {0.35, 0.4, 0.55}, kLamp = {0.8, 0.8, 0.8};

enum Label : int32_t {
  kFloorLabel,
  kCeilingLabel,
  kWallLabel,
  kDoorLabel,
  kLightLabel,
  kTableLabel,
  kShelfLabel
};
const char* const kLabelNames[] = {"floor", "ceiling", "wall", "door", "light", "table", "shelf"};

/// An axis-aligned rectangle at coordinate `c` on axis `axis`, spanning axes a1 = axis + 1 and
/// a2 = axis + 2 (mod 3) over the breakpoints u and v, lit on the side `facing` (+1 or −1) of
/// `axis`. Cells [skipU0, skipU1) × [skipV0, skipV1) of the breakpoint grid are holes.
struct Rect {
  int axis;
  double c;
  Breaks u, v;
  int facing;
  Label label;
  int skipU0 = 0, skipU1 = 0, skipV0 = 0, skipV1 = 0;
  bool skipped(int i, int j) const {
    return i >= skipU0 && i < skipU1 && j >= skipV0 && j < skipV1;
  }
};

/// The element size whose triangle count is nearest the target (in ratio). The count falls as
/// h grows, in steps, so bisect on log h.
double elementSize(const std::vector<Rect>& rects, int64_t target) {
  double lo = 1e-4, hi = 2 * kPitch;  // count(lo) ≥ target > count(hi) for any size allowed
  for (int step = 0; step < 50; ++step) {
    const double mid = std::sqrt(lo * hi);
    (triangleCount(rects, mid) >= target ? lo : hi) = mid;
  }
  const double over = double(triangleCount(rects, lo)) / target;
  const double under = double(target) / std::max<int64_t>(1, triangleCount(rects, hi));
  return over <= under ? lo : hi;
}

/// A closed box [lo, hi] without its bottom (it stands on the floor), lit outside.
void addBox(std::vector<Rect>& rects, Vec3 lo, Vec3 hi, Label label) {
  rects.push_back({1, hi.y, {lo.z, hi.z}, {lo.x, hi.x}, +1, label});  // top
  rects.push_back({0, lo.x, {lo.y, hi.y}, {lo.z, hi.z}, -1, label});
  rects.push_back({0, hi.x, {lo.y, hi.y}, {lo.z, hi.z}, +1, label});
  rects.push_back({2, lo.z, {lo.x, hi.x}, {lo.y, hi.y}, -1, label});
  rects.push_back({2, hi.z, {lo.x, hi.x}, {lo.y, hi.y}, +1, label});
}

/// Room (i, k) of an nx × nz plan: inner surfaces lit inside, a door passage towards the +x and
/// +z neighbours, a table and a shelf placed by `seed`.
void addRoom(std::vector<Rect>& rects, int i, int k, int nx, int nz, uint64_t seed) {
  // The same expressions for a room's far wall and its neighbour's near wall, so that the door
  // passage between them meets both floors at bit-identical coordinates.
  auto nearWall = [](int n) { return n * kPitch + kWall / 2; };
  auto farWall = [](int n) { return (n + 1) * kPitch - kWall / 2; };
  const double x0 = nearWall(i), x1 = farWall(i), z0 = nearWall(k), z1 = farWall(k);
  const double xc = (i + 0.5) * kPitch, zc = (k + 0.5) * kPitch;
  // Breakpoints: walls, light edges, door edges. Interval 2 is the door, 1–3 the light.
  const Breaks xs = {
      x0, xc - kLightSize / 2, xc - kDoorWidth / 2, xc + kDoorWidth / 2, xc + kLightSize / 2, x1};
  const Breaks zs = {
      z0, zc - kLightSize / 2, zc - kDoorWidth / 2, zc + kDoorWidth / 2, zc + kLightSize / 2, z1};
  const Breaks ys = {0, kDoorHeight, kHeight};
  const bool doorLowX = i > 0, doorHighX = i + 1 < nx, doorLowZ = k > 0, doorHighZ = k + 1 < nz;

  rects.push_back({1, 0, zs, xs, +1, kFloorLabel});
  Rect ceiling{1, kHeight, zs, xs, -1, kCeilingLabel, 1, 4, 1, 4};
  rects.push_back(ceiling);
  const Breaks lightZ = {zs.at[1], zs.at[2], zs.at[3], zs.at[4]};
  const Breaks lightX = {xs.at[1], xs.at[2], xs.at[3], xs.at[4]};
  rects.push_back({1, kHeight, lightZ, lightX, -1, kLightLabel});
  // Walls: the door cell is interval 2 along the wall and 0 in height.
  auto wall = [&](int axis, double c, const Breaks& along, int facing, bool door) {
    Rect r = axis == 2 ? Rect{2, c, along, ys, facing, kWallLabel}
                       : Rect{0, c, ys, along, facing, kWallLabel};
    if (door) {
      if (axis == 2) {
        r.skipU0 = 2, r.skipU1 = 3, r.skipV0 = 0, r.skipV1 = 1;
      } else {
        r.skipU0 = 0, r.skipU1 = 1, r.skipV0 = 2, r.skipV1 = 3;
      }
    }
    rects.push_back(r);
  };
  wall(2, z0, xs, +1, doorLowZ);
  wall(2, z1, xs, -1, doorHighZ);
  wall(0, x0, zs, +1, doorLowX);
  wall(0, x1, zs, -1, doorHighX);
  // Door passages through the walls to the +x and +z neighbours: floor, lintel, two jambs.
  if (doorHighX) {
    const Breaks across = {x1, nearWall(i + 1)}, door = {zs.at[2], zs.at[3]};
    rects.push_back({1, 0, door, across, +1, kDoorLabel});
    rects.push_back({1, kDoorHeight, door, across, -1, kDoorLabel});
    rects.push_back({2, door.at[0], across, {0, kDoorHeight}, +1, kDoorLabel});
    rects.push_back({2, door.at[1], across, {0, kDoorHeight}, -1, kDoorLabel});
  }
  if (doorHighZ) {
    const Breaks across = {z1, nearWall(k + 1)}, door = {xs.at[2], xs.at[3]};
    rects.push_back({1, 0, across, door, +1, kDoorLabel});
    rects.push_back({1, kDoorHeight, across, door, -1, kDoorLabel});
    rects.push_back({0, door.at[0], {0, kDoorHeight}, across, +1, kDoorLabel});
    rects.push_back({0, door.at[1], {0, kDoorHeight}, across, -1, kDoorLabel});
  }

  // A shelf against one of the four walls, beside its door; a table, turned or not, in the
  // middle, clear of the shelf.
  const uint64_t room = static_cast<uint64_t>(k) * static_cast<uint64_t>(nx) + i;
  const int side = static_cast<int>(4 * splitMixUniform(seed, room, 0));
  const double inner = x1 - x0, slack = (inner - kDoorWidth) / 2 - kShelfWidth - 0.2;
  const double offset = 0.1 + slack * splitMixUniform(seed, room, 1);  // from the wall's start
  const bool beforeDoor = splitMixUniform(seed, room, 2) < 0.5;
  const double start = beforeDoor ? offset : inner - offset - kShelfWidth;
  const double depth0 = kShelfGap, depth1 = kShelfGap + kShelfDepth;
  Vec3 lo, hi;
  switch (side) {
    case 0:
      lo = {x0 + start, 0, z0 + depth0}, hi = {x0 + start + kShelfWidth, kShelfHeight, z0 + depth1};
      break;
    case 1:
      lo = {x0 + start, 0, z1 - depth1}, hi = {x0 + start + kShelfWidth, kShelfHeight, z1 - depth0};
      break;
    case 2:
      lo = {x0 + depth0, 0, z0 + start}, hi = {x0 + depth1, kShelfHeight, z0 + start + kShelfWidth};
      break;
    default:
      lo = {x1 - depth1, 0, z0 + start}, hi = {x1 - depth0, kShelfHeight, z0 + start + kShelfWidth};
      break;
  }
  addBox(rects, lo, hi, kShelfLabel);
  const bool turned = splitMixUniform(seed, room, 3) < 0.5;
  const double hx = (turned ? kTableZ : kTableX) / 2, hz = (turned ? kTableX : kTableZ) / 2;
  const double margin = kShelfGap + kShelfDepth + 0.3 + kTableX / 2;  // any turn fits
  const double cx = x0 + margin + (inner - 2 * margin) * splitMixUniform(seed, room, 4);
  const double cz = z0 + margin + (inner - 2 * margin) * splitMixUniform(seed, room, 5);
  addBox(rects, {cx - hx, 0, cz - hz}, {cx + hx, kTableHeight, cz + hz}, kTableLabel);
}

/// The material of a rectangle: ρ and E.
void materialOf(const Rect& r, double light, Rgb& rho, Rgb& e) {
  e = {0, 0, 0};
  switch (r.label) {
    case kFloorLabel:
      rho = kFloor;
      break;
    case kCeilingLabel:
      rho = kCeiling;
      break;
    case kWallLabel:
      rho = kWallColour;
      break;
    case kDoorLabel:
      rho = r.axis == 1 && r.facing > 0 ? kFloor : kWallColour;
      break;
    case kLightLabel:
      rho = kLamp, e = {light, light, light};
      break;
    case kTableLabel:
      rho = kTable;
      break;
    case kShelfLabel:
      rho = kShelf;
      break;
  }
}

/// Tessellates every rectangle into an h-grid, welded into one mesh (grid_rectangles.h).
Mesh tessellate(const std::vector<Rect>& rects, double h, double light) {
  Mesh mesh = tessellateRectangles(rects, h, [&](size_t f, const Rect& r) {
    RectangleSurface surface{static_cast<int64_t>(f), {}, {}, r.label};
    materialOf(r, light, surface.reflectance, surface.emission);
    return surface;
  });
  mesh.labelNames.assign(std::begin(kLabelNames), std::end(kLabelNames));
  return mesh;
}

}  // namespace

Mesh buildRooms(int64_t patches, uint64_t seed, double light) {
  const auto rooms = std::max<int64_t>(1, std::llround(patches / kTrianglesPerRoom));
  const int nx = static_cast<int>(std::max<int64_t>(1, std::llround(std::sqrt(double(rooms)))));
  const int nz = static_cast<int>(std::max<int64_t>(1, std::llround(double(rooms) / nx)));
  std::vector<Rect> rects;
  rects.reserve(static_cast<size_t>(nx) * nz * 40);
  for (int k = 0; k < nz; ++k) {
    for (int i = 0; i < nx; ++i) addRoom(rects, i, k, nx, nz, seed);
  }
  return tessellate(rects, elementSize(rects, patches), light);
}

}  // namespace radiosity::detail
