// Private to io/store: what `info` reads from a file and works out of a result, shared by its
// text (result_info.cpp) and its JSON (result_info_json.cpp).
#pragma once

#include <hdf5.h>

#include <optional>
#include <string>
#include <vector>

#include "io/store/result.h"

namespace radiosity {

/// A root attribute as stored: text, numbers of one kind (one or an array), or another type
/// (then `text` is its type and shape).
struct AttributeValue {
  enum class Kind { kText, kFloat, kSigned, kUnsigned, kOther };
  Kind kind = Kind::kOther;
  std::string text;
  std::vector<double> floats;
  std::vector<long long> signeds;
  std::vector<unsigned long long> unsigneds;
};

/// Throws h5::Failure.
AttributeValue readAttribute(hid_t file, const std::string& name);

/// Every dataset in the file, by full name ("/patches/area"). Throws h5::Failure.
std::vector<std::string> datasetNames(hid_t file);

/// Per channel over the patches: B's least, sum and greatest, and the power emitted and
/// reflected (area times E, and times B - E); with the total area.
struct LightTotals {
  double area = 0;
  Rgb low{}, high{}, sum{}, emitted{}, reflected{};
};
LightTotals lightTotals(const Result& r);

/// A thermal result's figures, in SI: J (W/m²), the net flux q (W/m²) and the temperature (K)
/// over the patches; each group's heat rate and error (W, /groups) and mean temperature (K,
/// area-weighted); the balance Σ q A (W, the solve figure), NaN where the file has none.
struct HeatTotals {
  double lowJ = 0, meanJ = 0, highJ = 0, lowQ = 0, highQ = 0, lowT = 0, highT = 0;
  struct Group {
    std::string name;
    double rate = 0, error = 0, temperature = 0;
  };
  std::vector<Group> groups;
  double balance = 0;
};
HeatTotals heatTotals(const Result& r);

/// The estimated error of B in the measure of measure/light_error.h: sampling alone, and with
/// the discretisation estimate where the file has one. Only for a result with its stderr.
struct EstimatedErrors {
  Rgb sampling{};
  std::optional<Rgb> total;
};
EstimatedErrors estimatedErrors(const Result& r);

}  // namespace radiosity
