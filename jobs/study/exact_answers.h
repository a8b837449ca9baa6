// Exact (or reference) answers for the accuracy study: B and H per patch for the built-in scenes
// that have them, so that `radiosity study` needs no --reference for those.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace radiosity::jobs {

struct ExactAnswer {
  std::vector<Rgb> radiosity;   ///< B per patch (all patches)
  std::vector<Rgb> irradiance;  ///< H = Σ_j F_ij B_j per patch
  std::string how;              ///< how it was obtained, e.g. "closed box: B = E/(1 - rho)"
};

/// The exact answer for the SCENE argument `scene` meshed into `patches` (loadScene(scene),
/// refined; each patch keeps its ρ, E and sourceFace):
/// - builtin:box (closed, uniform ρ and E): B = E/(1 − ρ), H = B.
/// - builtin:sphere (closed, uniform ρ, E possibly only on the cap): with F_ij = A_j/A (exact
///   for a sphere, up to faceting for the icosphere), Ē = Σ_j A_j E_j / A, H = Ē/(1 − ρ) and
///   B = E + ρ H.
/// - builtin:plates with ρ = 0 on both plates: B = E, H = 0 on the emitter and E × F(patch →
///   emitter rectangle) on the receiver, F by adaptive quadrature (Dunavant degree 8) of the
///   closed-form view factor from a point to the rectangle, to better than 1e-9.
/// nullopt for any other scene (then the study needs --reference), for plates with ρ > 0, and
/// where ρ = 1 or a non-uniform ρ or E leaves no closed form. Throws InputError if a scene
/// parameter is not a number.
std::optional<ExactAnswer> exactAnswer(const std::string& scene, const Mesh& patches);

/// The mean of `f` over the triangle abc, by the 16-point degree-8 rule of Dunavant (1985) with
/// adaptive subdivision into four (midpoint) triangles until the rule and its subdivision agree
/// within `tolerance` (on the mean, the same for every sub-triangle, so that the errors add up to
/// at most about `tolerance`), at most `maxDepth` subdivisions deep (for integrands with a
/// discontinuity at a point, whose deepest triangles then weigh 4^−maxDepth).
double meanOverTriangle(const std::function<double(const Vec3&)>& f, Vec3 a, Vec3 b, Vec3 c,
                        double tolerance, int maxDepth = 20);

}  // namespace radiosity::jobs
