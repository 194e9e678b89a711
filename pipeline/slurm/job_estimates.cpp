#include "pipeline/slurm/job_estimates.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pipeline/stages.h"

namespace hos::pipeline {

int job_memory_mb(const std::string& job, const PipelineConfig& config, int views, int default_mb) {
  const StageSpec* spec = nullptr;
  StageJob kind = StageJob::kWhole;
  if (!find_stage_job(job, spec, kind)) return default_mb;
  const int estimate = spec->job_memory_mb(kind, config, views);
  return estimate > 0 ? estimate : default_mb;
}

double job_cpu_seconds(const std::string& job, const PipelineConfig& config, const RunBounds& bounds, int chunk_views) {
  const StageSpec* spec = nullptr;
  StageJob kind = StageJob::kWhole;
  if (!find_stage_job(job, spec, kind)) return 0;
  const double chunk = std::clamp(double(chunk_views), 1.0, double(std::max(bounds.views, 1)));
  return spec->job_cpu_seconds(kind, config, bounds, chunk);
}

std::string job_time_limit(const std::string& job,
                           const PipelineConfig& config,
                           const RunBounds& bounds,
                           int chunk_views,
                           const std::string& time_option) {
  if (!time_option.empty()) return time_option;
  const double seconds = job_cpu_seconds(job, config, bounds, chunk_views);
  if (seconds <= 0) return "";
  return slurm_time_text(std::max(kMinTimeSeconds, kTimeSafetyFactor * seconds));
}

std::string slurm_time_text(double seconds) {
  const long minutes = static_cast<long>(std::ceil(std::max(seconds, 0.0) / 60.0));
  const long days = minutes / (24 * 60), hours = minutes / 60 % 24, rest = minutes % 60;
  char text[48];
  if (days > 0) {
    std::snprintf(text, sizeof(text), "%ld-%02ld:%02ld:00", days, hours, rest);
  } else {
    std::snprintf(text, sizeof(text), "%02ld:%02ld:00", hours, rest);
  }
  return text;
}

}  // namespace hos::pipeline
