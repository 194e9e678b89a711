// Calling the COLMAP executable: finding it, checking it runs, and running
// one COLMAP command with its output sent to the log (debug messages) and its
// progress lines turned into Reporter progress.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/reporter.h"

namespace hos::sfm {

struct ColmapInfo {
  std::string executable;  // full path
  std::string version;     // e.g. "3.8"
  bool cuda = false;       // the binary says it was built with CUDA
};

// Finds COLMAP: sfm.colmap (default "colmap", looked up on PATH; $HOS_COLMAP
// replaces that default), and runs `colmap help` once to check it works. A missing
// or broken COLMAP throws StageError saying how to install it (a configured
// path that does not exist throws ConfigError).
ColmapInfo locate_colmap(const std::string& configured);

// Extracts "3.8" and the CUDA flag from the banner `colmap help` prints:
// "COLMAP 3.8 (Commit Unknown on Unknown without CUDA)".
ColmapInfo parse_colmap_banner(std::string_view banner);

// Work items done so far, read from one line of COLMAP's output.
// Feature extraction: "Processed file [i/N]"; exhaustive matching:
// "Matching block [i/n, j/m]"; sequential matching: "Matching image [i/N]";
// mapping: "Registering image #id (k)" (k images registered) and
// "Initializing with image pair" (2); undistortion: "Undistorting image [i/N]".
std::optional<std::int64_t> parse_colmap_progress(std::string_view line);

struct ColmapStep {
  std::string command;            // "feature_extractor", "mapper", ...
  std::vector<std::string> args;  // "--database_path", "x", ...
  std::string title;              // progress step name shown to the user
  std::int64_t total = 0;         // work items for the progress bar (0 = unknown)
};

struct ColmapStepResult {
  double seconds = 0.0;
  int exit_code = 0;
  std::vector<std::string> last_lines;  // the end of COLMAP's output, for error messages
};

// Runs one COLMAP command headless (QT_QPA_PLATFORM=offscreen). Every output
// line goes to reporter.debug (the stage log). Throws Cancelled when the user
// stops the run, OutputError naming the disk and the folder when COLMAP says
// the disk is full (SQLite's "database or disk is full" is only in its
// output); does not throw on another non-zero exit (the caller decides).
ColmapStepResult run_colmap_step(const ColmapInfo& colmap, const ColmapStep& step, Reporter& reporter);

// The last lines of output as one indented block, for error messages.
std::string format_tail(const std::vector<std::string>& lines);

}  // namespace hos::sfm
