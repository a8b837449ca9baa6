// What hierarchical transport would keep and what it would cost in accuracy, on one rank: the
// scene's rows sampled flat at `rays` and at `reference` rays; B solved (Jacobi) from the flat F
// and from the links the oracle makes of the same rows at each spread; each B's error against
// the reference's (measure/light_error.h), and the links per patch against F's nonzeros; then
// the hierarchy's own error (links of the reference's rows against its flat F), measured and as
// a first estimate from the links (ownErrorEstimate).
// Usage: build/bench/hierarchy_links SCENE PATCHES RAYS REFERENCE_RAYS ESTIMATOR SPREAD...
// (REFERENCE_RAYS 0: the entries alone, rows sampled a piece at a time, no flat F kept)
// where each SPREAD is the oracle's (hierarchy/links.h) with letters after it: s, receivers are
// patches (only sources grouped); e, light from emitters reaches patches; l, linear push; d, the
// direct light per patch apart (F E from the rows), the links carrying only the reflected light;
// f, receiver clusters within one input face; v, receiver clusters only where 8 probe rays
// between them and the source are all unblocked (w: 4 probe rays).
//   e.g. build/bench/hierarchy_links builtin:cornell 5000 256 4096 mis 0.4s 0.4 0.4el
#include <mpi.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "formfactor/formfactor.h"
#include "hierarchy/hierarchy.h"
#include "io/scene/scene.h"
#include "measure/light_error.h"
#include "partition/partition.h"

namespace radiosity {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// B = E + ρ ∘ G(B), channel by channel, by Jacobi from B = E until it changes by < 1e-12.
template <class Gather>
std::vector<Rgb> solve(const Mesh& patches, Gather gather) {
  const int64_t n = patches.triangleCount();
  std::vector<Rgb> b(patches.emission);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> x(n), h;
    for (int64_t i = 0; i < n; ++i) x[i] = patches.emission[i][c];
    for (int iteration = 0; iteration < 2000; ++iteration) {
      h = gather(x, c);
      double change = 0, size = 0;
      for (int64_t i = 0; i < n; ++i) {
        const double next = patches.emission[i][c] + patches.reflectance[i][c] * h[i];
        change = std::max(change, std::abs(next - x[i]));
        size = std::max(size, std::abs(next));
        x[i] = next;
      }
      if (change <= 1e-12 * size) break;
    }
    for (int64_t i = 0; i < n; ++i) b[i][c] = x[i];
  }
  return b;
}

std::vector<double> multiply(const SparseRows& f, const std::vector<double>& x) {
  std::vector<double> y(x.size(), 0.0);
  for (int64_t i = 0; i < f.rowCount(); ++i)
    for (int64_t k = f.rowStart[i]; k < f.rowStart[i + 1]; ++k) y[i] += f.value[k] * x[f.column[k]];
  return y;
}

std::array<double, 3> errorAgainst(const Mesh& patches, const std::vector<Rgb>& value,
                                   const std::vector<Rgb>& reference) {
  std::vector<double> area(patches.triangleCount());
  std::vector<Rgb> gap(value.size());
  for (int64_t i = 0; i < patches.triangleCount(); ++i) {
    area[i] = patches.area(i);
    for (int c = 0; c < 3; ++c) gap[i][c] = value[i][c] - reference[i][c];
  }
  return relativeLightError(MPI_COMM_SELF, area, patches.reflectance, reference, gap);
}

formfactor::Options samplingOptions(int64_t rays, formfactor::Estimator estimator) {
  formfactor::Options options;
  options.raysPerPatch = rays;
  options.estimator = estimator;
  options.threads = 2;
  return options;
}

SampleTally sampleAll(const trace::SceneTracer& tracer, const Mesh& patches, int64_t rays,
                      formfactor::Estimator estimator) {
  formfactor::RowSampling sampling(tracer, patches, samplingOptions(rays, estimator));
  formfactor::Statistics statistics;
  return sampling.sample(0, patches.triangleCount(), 0, rays, statistics);
}

