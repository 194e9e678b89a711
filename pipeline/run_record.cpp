#include "pipeline/run_record.h"

#include <ctime>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_report.h"
#include "pipeline/stage_config.h"

namespace hos::pipeline {
namespace fs = std::filesystem;

RunRecord load_run_record(const fs::path& file) {
  RunRecord record;
  std::ifstream in(file);
  if (!in) return record;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    record.photos = j.value("photos", "");
    record.output = j.value("output", "");
    if (j.contains("stages")) {
      for (const auto& [name, s] : j.at("stages").items()) {
        StageRecord r;
        r.state = s.value("state", "");
        r.input_hash = s.value("input_hash", "");
        r.config_hash = s.value("config_hash", "");
        r.wall_seconds = s.value("wall_seconds", 0.0);
        r.cpu_seconds = s.value("cpu_seconds", 0.0);
        r.peak_memory_bytes = s.value("peak_memory_bytes", std::int64_t{0});
        r.exit_code = s.value("exit_code", 0);
        r.finished_at = s.value("finished_at", "");
        if (s.contains("figures")) r.figures = s.at("figures");
        record.stages[name] = r;
      }
    }
    if (j.contains("slurm")) record.slurm = j.at("slurm");
  } catch (const nlohmann::json::exception&) {
    return RunRecord{};  // a damaged record only costs a full re-run
  }
  return record;
}

void save_run_record(const RunRecord& record, const fs::path& file) {
  nlohmann::ordered_json j;
  j["photos"] = record.photos;
  j["output"] = record.output;
  nlohmann::ordered_json stages = nlohmann::ordered_json::object();
  for (const auto& name : pipeline_stage_names()) {
    const auto it = record.stages.find(name);
    if (it == record.stages.end()) continue;
    const StageRecord& r = it->second;
    stages[name] = {{"state", r.state},
                    {"input_hash", r.input_hash},
                    {"config_hash", r.config_hash},
                    {"wall_seconds", r.wall_seconds},
                    {"cpu_seconds", r.cpu_seconds},
                    {"peak_memory_bytes", r.peak_memory_bytes},
                    {"exit_code", r.exit_code},
                    {"finished_at", r.finished_at},
                    {"figures", r.figures}};
  }
  j["stages"] = stages;
  if (!record.slurm.empty()) j["slurm"] = record.slurm;
  write_atomically(file, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    out << json_text(j) << "\n";
    if (!out) throw OutputError(file.string(), "the run record");
  });
}

std::string utc_timestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

}  // namespace hos::pipeline
