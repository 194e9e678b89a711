// The run record WS/run.json: per stage its state, the fingerprints of its
// inputs and config section, wall and CPU time, peak memory and key figures. It is
// what lets a re-run skip the stages that are up to date.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace hos::pipeline {

struct StageRecord {
  std::string state;        // "done", "running", "failed", "interrupted"
  std::string input_hash;   // Fingerprint of the stage's input files
  std::string config_hash;  // Fingerprint of its resolved config section
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;  // user + system of the stage and its children; 0: not measured (Slurm)
  std::int64_t peak_memory_bytes = 0;
  int exit_code = 0;
  std::string finished_at;  // UTC, ISO 8601
  nlohmann::ordered_json figures = nlohmann::ordered_json::object();
};

struct RunRecord {
  std::string photos;
  std::string output;
  std::map<std::string, StageRecord> stages;
  // The Slurm executor's jobs (pipeline/slurm/slurm_executor.h); empty for local runs.
  nlohmann::ordered_json slurm = nlohmann::ordered_json::object();
};

// A missing or unreadable record is an empty one: everything runs again.
RunRecord load_run_record(const std::filesystem::path& file);
// Written atomically.
void save_run_record(const RunRecord& record, const std::filesystem::path& file);

// The current UTC time as "2026-01-31T12:00:00Z".
std::string utc_timestamp();

}  // namespace hos::pipeline
