// Hierarchical transport end to end across ranks, as `radiosity solve` would run it: each rank
// samples its block of rows a piece at a time into links and direct light (hierarchy::LinkedRows,
// no flat F kept), the ranks' links become one transport (hierarchy::BlockTransport) and GMRES
// solves B = E + ρ ∘ (D + T (B − E)) over it (solve/hierarchical_solve.h). Prints each stage's
// seconds, the links and bytes a patch, the largest rank's peak resident set, and B's area-means
// (the same on any rank count). The oracle: spread 0.4, receivers grouped only where PROBE_RAYS
// probe rays see the source whole (8), linear push (PUSH: linear or uniform).
// Usage: mpiexec -n RANKS build/bench/hierarchy_solve SCENE PATCHES RAYS [SPREAD] [PROBE_RAYS]
//        [PUSH] [PETSc options]
//   e.g. mpiexec -n 2 build/bench/hierarchy_solve builtin:rooms 100000 256
#include <mpi.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "formfactor/formfactor.h"
#include "hierarchy/hierarchy.h"
#include "io/scene/scene.h"
#include "partition/partition.h"
#include "solve/hierarchical_solve.h"
#include "solve/runtime.h"

namespace radiosity {
namespace {

void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  std::fprintf(stderr, "PETSc failed in %s (error %d)\n", what, static_cast<int>(code));
  MPI_Abort(MPI_COMM_WORLD, 1);
}

double largest(double value) {
  MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return value;
}

double total(double value) {
  MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return value;
}

double peakMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return largest(static_cast<double>(usage.ru_maxrss) / 1024.0);
}

// Seconds of each stage, the slowest rank's.
class Stages {
 public:
  void end(const char* name, int rank) {
    MPI_Barrier(MPI_COMM_WORLD);
    const double now = MPI_Wtime();
    if (rank == 0)
      std::printf("%-22s %8.1f s   peak %7.0f MB a rank\n", name, now - last_, peakMegabytes());
    else
      peakMegabytes();
    last_ = now;
  }

 private:
  double last_ = MPI_Wtime();
};

int run(int argc, char** argv) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const std::string scene = argv[1];
  const int64_t patchCount = std::stoll(argv[2]), rays = std::stoll(argv[3]);
  const double spread = argc > 4 ? std::stod(argv[4]) : 0.4;
  const int probeRays = argc > 5 ? std::stoi(argv[5]) : 8;
  const hierarchy::Push push = argc > 6 && std::string(argv[6]) == "uniform"
                                   ? hierarchy::Push::kUniform
                                   : hierarchy::Push::kLinear;
  Stages stages;
  Mesh patches = partition::orderAlongCurve(partition::refineToCount(loadScene(scene), patchCount));
  normaliseForTracing(patches);
  const int64_t n = patches.triangleCount();
  const partition::PatchRange owned = partition::blockOf(n, rank, ranks);
  const int threads = std::max(1, 2 / ranks);
  const trace::SceneTracer tracer(patches, threads);
  stages.end("mesh and tracer", rank);

  const hierarchy::PatchTree tree(patches);
  hierarchy::VisibilityProbe probe(tracer, patches, probeRays);
  hierarchy::LinkOracle oracle;
  oracle.spread = spread;
  if (probeRays > 0) oracle.seesWhole = probe.asOracle();
  stages.end("tree", rank);

  formfactor::Options options;
  options.raysPerPatch = rays;
  options.estimator = formfactor::Estimator::kEmitterMis;
  options.threads = threads;
  formfactor::RowSampling sampling(tracer, patches, options);
  formfactor::Statistics statistics;
  hierarchy::LinkedRows linked(tree, oracle, patches, owned);
  double sampled = 0, linking = 0;
  const int64_t piece = 20000;
  for (int64_t first = owned.begin; first < owned.end; first += piece) {
    double start = MPI_Wtime();
    const SampleTally rows =
        sampling.sample(first, std::min(owned.end, first + piece), 0, rays, statistics);
    sampled += MPI_Wtime() - start;
    start = MPI_Wtime();
    linked.add(rows);
    linking += MPI_Wtime() - start;
  }
  if (rank == 0) std::printf("  (rank 0: sampled %.1f s, linked %.1f s)\n", sampled, linking);
  stages.end("rows into links", rank);

  std::unique_ptr<hierarchy::BlockTransport> transport;
  check(hierarchy::BlockTransport::create(MPI_COMM_WORLD, tree, owned, linked.tally(), push,
                                          &transport),
        "BlockTransport::create");
  linked.dropLinks();
  const double links = total(static_cast<double>(transport->linkCount()));
  const double transportBytes = total(static_cast<double>(transport->bytes()));
  stages.end("transport", rank);

  const std::vector<Rgb> rho(patches.reflectance.begin() + owned.begin,
                             patches.reflectance.begin() + owned.end);
  const std::vector<Rgb> e(patches.emission.begin() + owned.begin,
                           patches.emission.begin() + owned.end);
  const solve::HierarchicalSystem system{*transport, rho, e, linked.direct()};
  solve::HierarchicalSolution solution;
  check(solve::solveHierarchical(MPI_COMM_WORLD, system, 1e-8, &solution), "solveHierarchical");
  stages.end("solve", rank);

  double mean[3] = {0, 0, 0}, area = 0;
  for (int64_t p = 0; p < owned.size(); ++p) {
    area += patches.area(owned.begin + p);
    for (int c = 0; c < 3; ++c) mean[c] += patches.area(owned.begin + p) * solution.radiosity[p][c];
  }
  area = total(area);
  for (double& m : mean) m = total(m) / area;
  const double probed = total(static_cast<double>(probe.probed()));
  if (rank == 0) {
    std::printf(
        "%lld patches, %d ranks, %lld rays: %.1f links a patch, transport %.0f B a patch "
        "(+ tree %.0f B a patch a rank), %.1f probes a patch\n",
        static_cast<long long>(n), ranks, static_cast<long long>(rays), links / double(n),
        transportBytes / double(n), double(tree.bytes()) / double(n), probed / double(n));
    std::printf("GMRES iterations %lld, transports (three channels each) %lld\n",
                static_cast<long long>(solution.iterations),
                static_cast<long long>(solution.transports));
    std::printf("area-mean B: %.10g %.10g %.10g\n", mean[0], mean[1], mean[2]);
  }
  return 0;
}

}  // namespace
}  // namespace radiosity

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s SCENE PATCHES RAYS [SPREAD] [PROBE_RAYS] [PUSH]\n", argv[0]);
    return 2;
  }
  radiosity::solve::Runtime runtime(argc, argv);  // (PETSc options such as -log_view)
  return radiosity::run(argc, argv);
}
