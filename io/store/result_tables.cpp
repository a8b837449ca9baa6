#include "io/store/result_tables.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "io/store/hdf5_read.h"

namespace radiosity {
namespace {

using h5::exact;  // the shortest text that reads back as the same double, in any reader

/// A CSV field: quoted (quotes doubled) when it holds a comma, a quote or a line break.
std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + '"';
}

const GroupFactors& groupsOf(const Result& result, const std::string& source) {
  if (result.groups.empty())
    throw InputError(source +
                     ": has no group view factors (/groups): the scene had no labels or "
                     "more than 1024 (materials, groups, .vs3 surfaces, STL solids)");
  return result.groups;
}

/// Per group: its patches' area-weighted mean of `value(t)`.
template <class Value>
std::vector<double> areaMean(const Result& result, size_t groups, Value value) {
  std::vector<double> sum(groups, 0), area(groups, 0);
  for (int64_t t = 0; t < result.mesh.triangleCount(); ++t) {
    const auto g = static_cast<size_t>(result.mesh.label[t]);
    if (g >= groups) continue;
    sum[g] += result.area[t] * value(t);
    area[g] += result.area[t];
  }
  for (size_t g = 0; g < groups; ++g) sum[g] = area[g] > 0 ? sum[g] / area[g] : 0;
  return sum;
}

}  // namespace

std::string view3dText(const Result& result, const std::string& version,
                       const std::string& source) {
  const GroupFactors& groups = groupsOf(result, source);
  const size_t g = groups.names.size();
  bool closed = true;
  for (size_t a = 0; a < g; ++a) {
    double sum = 0;
    for (size_t b = 0; b < g; ++b) sum += groups.factors[a * g + b];
    closed = closed && std::abs(sum - 1) <= 1e-3;
  }
  // View3D's header: program, version, format (0: text), encl, emit (0: black factors), N,
  // padded to 30 characters; its readers take it with fgets into 35 bytes.
  std::string header = "radiosity " + version.substr(0, 7) + " 0 " + (closed ? "1" : "0") + " 0 " +
                       std::to_string(g);
  if (header.size() < 30) header.resize(30, ' ');
  std::ostringstream text;
  text << header << '\n';
  for (size_t a = 0; a < g; ++a) text << (a ? " " : "") << exact(groups.area[a]);
  text << '\n';
  for (size_t a = 0; a < g; ++a) {
    for (size_t b = 0; b < g; ++b) text << (b ? " " : "") << exact(groups.factors[a * g + b]);
    text << '\n';
  }
  const std::vector<double> rho =
      areaMean(result, g, [&](int64_t t) { return result.mesh.reflectance[t][0]; });
  char emissivity[32];
  for (size_t a = 0; a < g; ++a) {
    std::snprintf(emissivity, sizeof emissivity, "%.3f", 1 - rho[a]);
    text << (a ? " " : "") << emissivity;
  }
  text << '\n';
  return text.str();
}

std::string viewFactorCsv(const Result& result, const std::string& source) {
  const GroupFactors& groups = groupsOf(result, source);
  const size_t g = groups.names.size();
  const bool errors = groups.factorError.size() == g * g;
  std::ostringstream csv;
  csv << "from,to,from_name,to_name,view_factor" << (errors ? ",view_factor_error" : "") << '\n';
  for (size_t a = 0; a < g; ++a) {
    for (size_t b = 0; b < g; ++b) {
      csv << a << ',' << b << ',' << csvField(groups.names[a]) << ',' << csvField(groups.names[b])
          << ',' << exact(groups.factors[a * g + b]);
      if (errors) csv << ',' << exact(groups.factorError[a * g + b]);
      csv << '\n';
    }
  }
  return csv.str();
}

