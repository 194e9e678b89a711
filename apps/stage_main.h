// What every hos executable's main shares: a console reporter, SIGINT/SIGTERM
// turned into cooperative cancellation, YAML section loading, and the mapping
// of exceptions to the documented exit codes (core/exit_codes.h).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/option_set.h"
#include "core/reporter.h"

namespace CLI {
class App;
}

namespace hos::apps {

// Command-line options common to all stage executables.
struct CommonStageFlags {
  std::string config_file;               // --config FILE: YAML, this stage's section is used
  std::vector<std::string> assignments;  // --set key=value (section prefix optional)
  std::string progress = "auto";         // --progress auto|bar|plain|json|none
  std::string log_file;                  // --log FILE: every message, debug included
  bool verbose = false;                  // --verbose: debug messages on the terminal
  bool print_config = false;             // --print-config: the options the stage would run with, documented
  // The option table's short flags as given (--resolution 512), applied
  // after --config and --set.
  struct ShortFlag {
    std::string flag, key, value;
  };
  std::vector<ShortFlag> short_flags;
};

// Adds --config, --set, --progress, --log, --verbose and --print-config to a
// stage's command line, documented for its YAML section, and the short flags
// of the stage's option table.
void add_common_stage_flags(CLI::App& app, CommonStageFlags& flags, const OptionSet& options);

// Adds the short flags of the option table (OptionSet::flags) to app.
void add_option_flags(CLI::App& app, CommonStageFlags& flags, const OptionSet& options);

// Parses the command line. Returns the exit code when main is done already
// (--help, a usage error, or --print-config), nothing when the stage should
// run.
std::optional<int> parse_stage_command_line(
    CLI::App& app, int argc, char** argv, const CommonStageFlags& flags, OptionSet& options);

// --print-config: applies --config, --set and the short flags to options
// and prints them as documented YAML; returns the exit code (a ConfigError
// or a config file that cannot be read is reported on stderr).
int print_config(const CommonStageFlags& flags, OptionSet& options);

// Applies --config (the file's `section:` map), then every --set, then the short flags to the
// option set. "--set recon.lambda=0.2" and "--set lambda=0.2" are the same
// for the recon stage; another stage's prefix is an error.
void apply_config_and_overrides(OptionSet& options, const CommonStageFlags& flags);

// Runs body with a ConsoleReporter for stage; returns the exit code.
// SIGINT/SIGTERM set a flag that the reporter's cancel_requested() reports,
// so work stops between items and Cancelled maps to kExitInterrupted.
int run_stage_main(const std::string& stage, const CommonStageFlags& flags, const std::function<void(Reporter&)>& body);

// Parses "auto", "bar", "plain", "json", "none"; throws ConfigError.
ProgressStyle parse_progress_style(const std::string& name);

}  // namespace hos::apps
