// The recon stage's figures as JSON (hos-recon --report FILE,
// WS/recon/report.json in a pipeline run) for the run report: grid, samples,
// the solver's residual per iteration, isovalue, trimming and times.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "recon/reconstruct.h"

namespace hos::recon {

nlohmann::ordered_json recon_report_json(const ReconResult& result);
// Writes atomically; throws OutputError.
void write_recon_report(const std::filesystem::path& path, const ReconResult& result);

}  // namespace hos::recon
