// Exact rows: which scenes have them (every vertex on or in front of every triangle's plane)
// and the rows themselves.
#include "formfactor/exact_rows.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "formfactor/formfactor.h"

namespace radiosity::formfactor {

double planeSlack(const Mesh& patches) {
  Vec3 low{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3 high = -1.0 * low;
  for (const Vec3& v : patches.vertices) {
    for (int k = 0; k < 3; ++k) {
      low[k] = std::min(low[k], v[k]);
      high[k] = std::max(high[k], v[k]);
    }
  }
  return patches.vertices.empty() ? 0.0 : 1e-9 * length(high - low);
}

// Each triangle's plane has the whole scene on its lit side, so the scene lies on the boundary
// of a convex body, lit side in: the segment between points of two triangles that are not in
// one plane runs inside the body and meets no third triangle (it could only touch a third
// triangle's plane by lying in it, and then both ends would too). Stops at the first vertex
// behind a plane: for most scenes that are not convex, after a few triangles.
bool everyPairUnoccluded(const Mesh& patches) {
  const double slack = planeSlack(patches);
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    const Vec3 n = patches.normal(t), origin = patches.corner(t, 0);
    for (const Vec3& v : patches.vertices) {
      if (dot(n, v - origin) < -slack) return false;
    }
  }
  return true;
}

bool convexEnclosure(const Mesh& mesh) { return everyPairUnoccluded(mesh); }

RowsChoice chooseRows(const Mesh& patches, int64_t raysPerPatch) {
  const int64_t n = patches.triangleCount();
  if (n > kExactRowsMaxPatches)
    return {false, "rows sampled: " + std::to_string(n) + " patches are more than exact rows " +
                       "are made for (" + std::to_string(kExactRowsMaxPatches) +
                       ", an entry per patch a row)"};
  if (!everyPairUnoccluded(patches)) {
    return {false, "rows sampled: patches hide others (the scene is not one convex enclosure)"};
  }
  if (n > kExactPatchesPerRay * raysPerPatch) {  // (a pair's closed form costs about a ray)
    const int64_t rays = (n + kExactPatchesPerRay - 1) / kExactPatchesPerRay;
    return {false, "rows sampled, though the scene is convex: its " + std::to_string(n) +
                       " patches are more than " + std::to_string(kExactPatchesPerRay) + " × " +
                       std::to_string(raysPerPatch) +
                       " rays per patch, the cost exact rows are allowed (--rays " +
                       std::to_string(rays) + " or more would make them exact)"};
  }
  return {true,
          "rows exact, without rays: every pair of patches that face each other sees each other "
          "whole (a convex scene), so each F_ij is a closed form integrated over patch i"};
}

ExactRows::ExactRows(const Mesh& patches, bool onFloats, bool pairsOnce)
    : slack_(planeSlack(patches)), onFloats_(onFloats), pairsOnce_(pairsOnce) {
  shapes_.reserve(static_cast<size_t>(patches.triangleCount()));
  for (int64_t t = 0; t < patches.triangleCount(); ++t) {
    const Triangle corners{patches.corner(t, 0), patches.corner(t, 1), patches.corner(t, 2)};
    shapes_.emplace_back(corners, patches.normal(t));
    table_.add(corners);
  }
}

namespace {

// Row i's entries (its columns in ascending order and their units) appended as sums over
// `samples`: with pairsOnce, those of the pairs it owns and, in its diagonal's place, the units of
// the others (held by the rows that own them, through reciprocity).
void appendUnits(int64_t i, const std::vector<int64_t>& rowColumns,
                 const std::vector<int64_t>& units, int64_t samples, bool pairsOnce,
                 std::vector<int64_t>& columns, std::vector<int64_t>& sums) {
  int64_t rest = 0;
  for (size_t k = 0; k < units.size(); ++k)
    if (pairsOnce && units[k] > 0 && !ownsPair(i, rowColumns[k])) rest += units[k];
  bool diagonal = rest == 0;
  const auto placeDiagonal = [&] {
    columns.push_back(i);
    sums.push_back(rest * samples);
    diagonal = true;
  };
  for (size_t k = 0; k < units.size(); ++k) {
    if (units[k] <= 0) continue;
    const int64_t j = rowColumns[k];
    if (!diagonal && j > i) placeDiagonal();
    if (pairsOnce && !ownsPair(i, j)) continue;
    columns.push_back(j);
    sums.push_back(units[k] * samples);
  }
  if (!diagonal) placeDiagonal();
}

}  // namespace

ExactRows::Appended ExactRows::appendRow(int64_t i, int64_t samples, std::vector<int64_t>& columns,
                                         std::vector<int64_t>& sums) const {
  const PatchShape& from = shapes_[static_cast<size_t>(i)];
  const auto n = static_cast<int64_t>(shapes_.size());
  const auto first = columns.size();
  std::vector<double> values;
  std::array<std::vector<double>, 3> atPoint;
  for (auto& a : atPoint) a.resize(shapes_.size());
  threePointFactors(from, table_, atPoint[0].data(), atPoint[1].data(), atPoint[2].data());
  std::array<double, 3> covered{0, 0, 0};  // per point of the three-point rule
  double valueSum = 0;
  for (int64_t j = 0; j < n; ++j) {
    const PatchShape& to = shapes_[static_cast<size_t>(j)];
    if (j == i || !inFrontOfPlane(to.corners, from.corners[0], from.normal, slack_) ||
        !inFrontOfPlane(from.corners, to.corners[0], to.normal, slack_)) {
      continue;
    }
    const std::array<double, 3> atRulePoints{atPoint[0][j], atPoint[1][j], atPoint[2][j]};
    for (int k = 0; k < 3; ++k) covered[k] += atRulePoints[k];
    const double value = triangleToTriangleFactor(from, to, atRulePoints);
    valueSum += value;
    columns.push_back(j);
    values.push_back(value);
  }
  // Where the patches cover the whole hemisphere of the rule's points, they cover that of every
  // point of i (in a convex scene an opening seen from one point of i is seen from all), and the
  // row sums to 1 exactly: scaled to it, as a closed scene's sampled rows sum to 1 (every ray
  // hits). The rules alone leave it off by their tolerance, which B = E/(1 − ρ) magnifies at
  // a reflectance near 1.
  bool closed = valueSum > 0;
  for (double share : covered) closed = closed && std::abs(share - 1) <= kClosedSlack;
  const double rowSum = closed ? 1.0 : valueSum;
  const double scale = closed ? 1.0 / valueSum : 1.0;
  // In units of 2^-32, rounded so that the units add up to the rounded row sum: rounding each
  // alone would leave ~√N · 1e-10 on the row.
  std::vector<double> exact(values.size());
  for (size_t k = 0; k < values.size(); ++k) exact[k] = values[k] * scale * 0x1p32;
  const int64_t target = std::llround(rowSum * 0x1p32);
  const std::vector<int64_t> units = roundToUnits(exact, target, onFloats_);
  const std::vector<int64_t> rowColumns(columns.begin() + static_cast<std::ptrdiff_t>(first),
                                        columns.end());
  columns.resize(first);
  appendUnits(i, rowColumns, units, samples, pairsOnce_, columns, sums);
  int64_t total = 0;
  for (int64_t u : units) total += u;
  return {static_cast<int64_t>(values.size()), total != target};
}

void keepExactRowsOnFloats(SampleTally& rows) {
  const int64_t samples = rows.samples;
  if (samples <= 0) return;
  size_t kept = 0;
  std::vector<int64_t> start{0};
  for (int64_t r = 0; r < rows.rowCount(); ++r) {
    const auto begin = static_cast<size_t>(rows.rowStart[r]),
               end = static_cast<size_t>(rows.rowStart[r + 1]);
    std::vector<double> exact;
    int64_t sum = 0;
    for (size_t k = begin; k < end; ++k) {
      exact.push_back(static_cast<double>(rows.sum[k]) / static_cast<double>(samples));
      sum += rows.sum[k];
    }
    const std::vector<int64_t> units = roundToUnits(exact, (sum + samples / 2) / samples, true);
    for (size_t k = begin; k < end; ++k) {
      if (units[k - begin] <= 0) continue;
      rows.column[kept] = rows.column[k];
      rows.sum[kept++] = units[k - begin] * samples;
    }
    start.push_back(static_cast<int64_t>(kept));
  }
  rows.column.resize(kept);
  rows.sum.resize(kept);
  rows.rowStart = std::move(start);
}

namespace {

// One more unit each (`step` +1) or one less (−1) for up to `count` of the entries `candidates`
// names, those with the largest remainders first to give, the smallest first to take (ties by
// position: the order is total, so the set is one).
void handOut(std::vector<int64_t>& units, const std::vector<double>& remainder,
             std::vector<size_t>& candidates, int64_t count, int step) {
  const auto m =
      static_cast<size_t>(std::clamp<int64_t>(count, 0, static_cast<int64_t>(candidates.size())));
  std::nth_element(candidates.begin(), candidates.begin() + static_cast<std::ptrdiff_t>(m),
                   candidates.end(), [&](size_t a, size_t b) {
                     const double ra = step * remainder[a], rb = step * remainder[b];
                     return ra > rb || (ra == rb && a < b);
                   });
  for (size_t k = 0; k < m; ++k) units[candidates[k]] += step;
}

}  // namespace

std::vector<int64_t> roundToUnits(const std::vector<double>& exact, int64_t total, bool onFloats) {
  constexpr double kFloatWhole = 0x1p24;    // from here on a float's grid is coarser than a unit
  constexpr int64_t kAdjustable = 1 << 23;  // room for several units more below kFloatWhole
  std::vector<int64_t> units(exact.size());
  std::vector<double> remainder(exact.size());
  std::vector<size_t> candidates;
  candidates.reserve(exact.size());
  int64_t left = total;
  for (size_t k = 0; k < exact.size(); ++k) {
    if (onFloats && exact[k] >= kFloatWhole) {  // (a power of two apart: float's own rounding)
      units[k] = static_cast<int64_t>(static_cast<double>(static_cast<float>(exact[k])));
    } else {
      units[k] = static_cast<int64_t>(std::floor(exact[k]));
      remainder[k] = exact[k] - static_cast<double>(units[k]);
      if (!onFloats || units[k] < kAdjustable) candidates.push_back(k);
    }
    left -= units[k];
  }
  if (!onFloats) {  // (as before floats: one pass, the units left never exceed the entries)
    handOut(units, remainder, candidates, left, +1);
    return units;
  }
  while (left != 0 && !candidates.empty()) {
    const int step = left > 0 ? +1 : -1;
    if (step < 0)  // (a unit taken from an entry of none would make it negative)
      std::erase_if(candidates, [&](size_t k) { return units[k] == 0; });
    const auto given = std::min<int64_t>(std::abs(left), static_cast<int64_t>(candidates.size()));
    handOut(units, remainder, candidates, given, step);
    left -= step * given;
  }
  return units;
}

}  // namespace radiosity::formfactor