// The hierarchy's own error in B, estimated per patch from its links (a prototype of the
// solve's estimate): a link's light is off where B varies over its source (its two children's
// means apart, times how much the kernel varies across the source, 2 r_S / d) and where the
// kernel's curvature over the receiver is left out by linear push (2 (r_R / d)²). The links'
// errors are added in squares down the tree, and B's is ρ times H's (no bounces).
std::vector<Rgb> ownErrorEstimate(const hierarchy::PatchTree& tree, const hierarchy::Links& links,
                                  const Mesh& patches, const std::vector<Rgb>& b,
                                  bool directApart) {
  const int64_t n = patches.triangleCount();
  std::vector<Rgb> estimate(static_cast<size_t>(n), Rgb{0, 0, 0});
  for (int c = 0; c < 3; ++c) {
    std::vector<double> x(n);
    for (int64_t i = 0; i < n; ++i) x[i] = b[i][c] - (directApart ? patches.emission[i][c] : 0.0);
    const std::vector<double> mean = hierarchy::pullMeans(tree, x);
    std::vector<double> squared(static_cast<size_t>(tree.nodeCount()), 0.0);
    for (int64_t k = 0; k < links.size(); ++k) {
      const int64_t r = links.receiver[k], s = links.source[k];
      const hierarchy::ClusterNode receiver = tree.node(r), source = tree.node(s);
      const double d = length(receiver.centroid - source.centroid);
      if (d <= 0) continue;
      double err = 0;
      if (!source.isLeaf()) {
        const auto [a, bb] = tree.children(s);
        const double spread = std::abs(mean[a] - mean[bb]) / 2;
        err += std::pow(links.factor[k] * spread * std::min(1.0, 2 * source.radius / d), 2);
      }
      if (!receiver.isLeaf()) {
        const double curve = std::min(1.0, 2 * std::pow(receiver.radius / d, 2));
        err += std::pow(links.factor[k] * mean[s] * curve, 2);
      }
      squared[r] += err;
    }
    for (int64_t id = 0; id < tree.innerCount(); ++id)
      for (int64_t child : tree.children(id)) squared[child] += squared[id];
    for (int64_t i = 0; i < n; ++i)
      estimate[i][c] = patches.reflectance[i][c] * std::sqrt(squared[tree.leafOf(i)]);
  }
  return estimate;
}

// Of the reflecting patches, the share whose measured error is within twice the estimate.
std::array<double, 3> coverage(const Mesh& patches, const std::vector<Rgb>& measured,
                               const std::vector<Rgb>& estimate) {
  std::array<double, 3> share{};
  for (int c = 0; c < 3; ++c) {
    int64_t within = 0, count = 0;
    for (int64_t i = 0; i < patches.triangleCount(); ++i) {
      if (patches.reflectance[i][c] <= 0 || patches.emission[i][c] > 0) continue;
      ++count;
      within += std::abs(measured[i][c]) <= 2 * estimate[i][c];
    }
    share[c] = count > 0 ? double(within) / double(count) : 0;
  }
  return share;
}

// One column of the table: the oracle's spread with its letters (the usage above).
struct Variant {
  hierarchy::LinkOracle oracle;
  hierarchy::Push push = hierarchy::Push::kUniform;
  bool directApart = false;
  int probeRays = 0;  ///< receivers grouped only where this many probe rays see the source whole
  std::string how = "links";
};

Variant variantOf(std::string spread) {
  Variant v;
  while (!spread.empty() && std::isalpha(static_cast<unsigned char>(spread.back()))) {
    const char flag = spread.back();
    spread.pop_back();
    if (flag == 's') v.oracle.patchReceivers = true;
    if (flag == 'e') v.oracle.patchReceiversOfEmitters = true;
    if (flag == 'l') v.push = hierarchy::Push::kLinear;
    if (flag == 'd') v.directApart = true;
    if (flag == 'f') v.oracle.receiversWithinFace = true;
    if (flag == 'v') v.probeRays = 8;
    if (flag == 'w') v.probeRays = 4;
    v.how += flag;
  }
  v.oracle.spread = std::stod(spread);
  return v;
}

