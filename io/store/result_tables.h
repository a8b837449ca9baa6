// Text tables written from a result file for the users of other view-factor tools: the group
// view factors in View3D's text output layout or as CSV with their estimated errors, and a
// table of the groups (area, mean radiosity, heat rate). `radiosity export`; docs/view3d.md.
#pragma once

#include <string>

#include "io/store/result.h"

namespace radiosity {

/// The groups' view factors in View3D 3.2's text output layout, which its ViewHT and readers
/// take: a header line "PROGRAM VERSION 0 ENCL 0 G" (padded to 30 characters), the G areas, G
/// rows of F(a→b), the G emissivities (1 − the group's area-mean reflectance, first channel).
/// ENCL is 1 when every row sums to 1 within 1e-3 (a closed enclosure). `version`: ours, at
/// most 7 characters (the readers' buffer). Throws InputError naming `source` when the result
/// has no /groups.
std::string view3dText(const Result& result, const std::string& version, const std::string& source);

/// The groups' view factors as CSV, one row per pair (from, to), with the estimated standard
/// error where the result has it: from,to,from_name,to_name,view_factor,view_factor_error.
std::string viewFactorCsv(const Result& result, const std::string& source);

/// A thermal result's radiative exchange factors (Gebhart's) between its groups, from its saved
/// F: G(a→b), the share of what group a emits that group b absorbs after all reflections, with
/// ε = 1 − ρ per patch as solved (a surface of given flux re-radiates what it absorbs: ρ = 1,
/// it absorbs and emits nothing net and passes what reaches it on). One row per pair:
/// from,to,from_name,to_name,exchange_factor, and per group a row to the surroundings (to -1):
/// the share that no group absorbs. Throws InputError naming `source` when the result is not a
/// thermal one, has no /groups or no /formfactors.
std::string exchangeFactorCsv(const Result& result, const std::string& source);

/// One row per group: index, name, area, patches, the area-mean B per channel and, for a
/// thermal run, the heat rate and its error (W) and the area-mean temperature (K).
std::string groupsCsv(const Result& result, const std::string& source);

}  // namespace radiosity
