// The solve at the speed of memory: the bytes per second that products with F stream, against
// this machine's memory bandwidth measured in the same run by a STREAM-like triad. The solve's
// time is its products with F (PETSc's -log_view: MatMult is 80 % of the solve's flops at 10^6
// patches), and a product reads every nonzero once: memory-bound, so the triad is its ceiling.
//
// F is builtin:rooms' as `solve` samples it (kPatches patches, 32 rays, hemisphere estimator),
// in PETSc's AIJ form on one rank: ~ 5·10^6 nonzeros, ~ 60 MB, far beyond the caches.
//   BM_Triad            a = b + s c over 3 arrays of 2^25 doubles (STREAM counts 24 B/element)
//   BM_ProductOneChannel  y = F x (MatMult): what each channel's iteration does today
//   BM_ProductThreeChannels  Y = F X, X dense with 3 columns (MatMatMult): one pass over F for
//                         the three channels, what a block solve would do
//   BM_ProductThreeChannelsInterleaved  the same with the channels interleaved in one vector
//                         (PETSc's MAIJ: F ⊗ I_3, one row of F read once for all three)
// Bytes counted for a product (the least it must move): per nonzero its value and column index,
// per row its row pointer, x read and y written once per column (x's reuse from cache assumed).
// Sample run: bash bench/solve_bandwidth.sh build
#include <benchmark/benchmark.h>
#include <petscmat.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "formfactor/formfactor.h"
#include "io/scene/scene.h"
#include "partition/partition.h"

namespace radiosity {
namespace {

constexpr int64_t kPatches = 200000;
constexpr int64_t kTriadLength = int64_t{1} << 25;

void check(PetscErrorCode code) {
  if (code != 0) throw std::runtime_error("PETSc error " + std::to_string(code));
}

/// F of builtin:rooms with about kPatches patches, as a SeqAIJ matrix.
Mat roomsFormFactors() {
  static Mat F = [] {
    Mesh patches = partition::orderAlongCurve(partition::refineToCount(
        loadScene("builtin:rooms?patches=" + std::to_string(kPatches)), kPatches));
    normaliseForTracing(patches);
    const trace::SceneTracer tracer(patches);
    formfactor::Options options;
    options.raysPerPatch = 32;
    formfactor::Statistics statistics;
    const formfactor::SparseRows rows = formfactor::toFormFactors(
        formfactor::sampleRows(tracer, patches, 0, patches.triangleCount(), options, statistics));
    std::vector<PetscInt> rowStart(rows.rowStart.begin(), rows.rowStart.end());
    std::vector<PetscInt> column(rows.column.begin(), rows.column.end());
    std::vector<PetscScalar> value(rows.value.begin(), rows.value.end());
    Mat matrix;
    const PetscInt n = static_cast<PetscInt>(rows.rowCount());
    // MatCreateSeqAIJWithArrays does not copy: duplicate so that the arrays may go.
    Mat borrowed;
    check(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, n, n, rowStart.data(), column.data(),
                                    value.data(), &borrowed));
    check(MatDuplicate(borrowed, MAT_COPY_VALUES, &matrix));
    check(MatDestroy(&borrowed));
    return matrix;
  }();
  return F;
}

struct ProductSize {
  double rows = 0, nonzeros = 0;
};

ProductSize sizeOf(Mat F) {
  MatInfo info;
  check(MatGetInfo(F, MAT_LOCAL, &info));
  PetscInt rows, columns;
  check(MatGetSize(F, &rows, &columns));
  return {static_cast<double>(rows), info.nz_used};
}

double productBytes(const ProductSize& size, int columns) {
  return size.nonzeros * (sizeof(PetscScalar) + sizeof(PetscInt)) +
         (size.rows + 1) * sizeof(PetscInt) + 2.0 * columns * size.rows * sizeof(PetscScalar);
}

void BM_Triad(benchmark::State& state) {
  std::vector<double> a(kTriadLength), b(kTriadLength, 1.0), c(kTriadLength, 2.0);
  const double s = 3.0;
  for (auto _ : state) {
    for (int64_t i = 0; i < kTriadLength; ++i) a[i] = b[i] + s * c[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  state.counters["bytes/s"] = benchmark::Counter(3.0 * sizeof(double) * kTriadLength,
                                                 benchmark::Counter::kIsIterationInvariantRate);
  // (the CSV reporter wants every counter in every run, whichever order they run in)
  state.counters["channel-products/s"] = 0;
  state.counters["nonzeros"] = 0;
}

// The bytes a product of F with `channels` columns streams per second, and the channel-products.
void countProducts(benchmark::State& state, Mat F, int channels) {
  const ProductSize size = sizeOf(F);
  state.counters["bytes/s"] = benchmark::Counter(productBytes(size, channels),
                                                 benchmark::Counter::kIsIterationInvariantRate);
  state.counters["channel-products/s"] =
      benchmark::Counter(channels, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["nonzeros"] = size.nonzeros;
}

// y = A x with A = F (one channel) or F's MAIJ (channels interleaved in x and y).
void timeProducts(benchmark::State& state, Mat A, Mat F, int channels) {
  Vec x, y;
  check(MatCreateVecs(A, &x, &y));
  check(VecSet(x, 1.0));
  for (auto _ : state) check(MatMult(A, x, y));
  countProducts(state, F, channels);
  check(VecDestroy(&x));
  check(VecDestroy(&y));
}

void BM_ProductOneChannel(benchmark::State& state) {
  Mat F = roomsFormFactors();
  timeProducts(state, F, F, 1);
}

void BM_ProductThreeChannels(benchmark::State& state) {
  Mat F = roomsFormFactors();
  PetscInt n;
  check(MatGetSize(F, &n, nullptr));
  Mat X, Y = nullptr;
  check(MatCreateSeqDense(PETSC_COMM_SELF, n, 3, nullptr, &X));
  PetscScalar* values;
  check(MatDenseGetArray(X, &values));
  for (PetscInt k = 0; k < 3 * n; ++k) values[k] = 1.0;
  check(MatDenseRestoreArray(X, &values));
  check(MatMatMult(F, X, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &Y));
  for (auto _ : state) check(MatMatMult(F, X, MAT_REUSE_MATRIX, PETSC_DEFAULT, &Y));
  countProducts(state, F, 3);
  check(MatDestroy(&X));
  check(MatDestroy(&Y));
}

void BM_ProductThreeChannelsInterleaved(benchmark::State& state) {
  Mat F = roomsFormFactors();
  Mat F3;
  check(MatCreateMAIJ(F, 3, &F3));  // F applied to each of 3 interleaved components
  timeProducts(state, F3, F, 3);
  check(MatDestroy(&F3));
}

BENCHMARK(BM_Triad)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ProductOneChannel)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ProductThreeChannels)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ProductThreeChannelsInterleaved)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace radiosity

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (PetscInitializeNoArguments() != 0) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return PetscFinalize() == 0 ? 0 : 1;
}
