// `radiosity info` for a checkpoint: recognising one, and what it holds (stage, rows sampled,
// identity, channels, refinement, history), read and checked as the reader reads it.
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/channels.h"
#include "io/store/checkpoint.h"
#include "io/store/checkpoint_format.h"
#include "io/store/checkpoint_reading.h"
#include "io/store/hdf5_read.h"
#include "io/store/hdf5_util.h"

namespace radiosity {

namespace format = checkpoint_format;

bool isCheckpoint(const std::string& path) { return h5::fileKind(path) == format::kKind; }

std::string describeCheckpoint(const std::string& path) {
  h5::QuietErrors quiet;
  h5::Handle file = openCheckpoint(path);
  const Checkpoint c = readCheckpointShared(file.get(), path);
  const int64_t np = c.patchCount;
  const std::vector<int64_t> samples = readCheckpointSamples(file.get(), path, np);
  std::map<int64_t, int64_t> rowsWith;  // samples per row → rows with that many (sampled rows)
  for (int64_t r = 0; r < np; ++r)
    if (samples[r] > 0) ++rowsWith[samples[r]];
  int64_t sampled = 0;
  for (const auto& [count, rows] : rowsWith) sampled += rows;

  std::ostringstream out;
  out << "file: " << path << "\n"
      << "checkpoint (format " << format::kFormatVersion << ")\n"
      << "  stage: " << c.stage << "\n"
      << "  patches: " << np << "\n"
      << "  rows sampled: " << sampled << " of " << np;
  if (np > 0) {
    char percent[32];
    std::snprintf(percent, sizeof percent, " (%.1f%%)", 100.0 * double(sampled) / double(np));
    out << percent;
  }
  out << "\n  samples per row: ";
  if (rowsWith.empty()) out << "none yet";
  for (auto it = rowsWith.begin(); it != rowsWith.end(); ++it) {
    out << (it == rowsWith.begin() ? "" : ", ") << it->first;
    if (rowsWith.size() == 1 && it->second == np)
      out << " (all)";
    else
      out << " (" << it->second << (it->second == 1 ? " row)" : " rows)");
  }
  out << "\n"
      << "  identity:" << (c.identity.empty() ? " none" : "") << "\n";
  for (const auto& [key, value] : c.identity) {
    out << "    " << key << " =";
    if (value.find('\n') == std::string::npos) {
      out << " " << value << "\n";
      continue;
    }
    std::istringstream lines(value);
    for (std::string line; std::getline(lines, line);) out << "\n      " << line;
    out << "\n";
  }
  out << "  channels:";
  for (int k = 0; k < 3; ++k)
    out << (k ? "," : "") << " " << kChannelNames[k] << ": "
        << format::kChannelStates[c.progress.channelState[k]];
  if (c.refinement.rounds() > 0)
    out << "\n  refinement rounds: " << c.refinement.rounds() << " (" << c.refinement.marked.size()
        << " patches split"
        << (c.refinement.merged.empty()
                ? std::string()
                : ", " + std::to_string(c.refinement.merged.size()) + " bisections undone")
        << ")";
  out << "\n  solve history: " << c.progress.history.size()
      << (c.progress.history.size() == 1 ? " entry" : " entries") << "\n";
  return out.str();
}

}  // namespace radiosity
