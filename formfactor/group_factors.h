// View factors between the scene's labelled groups of patches (materials, OBJ groups, the
// buildings of builtin:city): what users of view-factor codes read for whole surfaces.
#pragma once

#include <mpi.h>

#include <cstddef>

#include "core/matrix_rows.h"
#include "core/mesh.h"
#include "formfactor/formfactor.h"

namespace radiosity::formfactor {

/// Groups beyond this many are not tabled: G² values per result (8 MB at 1024).
inline constexpr size_t kMaxGroups = 1024;

/// F(a→b) for every pair of labels, from this rank's rows of F (`rows`) and every other
/// rank's: the group flux A_a F(a→b) is estimated twice, from a's rows and (by reciprocity,
/// A_a F(a→b) = A_b F(b→a)) from b's, with independent rays; the two are combined with weights
/// Ā_b : Ā_a (Ā: a group's area-weighted mean patch area, to which each estimate's variance is
/// about proportional), which is unbiased and more accurate than either
/// (docs/design/form-factors.md).
/// Reciprocal: A_a F(a→b) = A_b F(b→a) up to round-off. The fluxes are summed in fixed point, so
/// the table is the same bits on any number of ranks. `patches`: the traced mesh (any frame:
/// factors are ratios); `areaScale`: what its areas are multiplied by for the reported group areas
/// (the tracing frame's scale squared). Work: a pass over the rows' entries and the groups each row
/// reaches. Empty when the mesh has no labels or more than kMaxGroups. Collective.
///
/// Each factor's estimated standard error (GroupFactors::factorError): sampled rows (`exactRows`
/// false) take the shape of the variance from the binomial model of each row's share of group b,
/// A_i² p(1 − p)/N with p = Σ_{j∈b} F_ij, and its scale from the data: the two independent
/// estimates of each pair's flux differ by what their variances say, so the mean of
/// (forward − backward)² / (V_forward + V_backward) over the pairs scales the model (shrunk
/// towards 1 by one pair's weight, for scenes of few groups); Sobol' points and MIS do better
/// than the model by a factor that depends on the scene, which this measures. Exact rows
/// (closed forms) have no sampling error; theirs is half the two estimates' difference plus the
/// quadrature's measured relative error (1e-6 of the factor), which mirror-image pairs hide.
GroupFactors groupFactors(MPI_Comm comm, const Mesh& patches, const SampleTally& rows,
                          double areaScale, bool exactRows = false);
/// Each label's area, summed over its patches in the mesh's own coordinates: a result's group
/// areas in the user's units (those of groupFactors carry the tracing frame's round-off, 6e-15
/// on a unit square). Empty where groupFactors tables none.
std::vector<double> groupAreas(const Mesh& patches);

/// The same from F's one store, read in place. Rows stored once a pair (SplitRows::pairsOnce)
/// give each pair's flux both ways (A_i F_ij = A_j F_ji), their diagonal entries (the others'
/// sum) none.
GroupFactors groupFactors(MPI_Comm comm, const Mesh& patches, const SplitRows& rows,
                          double areaScale, bool exactRows = false);

}  // namespace radiosity::formfactor
