// What hos-pipeline is asked to do: the photos, the output, the workspace,
// the config and the stage range. The stage table (pipeline/stages.h) and
// the executors read it; the driver (pipeline/driver.h) runs it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hos::pipeline {

struct DriverOptions {
  std::filesystem::path photos;          // folder of photos
  std::filesystem::path output;          // OUT.glb
  std::filesystem::path workspace;       // empty: OUT's folder / "<OUT stem>_workspace"
  std::filesystem::path existing_model;  // optional COLMAP sparse model of the photos (sfm skips SfM)
  std::string preset = "default";        // fast | default | quality | a YAML file
  std::string config_file;               // --config
  std::vector<std::string> assignments;  // --set stage.key=value
  std::string from;                      // first stage to consider (empty: sfm)
  std::string to;                        // last stage (empty: texture)
  bool force = false;                    // run the stages in range even if up to date
  std::string progress = "auto";         // passed to the stages
  bool verbose = false;
  std::filesystem::path bin_dir;              // where the stage executables are
  std::string executor = "local";             // local | slurm (pipeline/slurm/slurm_executor.h)
  std::vector<std::string> executor_options;  // --executor-option KEY=VALUE (slurm: partition, account, ...)
};

}  // namespace hos::pipeline
