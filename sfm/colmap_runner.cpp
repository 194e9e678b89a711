#include "sfm/colmap_runner.h"

#include <algorithm>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <regex>

#include "core/disk_space.h"
#include "core/error.h"
#include "core/subprocess.h"

namespace hos::sfm {
namespace {

constexpr const char* kInstallHint =
    "install COLMAP (Debian/Ubuntu: sudo apt-get install colmap) or set sfm.colmap / "
    "$HOS_COLMAP to the colmap executable";
constexpr std::size_t kTailLines = 12;
constexpr const char* kDefaultColmap = "colmap";

// The folder a COLMAP command writes into: its database's or output's.
std::string folder_written_by(const ColmapStep& step) {
  for (const char* flag : {"--database_path", "--output_path"}) {
    const auto it = std::find(step.args.begin(), step.args.end(), flag);
    if (it != step.args.end() && it + 1 != step.args.end()) {
      const std::filesystem::path path(*(it + 1));
      return std::string(flag) == "--database_path" ? path.parent_path().string() : path.string();
    }
  }
  return ".";
}

}  // namespace

ColmapInfo parse_colmap_banner(std::string_view banner) {
  ColmapInfo info;
  static const std::regex kVersion(R"(COLMAP\s+([0-9][0-9A-Za-z.\-]*))");
  const std::string text(banner);
  std::smatch sm;
  if (std::regex_search(text, sm, kVersion)) info.version = sm[1];
  info.cuda = text.find("with CUDA") != std::string::npos && text.find("without CUDA") == std::string::npos;
  return info;
}

ColmapInfo locate_colmap(const std::string& configured) {
  std::string wanted = configured.empty() ? std::string(kDefaultColmap) : configured;
  std::string origin = "sfm.colmap";
  if (wanted == kDefaultColmap) {
    if (const char* env = std::getenv("HOS_COLMAP"); env && *env) {
      wanted = env;
      origin = "$HOS_COLMAP";
    }
  }
  const std::string path = find_executable(wanted);
  if (path.empty()) {
    if (wanted == kDefaultColmap) {
      throw StageError("sfm", std::string("COLMAP was not found on PATH; ") + kInstallHint);
    }
    throw ConfigError(origin, "value '" + wanted + "' is not an executable; " + kInstallHint);
  }
  std::string banner;
  ProcessOptions process;
  process.argv = {path, "help"};
  process.environment = {{"QT_QPA_PLATFORM", "offscreen"}};
  process.on_line = [&](std::string_view line) {
    if (banner.size() < 4096) banner += std::string(line) + "\n";
  };
  const ProcessResult result = run_process(process);
  ColmapInfo info = parse_colmap_banner(banner);
  if (!result.ok() || info.version.empty()) {
    throw StageError(
        "sfm", path + " does not run as COLMAP (exit code " + std::to_string(result.exit_code) + "); " + kInstallHint);
  }
  info.executable = path;
  return info;
}

std::optional<std::int64_t> parse_colmap_progress(std::string_view line_view) {
  static const std::regex kIndexed(R"(^\s*(?:Processed file|Matching image|Undistorting image) \[(\d+)/(\d+)\])");
  static const std::regex kBlock(R"(^\s*Matching block \[(\d+)/(\d+), (\d+)/(\d+)\])");
  static const std::regex kRegistering(R"(^\s*Registering image #\d+ \((\d+)\))");
  const std::string line(line_view);
  std::smatch m;
  if (std::regex_search(line, m, kIndexed)) return std::stoll(m[1]);
  if (std::regex_search(line, m, kBlock)) {
    const std::int64_t i = std::stoll(m[1]);
    const std::int64_t j = std::stoll(m[3]);
    const std::int64_t columns = std::stoll(m[4]);
    return (i - 1) * columns + j;
  }
  if (std::regex_search(line, m, kRegistering)) return std::stoll(m[1]);
  if (line.find("Initializing with image pair") != std::string::npos) return 2;
  return std::nullopt;
}

ColmapStepResult run_colmap_step(const ColmapInfo& colmap, const ColmapStep& step, Reporter& reporter) {
  ProcessOptions process;
  process.argv = {colmap.executable, step.command};
  process.argv.insert(process.argv.end(), step.args.begin(), step.args.end());
  process.environment = {{"QT_QPA_PLATFORM", "offscreen"}};
  process.cancel_source = &reporter;

  std::string command_line = "$";
  for (const auto& a : process.argv) command_line += " " + a;
  reporter.debug(command_line);

  std::deque<std::string> tail;
  std::string disk_full;  // SQLite's or the C library's words for a full disk
  std::int64_t shown = 0;
  process.on_line = [&](std::string_view line) {
    reporter.debug(line);
    if (disk_full.empty() && says_disk_full(std::string(line))) disk_full = line;
    if (line.find_first_not_of(" =-") == std::string_view::npos) return;
    tail.emplace_back(line);
    if (tail.size() > kTailLines) tail.pop_front();
    if (const auto done = parse_colmap_progress(line); done && *done > shown) {
      // The mapper may register more than the expected total is unlikely but
      // harmless; the bar just stays full.
      reporter.advance(*done - shown);
      shown = *done;
    }
  };
  reporter.begin(step.title, step.total);
  const ProcessResult result = run_process(process);
  reporter.end();
  if (result.cancelled) throw Cancelled();
  if (!disk_full.empty()) {
    const std::string folder = folder_written_by(step);
    throw OutputError(folder, "the disk is full: " + describe_disk(folder) + "; COLMAP " + step.command +
                                  " said: " + disk_full + ". Free some space and run the same command again");
  }
  ColmapStepResult out;
  out.seconds = result.wall_seconds;
  out.exit_code = result.exit_code;
  out.last_lines.assign(tail.begin(), tail.end());
  reporter.debug(format_message("colmap ", step.command, " finished in ", result.wall_seconds, " s with exit code ",
                                result.exit_code));
  return out;
}

std::string format_tail(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += "\n    " + l;
  return out;
}

}  // namespace hos::sfm
