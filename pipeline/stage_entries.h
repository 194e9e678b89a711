// The entries of the stage table (pipeline/stages.h), each stage's in its
// own file (pipeline/<stage>_stage.cpp), and the readers they share.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "pipeline/stages.h"
#include "sfm/sfm_report.h"

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

// A stage's report as read(file) reads it, for the stage's plots: none when
// the stage has not written it; read's InputError when it is damaged.
template <typename Report>
std::optional<Report> report_if_written(const std::filesystem::path& file,
                                        Report (*read)(const std::filesystem::path&)) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return std::nullopt;
  return read(file);
}

// The sfm stage's report (WS/sfm/report.json), for the run report's photos;
// none when the stage has not written it or it cannot be read.
std::optional<sfm::SfmReport> written_sfm_report(const StagePaths& paths);

// figures[key] as JSON text, "?" when missing.
std::string figure_text(const nlohmann::ordered_json& figures, const char* key);

// "vertices" and "faces" of a PLY mesh, and their line.
void add_mesh_figures(const std::filesystem::path& mesh, nlohmann::ordered_json& figures);
std::string mesh_figures_text(const nlohmann::ordered_json& figures);

}  // namespace hos::pipeline