// Without a reference: the rows sampled a piece at a time into one link tally per variant, as
// the form-factor stage would, counting F's nonzeros beside them (no flat F is kept: scenes of
// 10^6 patches and more).
void countLinks(const trace::SceneTracer& tracer, const Mesh& patches, int64_t rays,
                formfactor::Estimator estimator, const std::vector<Variant>& variants) {
  const int64_t n = patches.triangleCount();
  auto start = std::chrono::steady_clock::now();
  const hierarchy::PatchTree tree(patches);
  std::printf("tree: %lld nodes, %.0f B a patch, %.2f s\n",
              static_cast<long long>(tree.nodeCount()), double(tree.bytes()) / double(n),
              secondsSince(start));
  std::vector<hierarchy::LinkTally> tallies;
  std::vector<std::unique_ptr<hierarchy::VisibilityProbe>> probes;
  for (const Variant& v : variants) {
    hierarchy::LinkOracle oracle = v.oracle;
    if (v.probeRays > 0) {
      probes.push_back(std::make_unique<hierarchy::VisibilityProbe>(tracer, patches, v.probeRays));
      oracle.seesWhole = probes.back()->asOracle();
    }
    tallies.emplace_back(tree, oracle);
  }
  formfactor::RowSampling sampling(tracer, patches, samplingOptions(rays, estimator));
  formfactor::Statistics statistics;
  int64_t nonzeros = 0;
  double sampled = 0, linked = 0;
  const int64_t piece = 20000;
  for (int64_t first = 0; first < n; first += piece) {
    start = std::chrono::steady_clock::now();
    const SampleTally rows =
        sampling.sample(first, std::min(n, first + piece), 0, rays, statistics);
    sampled += secondsSince(start);
    nonzeros += static_cast<int64_t>(rows.column.size());
    start = std::chrono::steady_clock::now();
    for (hierarchy::LinkTally& tally : tallies) tally.add(rows);
    linked += secondsSince(start);
  }
  std::printf("%lld patches, %lld rays: sampled in %.1f s, linked in %.1f s\n",
              static_cast<long long>(n), static_cast<long long>(rays), sampled, linked);
  for (const auto& probe : probes)
    std::printf("probed %.1f pairs a patch\n", double(probe->probed()) / double(n));
  std::printf("%-10s %10s %12s %10s\n", "transport", "spread", "entries/patch", "B/patch");
  std::printf("%-10s %10s %12.1f %10.0f\n", "flat", "-", double(nonzeros) / double(n),
              12.0 * double(nonzeros) / double(n));
  for (size_t k = 0; k < variants.size(); ++k)
    std::printf("%-10s %10.3f %12.1f %10.0f\n", variants[k].how.c_str(), variants[k].oracle.spread,
                double(tallies[k].size()) / double(n),
                12.0 * double(tallies[k].size()) / double(n));
  // Where the links are: a patch or a cluster at each end, a patch apiece.
  std::printf("%-10s %14s %14s %14s %14s\n", "transport", "patch<-patch", "patch<-cluster",
              "cluster<-patch", "cluster<-both");
  for (size_t k = 0; k < variants.size(); ++k) {
    const hierarchy::Links links = tallies[k].links();
    double kinds[4] = {0, 0, 0, 0};
    for (int64_t l = 0; l < links.size(); ++l)
      kinds[2 * !tree.isLeaf(links.receiver[l]) + !tree.isLeaf(links.source[l])] += 1;
    std::printf("%-10s %14.1f %14.1f %14.1f %14.1f\n", variants[k].how.c_str(),
                kinds[0] / double(n), kinds[1] / double(n), kinds[2] / double(n),
                kinds[3] / double(n));
  }
}

}  // namespace
}  // namespace radiosity

