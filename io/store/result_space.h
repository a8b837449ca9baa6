// Private to io/store: the disk space a result file may take, reserved before parallel HDF5
// writes it (io/store/space_reservation.h).
#pragma once

#include <mpi.h>

#include <cstdint>

#include "io/store/result.h"

namespace radiosity {

/// At most the bytes of the result file hdf5_result_writer.cpp writes for these patches,
/// attributes and form factors, the same on every rank. Collective.
int64_t resultSpace(MPI_Comm comm, const Mesh& patches, const ResultAttributes& a,
                    const FormFactorOutput& formFactors);

}  // namespace radiosity
