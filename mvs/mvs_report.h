// The mvs stage's report (hos-mvs --report FILE, WS/mvs/report.json in a
// pipeline run) for the run report: views, points, times, depth-map
// coverage per view and the histogram of the points' confidence. Its JSON
// keys are in mvs_report.cpp alone: the stage writes and the pipeline reads
// it through these functions.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/histogram.h"
#include "mvs/run_mvs.h"

namespace hos::mvs {

// Confidence counts agreeing views (mvs/fusion.h): one bin per count up to
// this one, the larger counts in the last bin.
inline constexpr int kMaxPlottedConfidence = 40;

struct MvsViewReport {
  std::string name;
  int sources = 0;
  bool skipped = false;
  std::int64_t pixels = 0;        // of the depth map (finest level)
  std::int64_t valid_pixels = 0;  // with a depth
  double coverage = 0.0;          // valid_pixels / pixels (0 without pixels)
  double seconds = 0.0;
};

struct MvsReport {
  int views = 0;
  int views_skipped = 0;
  std::int64_t points = 0;
  double seconds_depth = 0.0;
  double seconds_fusion = 0.0;
  std::vector<MvsViewReport> per_view;
  Histogram confidence;  // of the fused points, one bin per count (kMaxPlottedConfidence)
};

// The report of a run.
MvsReport mvs_report(const MvsResult& result);

nlohmann::ordered_json to_json(const MvsReport& report);
// Throws InputError naming the file when it is missing or malformed.
MvsReport read_mvs_report(const std::filesystem::path& path);

// Writes mvs_report(result) atomically; throws OutputError.
void write_mvs_report(const std::filesystem::path& path, const MvsResult& result);

}  // namespace hos::mvs
