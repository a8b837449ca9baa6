// Private to io/store: the `units` and `description` attributes every dataset of a result file
// (and of a scene file) carries, so that the file explains itself to whoever opens it without our
// docs.
#pragma once

#include <hdf5.h>

#include <string>

#include "io/store/hdf5_parallel.h"

namespace radiosity {

/// Writes `units` and `description` on every dataset of the result file that exists; lengths
/// and areas in `lengthUnit` ("m", "m^2"), or said to be in the scene's unit where it is empty;
/// E, B and H in W/m^2 for a `thermal` run. Collective (attributes are metadata: every rank
/// writes the same).
void labelResultDatasets(h5::CollectiveSteps& steps, hid_t file, const std::string& lengthUnit,
                         bool thermal = false);

/// Writes `units` and `description` on the dataset `name` if the file has it. Throws h5::Failure.
void labelDataset(hid_t file, const char* name, const std::string& units,
                  const std::string& description);

}  // namespace radiosity
