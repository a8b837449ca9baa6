// Private to io/: the layout of the checkpoint file, shared by its writer and reader.
//
//   root attributes   kind = "radiosity checkpoint", format_version (int32), stage (string:
//                     "formfactors", "solve" or "done"), patch_count (int64), channel_state
//                     (int32 [3]: 0 not started, 1 in progress, 2 done; red, green, blue)
//   /identity         group, one string attribute per key of Checkpoint::identity
//   /formfactors/samples    int64 [np]: samples behind each row's sums, 0 to 2^32 - 1 (0: not
//                           sampled yet, the row is then empty); rows may differ, as a restart
//                           with more rays extends them one piece at a time
//   /formfactors/row_start  int64 [np + 1]: global CSR over all rows (unsampled rows empty)
//   /formfactors/column     int64 [nnz]
//   /formfactors/sum        int64 [nnz]: Σ contributions · 2^32 (formfactor's SampleTally)
//   /formfactors/row_balance float64 [np]: the row factors of a thermal run's balance of F (1:
//                           none yet); absent in files of earlier versions
//   /refinement/marked      int64 [m]: the patches each adaptive refinement round split, round
//                           after round (core/run_state.h, RefinementHistory); absent: none
//   /refinement/round_start int64 [rounds + 1]: where each round's marks start in `marked`
//   /refinement/patches     int64 [rounds]: the patches after each round
//   /refinement/rays        int64 [rounds]: the rays per patch each round sampled at (0: not
//                           known); absent in files of earlier versions
//   /refinement/estimate    float64 [rounds]: the estimated discretisation error each round was
//                           taken on
//   /mesh/vertices          float64 [nv, 3]: the patches' corners in the scene's coordinates
//   /mesh/triangles         int64 [np, 3]: each patch's corners, rows of /mesh/vertices
//   /mesh/source_face       int64 [np]: the scene's face each patch came from
//   /mesh attribute `input` string: the fingerprint of the scene and the meshing options the
//                           patches were made from; /mesh is absent in files of earlier
//                           versions (a run reusing F then meshes the scene again)
//   /solve/radiosity        float64 [np, 3]
//   /solve/history          float64 [n, 4]: channel, iteration, residual, seconds (as the
//                           result's; attribute `columns` names them)
//
// Every dataset is chunked (at most h5::kChunkElements values a chunk) with HDF5's Fletcher32
// checksum, which HDF5 verifies on every read of a chunk; the file uses the HDF5 1.10 format,
// whose superblock, object headers and chunk indexes carry checksums too.
//
// Version 1 stored a uint8 /formfactors/finished flag per row and one root attribute `samples`
// for all finished rows; it is not read any more.
#pragma once

#include <array>
#include <cstdint>

#include "io/store/format_names.h"

namespace radiosity::checkpoint_format {

inline constexpr char kKind[] = "radiosity checkpoint";
inline constexpr int kFormatVersion = 2;

/// The samples of a row are below this (2^32), in the file and in a Checkpoint alike.
inline constexpr int64_t kSampleLimit = int64_t{1} << 32;

inline constexpr std::array<const char*, 3> kStages = {"formfactors", "solve", "done"};
inline constexpr std::array<const char*, 3> kChannelStates = {"not started", "in progress", "done"};

inline constexpr char kIdentity[] = "/identity";
using format_names::kFormFactors, format_names::kRowStart, format_names::kColumn;
inline constexpr char kSamples[] = "/formfactors/samples", kSum[] = "/formfactors/sum",
                      kRowBalance[] = "/formfactors/row_balance";
using format_names::kSolve, format_names::kHistory;
inline constexpr char kRadiosity[] = "/solve/radiosity";
inline constexpr char kMesh[] = "/mesh", kMeshVertices[] = "/mesh/vertices",
                      kMeshTriangles[] = "/mesh/triangles", kMeshSourceFace[] = "/mesh/source_face",
                      kMeshInput[] = "input";
inline constexpr char kRefinement[] = "/refinement", kMarked[] = "/refinement/marked",
                      kRoundStart[] = "/refinement/round_start",
                      kPatchesAfter[] = "/refinement/patches", kMerged[] = "/refinement/merged",
                      kMergedStart[] = "/refinement/merged_start",
                      kRoundRays[] = "/refinement/rays", kRoundEstimate[] = "/refinement/estimate";

/// Attribute names of the root.
namespace attribute {
using namespace format_names::attribute;
inline constexpr char kStage[] = "stage", kPatchCount[] = "patch_count",
                      kChannelState[] = "channel_state";
}  // namespace attribute

/// The environment variable of the writer's test hook (see checkpoint_writer.cpp).
inline constexpr char kStallVariable[] = "RADIOSITY_TEST_CHECKPOINT_STALL";

}  // namespace radiosity::checkpoint_format
