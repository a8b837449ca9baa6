// Private to formfactor/: what one thread needs to sample rows of F (RowSampling gives each
// thread one). A row is sampled in three passes over its samples: make the rays, trace them
// (the tight loop of bare Embree), score the hits; with emitter MIS, again for the shadow rays.
#pragma once

#include <cstdint>
#include <vector>

#include "formfactor/emitter_set.h"
#include "formfactor/exact_rows.h"
#include "formfactor/formfactor.h"
#include "formfactor/light_choice.h"

namespace radiosity::formfactor {

class ThreadSampler {
 public:
  /// Keeps references to all but `options`, which must outlive it; `normals`: of every patch;
  /// `exact`: rows by closed forms instead of rays, or null.
  ThreadSampler(const SceneTracer& tracer, const Mesh& patches, const std::vector<Vec3>& normals,
                const Options& options, const EmitterSet& emitters, const ExactRows* exact);

  /// Samples row i, its emitter samples aimed by `lights`, and appends it to (sorted columns,
  /// fixed-point sums).
  void sampleRow(int64_t i, const LightChoice& lights, std::vector<int64_t>& columns,
                 std::vector<int64_t>& sums);

  bool castsTwoRaysPerSample() const { return mis_; }

  /// The statistics gathered since the last call, which starts them again.
  Statistics takeStatistics();

  /// Samples [firstSample, firstSample + count) of every row from now on.
  void setSamples(int64_t firstSample, int64_t count);

 private:
  void scoreHemisphereRays(int64_t i, Vec3 normal);
  void makeEmitterRays(int64_t i, Vec3 normal);
  void scoreEmitterRays();
  /// Whether every ray of the batch from patch i met a back (or i itself).
  bool seesOnlyBacks(int64_t i) const;

  void add(int64_t column, int64_t amount);
  void add(int64_t column, double amount);
  /// The row's sums, in column order, appended; the accumulator is left zero.
  void appendAccumulated(std::vector<int64_t>& columns, std::vector<int64_t>& sums);
  void appendPairs(std::vector<int64_t>& columns, std::vector<int64_t>& sums);

  const SceneTracer& tracer_;
  const ExactRows* exact_;  ///< rows without rays, or null
  const Mesh& patches_;
  const std::vector<Vec3>& normals_;  ///< of every patch, computed once
  Options options_;
  const LightChoice* lights_ = nullptr;  ///< of the row being sampled
  const bool mis_;
  Statistics statistics_;
  SceneTracer::RayBatch rays_;
  SceneTracer::HitBatch hits_;
  std::vector<uint32_t> scratch_;
  std::vector<int64_t> emitterTarget_;  ///< per sample: the emitter patch aimed at, or -1
  std::vector<double> emitterWeight_;   ///< per sample: its MIS weight p_h / (p_h + p_e)
  /// Sums per column of the row being sampled (zero elsewhere): a dense array of one int64 per
  /// patch per thread, cheaper than sorting every contribution.
  std::vector<int64_t> accumulator_;
  std::vector<int64_t> touched_;  ///< columns with a nonzero sum in the current row
  /// Rows of at most kFewHits samples (MIS: two rays each) in scenes of at least kLargeScene
  /// patches are summed from their hits sorted: there the accumulator, out of cache, costs a
  /// miss per hit; in smaller scenes it stays in cache and beats the sort (measured with
  /// bench/formfactor_ratio.sh). So is every row of a scene of more than kDenseMaxPatches,
  /// whose accumulators (256 MB a thread at the bound) a node's threads could not all hold:
  /// 68 GB on 32 threads at 2.65·10^8 patches (docs/scaling-model.md, "Adaptive meshes at
  /// 10^8 patches' detail"). The sums are the same integers either way.
  static constexpr int64_t kFewHits = 256, kLargeScene = int64_t{1} << 17,
                           kDenseMaxPatches = int64_t{1} << 25;
  bool sortHits_ = false;
  struct Hit {
    int64_t column, amount;
  };
  std::vector<Hit> pairs_;  ///< the current row's hits, when sortHits_
};

}  // namespace radiosity::formfactor
