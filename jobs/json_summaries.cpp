#include "jobs/json_summaries.h"

#include "core/channels.h"
#include "core/error.h"
#include "io/store/json_text.h"

namespace radiosity::jobs {

using json = JsonDocument;

std::string verifyJson(const VerifySettings& settings, int64_t patches, int64_t reflecting,
                       int64_t sampled, const Measures& channels, bool hasStderr,
                       const std::string& cappedNote, int exitCode) {
  json measured = json::object();
  for (int c = 0; c < 3; ++c) {
    const ChannelMeasures& m = channels[c];
    if (m.patches == 0) continue;  // (no patch reflects in it: nothing measured)
    json channel = {{"patches", m.patches},
                    {"mean_reference", m.meanReference},
                    {"measured_error", m.measured},
                    {"reference_noise", m.noise},
                    {"error_noise_taken_out", m.corrected},
                    {"error_interval", {m.correctedLow, m.correctedHigh}}};
    if (hasStderr) {
      channel["estimated_error"] = m.estimate;
      channel["coverage"] = m.coverage;
      const EstimateCheck check = checkEstimate(m);
      channel["estimate_covers_error"] = check.understated.empty();
      if (!check.understated.empty()) channel["estimate_understated"] = check.understated;
    }
    measured[channels.name(c)] = channel;
  }
  json document = {{"schema", "radiosity.verify/1"},
                   {"exit_code", exitCode},
                   {"passed", exitCode == exit_code::kOk},
                   {"result", settings.input},
                   {"patches", patches},
                   {"reflecting_patches", reflecting},
                   {"sampled_patches", sampled},
                   {"paths_per_patch", settings.paths},
                   {"seed", settings.seed},
                   {"tol", settings.tol},
                   {"channels", measured}};
  if (!cappedNote.empty()) document["reference_cut_short"] = cappedNote;
  return jsonText(document);
}

std::string failureJson(const std::string& command, int exitCode, const std::string& message) {
  return jsonText({{"schema", "radiosity.failure/1"},
                   {"command", command},
                   {"exit_code", exitCode},
                   {"error", message}});
}

}  // namespace radiosity::jobs