int main(int argc, char** argv) {
  using namespace radiosity;
  MPI_Init(&argc, &argv);
  if (argc < 7) {
    std::fprintf(stderr, "usage: %s SCENE PATCHES RAYS REFERENCE_RAYS ESTIMATOR SPREAD...\n",
                 argv[0]);
    return 2;
  }
  const std::string scene = argv[1];
  const int64_t patchCount = std::stoll(argv[2]), rays = std::stoll(argv[3]),
                referenceRays = std::stoll(argv[4]);
  const formfactor::Estimator estimator = *valueNamed(formfactor::kEstimatorNames, argv[5]);
  Mesh patches = partition::orderAlongCurve(partition::refineToCount(loadScene(scene), patchCount));
  normaliseForTracing(patches);
  const trace::SceneTracer tracer(patches, 2);
  const int64_t n = patches.triangleCount();
  std::vector<Variant> variants;
  for (int a = 6; a < argc; ++a) variants.push_back(variantOf(argv[a]));
  if (referenceRays == 0) {
    countLinks(tracer, patches, rays, estimator, variants);
    MPI_Finalize();
    return 0;
  }

  auto start = std::chrono::steady_clock::now();
  const SampleTally reference = sampleAll(tracer, patches, referenceRays, estimator);
  const SparseRows referenceF = formfactor::toFormFactors(reference);
  const std::vector<Rgb> referenceB =
      solve(patches, [&](const std::vector<double>& x, int) { return multiply(referenceF, x); });
  std::printf("%s: %lld patches; reference %lld rays (%.1f s), %.1f nonzeros a row\n",
              scene.c_str(), static_cast<long long>(n), static_cast<long long>(referenceRays),
              secondsSince(start), double(referenceF.nonzeros()) / double(n));

  const SampleTally tally = sampleAll(tracer, patches, rays, estimator);
  const SparseRows flat = formfactor::toFormFactors(tally);
  const std::vector<Rgb> flatB =
      solve(patches, [&](const std::vector<double>& x, int) { return multiply(flat, x); });
  const auto flatError = errorAgainst(patches, flatB, referenceB);
  std::printf("%-10s %10s %12s %10s %10s %10s %8s\n", "transport", "spread", "entries/patch",
              "B/patch", "err R", "err G", "err B");
  std::printf("%-10s %10s %12.1f %10.0f %10.4f %10.4f %8.4f  (%lld rays)\n", "flat", "-",
              double(flat.nonzeros()) / double(n), 12.0 * double(flat.nonzeros()) / double(n),
              flatError[0], flatError[1], flatError[2], static_cast<long long>(rays));

  start = std::chrono::steady_clock::now();
  const hierarchy::PatchTree tree(patches);
  std::printf("tree: %lld nodes, %.0f B a patch, %.2f s\n",
              static_cast<long long>(tree.nodeCount()), double(tree.bytes()) / double(n),
              secondsSince(start));
  for (const Variant& variant : variants) {
    Variant v = variant;
    hierarchy::VisibilityProbe probe(tracer, patches, v.probeRays);
    if (v.probeRays > 0) v.oracle.seesWhole = probe.asOracle();
    start = std::chrono::steady_clock::now();
    const hierarchy::Links links = hierarchy::linksFromRows(tree, v.oracle, tally);
    const double linking = secondsSince(start);
    // d: the direct light D = F E per patch from the rows themselves, the links carrying only
    // the reflected light B − E (smooth where D has its shadows).
    const auto solveLinked = [&](const hierarchy::Links& links, const SparseRows& rows) {
      return solve(patches, [&](const std::vector<double>& x, int c) {
        if (!v.directApart) return hierarchy::transport(tree, links, x, v.push);
        std::vector<double> e(n), reflected(n);
        for (int64_t i = 0; i < n; ++i) {
          e[i] = patches.emission[i][c];
          reflected[i] = x[i] - e[i];
        }
        std::vector<double> h = multiply(rows, e);
        const std::vector<double> indirect = hierarchy::transport(tree, links, reflected, v.push);
        for (int64_t i = 0; i < n; ++i) h[i] += indirect[i];
        return h;
      });
    };
    const std::vector<Rgb> linkedB = solveLinked(links, flat);
    const auto error = errorAgainst(patches, linkedB, referenceB);
    std::printf("%-10s %10.3f %12.1f %10.0f %10.4f %10.4f %8.4f  (linking %.1f s)\n", v.how.c_str(),
                v.oracle.spread, double(links.size()) / double(n),
                12.0 * double(links.size()) / double(n), error[0], error[1], error[2], linking);
    // The hierarchy's own error: links made of the reference's rows against the reference's flat
    // F (little sampling noise in either, so what is left is the hierarchy's), measured and
    // estimated.
    const hierarchy::Links referenceLinks = hierarchy::linksFromRows(tree, v.oracle, reference);
    const std::vector<Rgb> referenceLinkedB = solveLinked(referenceLinks, referenceF);
    std::vector<double> area(n);
    std::vector<Rgb> own(n);
    for (int64_t i = 0; i < n; ++i) {
      area[i] = patches.area(i);
      for (int c = 0; c < 3; ++c) own[i][c] = referenceLinkedB[i][c] - referenceB[i][c];
    }
    const std::vector<Rgb> estimate =
        ownErrorEstimate(tree, referenceLinks, patches, referenceLinkedB, v.directApart);
    const auto measured = errorAgainst(patches, referenceLinkedB, referenceB);
    const auto estimated =
        relativeLightError(MPI_COMM_SELF, area, patches.reflectance, referenceB, estimate);
    const auto covered = coverage(patches, own, estimate);
    std::printf(
        "  own error (links of the reference's rows against its flat F): measured %.4f "
        "%.4f %.4f, estimated %.4f %.4f %.4f, within 2x the estimate %.2f %.2f %.2f\n",
        measured[0], measured[1], measured[2], estimated[0], estimated[1], estimated[2], covered[0],
        covered[1], covered[2]);
  }
  MPI_Finalize();
  return 0;
}