std::string exchangeFactorCsv(const Result& result, const std::string& source) {
  const GroupFactors& groups = groupsOf(result, source);
  if (result.temperature.empty())
    throw InputError(source +
                     ": not a thermal result (solve --thermal): exchange factors need "
                     "its emissivities");
  if (!result.formFactors || result.formFactors->rowCount() != result.mesh.triangleCount())
    throw InputError(source +
                     ": has no form factors (/formfactors): solve with "
                     "--save-formfactors for exchange factors");
  const SparseRows& f = *result.formFactors;
  const size_t g = groups.names.size();
  const auto n = static_cast<size_t>(result.mesh.triangleCount());
  // ε per patch as solved; a hidden patch exchanges nothing.
  std::vector<double> emissivity(n), rho(n);
  for (size_t p = 0; p < n; ++p) {
    const bool hidden = !result.hidden.empty() && result.hidden[p] != 0;
    rho[p] = hidden ? 0.0 : result.mesh.reflectance[p][0];
    emissivity[p] = hidden ? 0.0 : 1 - rho[p];
  }
  std::vector<double> factors(g * g, 0.0);
  std::vector<double> j(n), h(n), next(n);
  for (size_t a = 0; a < g; ++a) {
    // J = E + ρ F J with E = ε on group a (unit σT⁴), 0 elsewhere; by Jacobi sweeps, which
    // converge where anything absorbs (ρ < 1 somewhere the light goes) or leaves.
    double emitted = 0;
    std::vector<double> e(n, 0.0);
    for (size_t p = 0; p < n; ++p)
      if (static_cast<size_t>(result.mesh.label[p]) == a) {
        e[p] = emissivity[p];
        emitted += emissivity[p] * result.area[p];
      }
    if (!(emitted > 0)) continue;  // a surface of given flux emits nothing of its own
    j = e;
    bool converged = false;
    for (int sweep = 0; sweep < 100000 && !converged; ++sweep) {
      double change = 0, size = 0;
      for (size_t p = 0; p < n; ++p) {
        double sum = 0;
        for (int64_t k = f.rowStart[p]; k < f.rowStart[p + 1]; ++k)
          sum += f.value[k] * j[static_cast<size_t>(f.column[k])];
        h[p] = sum;
        next[p] = e[p] + rho[p] * sum;
        change = std::max(change, std::abs(next[p] - j[p]));
        size = std::max(size, std::abs(next[p]));
      }
      j.swap(next);
      converged = change <= 1e-13 * size;
    }
    if (!converged)
      throw Error(exit_code::kNumerical,
                  source + ": the exchange factors of '" + groups.names[a] +
                      "' did not converge in 100000 sweeps (nothing absorbs what it emits)");
    for (size_t p = 0; p < n; ++p) {
      double sum = 0;  // H of the converged J
      for (int64_t k = f.rowStart[p]; k < f.rowStart[p + 1]; ++k)
        sum += f.value[k] * j[static_cast<size_t>(f.column[k])];
      const auto b = static_cast<size_t>(result.mesh.label[p]);
      if (b < g) factors[a * g + b] += emissivity[p] * result.area[p] * sum / emitted;
    }
  }
  std::ostringstream csv;
  csv << "from,to,from_name,to_name,exchange_factor\n";
  for (size_t a = 0; a < g; ++a) {
    double absorbed = 0;
    for (size_t b = 0; b < g; ++b) {
      absorbed += factors[a * g + b];
      csv << a << ',' << b << ',' << csvField(groups.names[a]) << ',' << csvField(groups.names[b])
          << ',' << exact(factors[a * g + b]) << '\n';
    }
    csv << a << ",-1," << csvField(groups.names[a]) << ",surroundings,"
        << exact(absorbed > 0 ? std::max(0.0, 1 - absorbed) : 0.0) << '\n';
  }
  return csv.str();
}

std::string groupsCsv(const Result& result, const std::string& source) {
  const GroupFactors& groups = groupsOf(result, source);
  const size_t g = groups.names.size();
  const int channels = result.attributes.channels;
  const bool thermal = !result.temperature.empty();
  std::vector<int64_t> patches(g, 0);
  for (int32_t label : result.mesh.label)
    if (label >= 0 && static_cast<size_t>(label) < g) ++patches[label];
  std::vector<std::vector<double>> radiosity;
  for (int c = 0; c < channels; ++c)
    radiosity.push_back(areaMean(result, g, [&](int64_t t) { return result.radiosity[t][c]; }));
  std::ostringstream csv;
  csv << "group,name,area,patches";
  static const char* const kChannelNames[] = {"red", "green", "blue"};
  if (channels == 1)
    csv << ",radiosity";
  else
    for (int c = 0; c < channels; ++c) csv << ",radiosity_" << kChannelNames[c];
  if (thermal) csv << ",heat_rate,heat_rate_error,temperature";
  csv << '\n';
  std::vector<double> temperature;
  if (thermal) temperature = areaMean(result, g, [&](int64_t t) { return result.temperature[t]; });
  for (size_t a = 0; a < g; ++a) {
    csv << a << ',' << csvField(groups.names[a]) << ',' << exact(groups.area[a]) << ','
        << patches[a];
    for (int c = 0; c < channels; ++c) csv << ',' << exact(radiosity[c][a]);
    if (thermal) {
      const bool rates = groups.heatRate.size() == g && groups.heatRateError.size() == g;
      csv << ',' << (rates ? exact(groups.heatRate[a]) : "") << ','
          << (rates ? exact(groups.heatRateError[a]) : "") << ',' << exact(temperature[a]);
    }
    csv << '\n';
  }
  return csv.str();
}

}  // namespace radiosity
