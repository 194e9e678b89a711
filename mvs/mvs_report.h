// The mvs stage's figures as JSON (hos-mvs --report FILE, WS/mvs/report.json
// in a pipeline run) for the run report: views, points, times, depth-map
// coverage per view and the histogram of the points' confidence.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "mvs/run_mvs.h"

namespace hos::mvs {

// Confidence counts agreeing views (mvs/fusion.h): one bin per count up to
// this one, the larger counts in the last bin.
inline constexpr int kMaxPlottedConfidence = 40;

nlohmann::ordered_json mvs_report_json(const MvsResult& result);
// Writes atomically; throws OutputError.
void write_mvs_report(const std::filesystem::path& path, const MvsResult& result);

}  // namespace hos::mvs
