// The entries of the stage table (pipeline/stages.h), each stage's in its
// own file (pipeline/<stage>_stage.cpp), and the readers they share.
#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/histogram.h"
#include "pipeline/stages.h"

namespace hos::pipeline {

StageSpec sfm_stage();
StageSpec mvs_stage();
StageSpec recon_stage();
StageSpec refine_stage();
StageSpec texture_stage();

// A stage's config: its options struct with their table.
template <typename Options>
std::function<std::unique_ptr<StageConfig>()> typed_config(const char* section) {
  return [section] { return std::make_unique<TypedStageConfig<Options>>(section); };
}

// The undistorted workspace sfm writes, as the stages after it read it.
void add_undistorted_workspace(Fingerprint& f, const StagePaths& p);

// Logs, reports and small files every stage writes besides its result.
inline constexpr std::uintmax_t kScratchBytes = 64ull << 20;

// Bytes of a file, or of every file in a folder (0 when missing).
std::uintmax_t size_of(const std::filesystem::path& path);

// A histogram stored under key in a report, or nothing if it has none.
std::optional<Histogram> histogram_at(const nlohmann::json& report, const char* key);

// The keys a stage's report.json has, copied into figures (none if it cannot
// be read).
void copy_report_figures(const std::filesystem::path& report,
                         std::initializer_list<const char*> keys,
                         nlohmann::ordered_json& figures);

// figures[key] as JSON text, "?" when missing.
std::string figure_text(const nlohmann::ordered_json& figures, const char* key);

// "vertices" and "faces" of a PLY mesh, and their line.
void add_mesh_figures(const std::filesystem::path& mesh, nlohmann::ordered_json& figures);
std::string mesh_figures_text(const nlohmann::ordered_json& figures);

}  // namespace hos::pipeline
