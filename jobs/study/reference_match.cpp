#include "jobs/study/reference_match.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace radiosity::jobs {

namespace {

std::string point(const Vec3& p) {
  std::ostringstream text;
  text.precision(9);
  text << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return text.str();
}

std::string colour(const Rgb& c) {
  std::ostringstream text;
  text.precision(9);
  text << c[0] << " " << c[1] << " " << c[2];
  return text.str();
}

bool closeTo(const Rgb& a, const Rgb& b) {
  for (int c = 0; c < 3; ++c)
    if (std::abs(a[c] - b[c]) > 1e-9 * std::max(std::abs(a[c]), std::abs(b[c]))) return false;
  return true;
}

}  // namespace

std::string meshDifference(const Mesh& reference, const Mesh& study) {
  if (reference.triangleCount() != study.triangleCount())
    return std::to_string(reference.triangleCount()) + " patches, the study's " +
           std::to_string(study.triangleCount());
  if (reference.vertices.size() != study.vertices.size())
    return std::to_string(reference.vertices.size()) + " vertices, the study's " +
           std::to_string(study.vertices.size());
  Vec3 lo, hi;
  study.boundingBox(lo, hi);
  const double tolerance = 1e-9 * std::max(length(hi - lo), 1e-300);
  for (int64_t t = 0; t < study.triangleCount(); ++t) {
    const std::string patch = "patch " + std::to_string(t);
    if (reference.triangles[t] != study.triangles[t]) return patch + " has other vertex indices";
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = reference.corner(t, k), b = study.corner(t, k);
      if (!(length(a - b) <= tolerance))
        return patch + "'s corner " + std::to_string(k) + " is at " + point(a) +
               ", the study's at " + point(b);
    }
    if (t < static_cast<int64_t>(reference.reflectance.size()) &&
        t < static_cast<int64_t>(study.reflectance.size()) &&
        !closeTo(reference.reflectance[t], study.reflectance[t]))
      return patch + "'s reflectance is " + colour(reference.reflectance[t]) + ", the study's " +
             colour(study.reflectance[t]);
    if (t < static_cast<int64_t>(reference.emission.size()) &&
        t < static_cast<int64_t>(study.emission.size()) &&
        !closeTo(reference.emission[t], study.emission[t]))
      return patch + "'s emission is " + colour(reference.emission[t]) + ", the study's " +
             colour(study.emission[t]);
  }
  return "";
}

}  // namespace radiosity::jobs
