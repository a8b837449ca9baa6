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

/// The estimated error of B in the measure of io/store/light_error.h: sampling alone, and with
/// the discretisation estimate where the file has one. Only for a result with its stderr.
struct EstimatedErrors {
  Rgb sampling{};
  std::optional<Rgb> total;
};
EstimatedErrors estimatedErrors(const Result& r);

}  // namespace radiosity
