#include "pipeline/slurm/slurm_commands.h"

#include <pwd.h>
#include <unistd.h>

#include <sstream>

#include "core/error.h"
#include "core/subprocess.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

std::string user_name() {
  const passwd* pw = getpwuid(getuid());
  return pw ? pw->pw_name : std::to_string(getuid());
}

}  // namespace

CommandOutput run_command(const std::vector<std::string>& argv) {
  ProcessOptions process;
  process.argv = argv;
  CommandOutput out;
  process.on_line = [&](std::string_view line) {
    out.text += line;
    out.text += '\n';
  };
  out.exit_code = run_process(process).exit_code;
  return out;
}

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::set<std::string> active_job_ids() {
  const CommandOutput out = run_command({"squeue", "--noheader", "--array", "--format=%i", "--user=" + user_name()});
  if (out.exit_code != 0) throw StageError("pipeline", "squeue failed: " + trimmed(out.text));
  std::set<std::string> ids;
  std::istringstream lines(out.text);
  for (std::string line; std::getline(lines, line);) {
    if (!trimmed(line).empty()) ids.insert(trimmed(line));
  }
  return ids;
}

std::string sacct_state(const std::string& id) {
  const CommandOutput out =
      run_command({"sacct", "--noheader", "--parsable2", "--allocations", "--format=JobID,State", "--jobs=" + id});
  std::istringstream lines(out.text);
  for (std::string line; out.exit_code == 0 && std::getline(lines, line);) {
    const auto bar = line.find('|');
    if (bar != std::string::npos && line.substr(0, bar) == id) return trimmed(line.substr(bar + 1));
  }
  return "";
}

CommandOutput run_sbatch(const fs::path& script,
                         bool array,
                         const std::vector<int>& array_tasks,
                         const std::vector<std::string>& after) {
  std::vector<std::string> argv{"sbatch", "--parsable"};
  if (array) {
    std::string list;
    for (int t : array_tasks) {
      if (!list.empty()) list += ',';
      list += std::to_string(t);
    }
    argv.push_back("--array=" + list);
  }
  if (!after.empty()) {
    std::string dependency = "--dependency=afterok";
    for (const auto& id : after) dependency += ":" + id;
    argv.push_back(dependency);
  }
  argv.push_back(script.string());
  return run_command(argv);
}

void cancel_jobs(const std::vector<std::string>& ids, Reporter& reporter) {
  if (ids.empty()) return;
  std::vector<std::string> argv{"scancel"};
  argv.insert(argv.end(), ids.begin(), ids.end());
  const CommandOutput out = run_command(argv);
  std::string list;
  for (const auto& id : ids) list += " " + id;
  if (out.exit_code != 0) {
    reporter.warn("scancel" + list + " failed: " + trimmed(out.text));
  } else {
    reporter.info("cancelled Slurm jobs" + list);
  }
}

}  // namespace hos::pipeline
