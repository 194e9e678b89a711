// The Slurm executor of hos-pipeline (--executor slurm): every stage of the
// range becomes an sbatch job that starts after the one before it
// (--dependency=afterok), the stages that split become a job array and a
// job that joins its tasks: mvs and texture in chunks of the views, recon
// one task per tile when recon.tiles asks for tiles. The workspace must be
// on a filesystem every node sees. docs/scale.md describes it for users.
//
// Each job script ends by writing its exit code to
// WS/slurm/status/<job>[.<task>].exit. That file says a job finished and how;
// squeue says which jobs are still pending or running, and sacct (when the
// cluster keeps accounting) why one without a status file ended. The run
// record (run.json, "slurm") holds every job id, so a re-run resumes: stages
// whose jobs completed are done, pending and running jobs are kept, and only
// failed jobs (for an array: only its failed tasks) and what follows them are
// submitted again.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "core/reporter.h"
#include "pipeline/driver_options.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/run_record.h"
#include "pipeline/slurm/slurm_options.h"
#include "pipeline/stage_paths.h"

namespace hos::pipeline {

// Checks that Slurm can take jobs from here: sbatch, squeue, scancel and
// sinfo are on PATH and sinfo reaches the controller. Throws ConfigError
// saying which is missing, with sinfo's own message.
void check_slurm_available();

// Submits (or resumes) the stages first..last of pipeline_stages() on Slurm
// and, with options.wait, waits for them and records each stage as done
// (figures and fingerprints as a local run would, so a later local run finds
// them up to date). Returns true when every stage of the range is done.
// Throws as the local driver does for a failed stage (its log named),
// StageError when sbatch fails, Cancelled on Ctrl-C after cancelling every
// job of the run (scancel).
bool run_on_slurm(const DriverOptions& driver,
                  const SlurmOptions& options,
                  std::size_t first,
                  std::size_t last,
                  const StagePaths& paths,
                  const PipelineConfig& config,
                  RunRecord& record,
                  Reporter& reporter);

}  // namespace hos::pipeline
