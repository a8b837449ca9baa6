// The project's one parallel loop: the threads of a rank share the patches (form-factor rows,
// light choices, verify's paths) through parallelFor, built on oneTBB and kept behind this
// header. A worker's exception reaches the caller instead of ending the program.
#pragma once

#include <cstdint>
#include <functional>

namespace radiosity::trace {

/// What a piece of a loop does with its indices [begin, end); `slot` in [0, threads) names the
/// thread running it (see parallelFor).
using LoopBody = std::function<void(int64_t begin, int64_t end, int slot)>;

/// Calls `body` on pieces [begin, end) that together cover [0, count) once each, on at most
/// `threads` threads (a task arena of that size, so ranks sharing a node with --threads each do
/// not oversubscribe it). A piece holds at most `most` indices: few enough that the threads
/// finish together even when one of them loses its core for a while, enough that handing out a
/// piece costs little beside its work.
///
/// No two pieces run at once with the same `slot`, so state kept per slot (buffers, counts)
/// needs no lock; slot 0 is the calling thread (for progress reports). Which thread runs which
/// piece, and in which order, varies from run to run: results must not depend on it
/// (per-index random numbers, integer counts, outputs placed by index).
///
/// threads <= 1: body(0, count, 0) on the calling thread. An exception thrown by `body` stops
/// the pieces not yet started and is rethrown here, on the calling thread (the first one, if
/// several pieces throw).
void parallelFor(int64_t count, int threads, const LoopBody& body, int64_t most = 1);

}  // namespace radiosity::trace
