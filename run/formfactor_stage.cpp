#include "run/formfactor_stage.h"

#include <algorithm>

#include "run/rank_balance.h"

namespace radiosity::run {

namespace {

constexpr int64_t kPiecesPerRank = 200;  // safe points in the stage: ~0.5 % of it between two

// Rows [from, to) of what was saved (a checkpoint's tally, or an earlier round's one store of F).
SampleTally savedSlice(const SampledRows& saved, int64_t from, int64_t to, int64_t samples) {
  if (saved.values.rowCount() > 0) return saved.values.tally(from, to);
  return saved.tally.slice(from, to, samples);
}

// Appends `rows`.
void append(SampleTally& to, const SampleTally& rows) {
  const auto base = static_cast<int64_t>(to.column.size());
  to.column.insert(to.column.end(), rows.column.begin(), rows.column.end());
  to.sum.insert(to.sum.end(), rows.sum.begin(), rows.sum.end());
  for (int64_t r = 1; r <= rows.rowCount(); ++r) to.rowStart.push_back(base + rows.rowStart[r]);
}

// The rows done so far followed by the saved rows not reached yet, as one tally.
SampledRows snapshot(const formfactor::SplitRows& done, int64_t samples, const SampledRows& saved) {
  const int64_t cursor = done.rowCount(), count = static_cast<int64_t>(saved.rowSamples.size());
  SampledRows now;
  now.tally = done.tally(0, cursor);
  append(now.tally, savedSlice(saved, cursor, count, 0));
  now.rowSamples.assign(cursor, samples);
  now.rowSamples.insert(now.rowSamples.end(), saved.rowSamples.begin() + cursor,
                        saved.rowSamples.end());
  return now;
}

// Lends the rows so far to hooks.save. Where no saved row lies past the cursor (a round sampled
// afresh), that is F's store itself, its rows past the cursor empty (0 samples): no copy, where a
// tally of the rows so far took 16 B a nonzero beside the store's 12 while it was written.
// Otherwise (a restart's rows ahead) one tally of both, made for the write and let go.
void checkpointRows(formfactor::SplitRows& done, int64_t samples, const SampledRows& saved,
                    const SamplingHooks& hooks) {
  const int64_t cursor = done.rowCount();
  const bool savedAhead = std::any_of(saved.rowSamples.begin() + cursor, saved.rowSamples.end(),
                                      [](int64_t s) { return s > 0; });
  if (savedAhead || cursor == 0) {
    SampledRows copy = snapshot(done, samples, saved);
    hooks.save(copy);
    return;
  }
  SampledRows lent;
  lent.rowSamples.assign(cursor, samples);
  lent.rowSamples.resize(saved.rowSamples.size(), 0);
  lent.values = std::move(done);
  struct GiveBack {  // (also when the save throws: the caller may still hold on to its rows)
    formfactor::SplitRows& to;
    SampledRows& from;
    ~GiveBack() { to = std::move(from.values); }
  } giveBack{done, lent};
  hooks.save(lent);
}

}  // namespace

formfactor::SplitRows sampleOwnedRows(const OwnedRowsJob& job, SampledRows saved,
                                      const SamplingHooks& hooks,
                                      formfactor::Statistics& statistics) {
  const partition::PatchRange owned = job.owned;
  const int64_t count = owned.size(), samples = job.options.raysPerPatch;
  if (saved.rowSamples.empty()) {  // nothing saved: every row still to sample
    saved.tally = SampleTally();
    saved.tally.firstRow = owned.begin;
    saved.tally.rowStart.assign(count + 1, 0);
    saved.rowSamples.assign(count, 0);
  }
  // The same number of pieces on every rank, so that the safe points (collectives) match, each
  // the same share of a rank's rows: blocks cut by cost differ in count, not in work.
  int64_t largest = 0;
  MPI_Allreduce(&count, &largest, 1, MPI_INT64_T, MPI_MAX, job.comm);
  const int64_t pieces = std::max<int64_t>(1, std::min(largest, kPiecesPerRank));

  formfactor::RowSampling sampling(job.tracer, job.patches, job.options);
  formfactor::SplitRows done;  // each piece goes in as values and its tally is let go
  done.firstRow = owned.begin;
  done.endRow = owned.end;
  done.samples = samples;
  done.singlePrecision = job.singlePrecision;
  done.pairsOnce = job.pairsOnce;
  // A stop asked for while the scene was loaded, meshed or planned: the rows there are (none, or
  // a restart's) go to the checkpoint before any ray is cast.
  if (hooks.safePoints.stopRequested()) {
    checkpointRows(done, samples, saved, hooks);
    hooks.safePoints.checkpointWritten();
    throw solve::SolveStopped();
  }
  // Saved exact rows go into a store of floats as ExactRows puts them there, each row's sum kept
  // (a checkpoint made on doubles, rows extended by more samples); others are rounded as they come.
  // (rows stored once a pair are on floats already but for their rest, which is exact as it is)
  const bool exactOnFloats = job.options.exactRows && job.singlePrecision && !job.pairsOnce;
  const auto keepSums = [&](SampleTally rows) {
    if (exactOnFloats) formfactor::keepExactRowsOnFloats(rows);
    return rows;
  };
  int64_t cursor = 0;
  for (int64_t p = 0; p < pieces; ++p) {
    const int64_t pieceEnd = count * (p + 1) / pieces;
    const double cpuStart = hooks.cpuSeconds ? processCpuSeconds() : 0;
    while (cursor < pieceEnd) {  // runs of rows saved with the same number of samples
      const int64_t had = saved.rowSamples[cursor];
      int64_t runEnd = cursor + 1;
      while (runEnd < pieceEnd && saved.rowSamples[runEnd] == had) ++runEnd;
      const int64_t first = owned.begin + cursor, end = owned.begin + runEnd;
      if (had == samples) {
        formfactor::appendRows(done, keepSums(savedSlice(saved, cursor, runEnd, had)));
      } else if (had == 0) {
        formfactor::appendRows(done, sampling.sample(first, end, 0, samples, statistics));
      } else {  // more rays than the checkpoint's: only the missing samples
        formfactor::appendRows(done,
                               keepSums(formfactor::mergeSamples(
                                   savedSlice(saved, cursor, runEnd, had),
                                   sampling.sample(first, end, had, samples - had, statistics))));
      }
      // Room for every row of the rank once some are in, at twice their entries per row.
      formfactor::reserveRows(done, count);
      cursor = runEnd;
      if (hooks.progress) hooks.progress(cursor);
    }
    // The saved rows behind the cursor are in `done` now: their memory goes back, so that the
    // saved rows and their extension are never both whole (a rays round held the last round's
    // store, 12 B a nonzero, beside the new one to its end).
    if (saved.values.rowCount() > 0) saved.values.releaseRowsBefore(cursor);
    if (saved.tally.rowCount() > 0) saved.tally.releaseRowsBefore(cursor);
    if (hooks.cpuSeconds) *hooks.cpuSeconds += processCpuSeconds() - cpuStart;
    const solve::SafePointAction action = hooks.safePoints.poll();
    if (action == solve::SafePointAction::kContinue) continue;
    checkpointRows(done, samples, saved, hooks);
    hooks.safePoints.checkpointWritten();
    if (action == solve::SafePointAction::kStop) throw solve::SolveStopped();
  }
  return done;
}

}  // namespace radiosity::run
