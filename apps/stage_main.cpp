#include "apps/stage_main.h"

#include <malloc.h>
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <exception>
#include <iostream>
#include <limits>

#include "core/error.h"
#include "core/exit_codes.h"

namespace hos::apps {
namespace {

// Signal handlers can only touch lock-free atomics with static storage; this
// is the one piece of global state in hos and it lives only in executables.
std::atomic<bool> g_stop_requested{false};

void on_stop_signal(int) { g_stop_requested.store(true); }

// The stages allocate and free buffers of megabytes again and again (images,
// per-view maps, solver vectors). glibc by default maps each such buffer
// afresh and hands freed memory back to the system, so every reuse pays a
// page fault per 4 KiB: 0.6 million of them, a sixth of hos-texture's time
// on fountain-P11. Heap memory up to 32 MiB a buffer (glibc's largest
// threshold) is kept and reused instead.
void keep_freed_memory_for_reuse() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
}

}  // namespace

ProgressStyle parse_progress_style(const std::string& name) {
  if (name == "auto") return ProgressStyle::kAuto;
  if (name == "bar") return ProgressStyle::kBar;
  if (name == "plain") return ProgressStyle::kPlain;
  if (name == "json") return ProgressStyle::kJson;
  if (name == "none") return ProgressStyle::kNone;
  throw ConfigError("--progress", "value '" + name + "' must be one of: auto bar plain json none");
}

void apply_config_and_overrides(OptionSet& options, const CommonStageFlags& flags) {
  if (!flags.config_file.empty()) {
    const YAML::Node root = load_yaml_file(flags.config_file);
    if (root.IsMap()) options.apply_yaml(root[options.section()], flags.config_file);
  }
  for (const auto& assignment : flags.assignments) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos) {
      throw ConfigError(assignment, "--set expects key=value");
    }
    std::string key = assignment.substr(0, eq);
    const std::string prefix = options.section() + ".";
    if (key.rfind(prefix, 0) == 0) {
      key = key.substr(prefix.size());
    } else if (!options.has_key(key) && key.find('.') != std::string::npos) {
      throw ConfigError(key, "is not an option of the " + options.section() + " stage");
    }
    options.apply_assignment(key, assignment.substr(eq + 1), "--set");
  }
  for (const auto& [flag, key, value] : flags.short_flags) options.apply_assignment(key, value, flag);
}

int run_stage_main(const std::string& stage,
                   const CommonStageFlags& flags,
                   const std::function<void(Reporter&)>& body) {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  keep_freed_memory_for_reuse();
  ConsoleReporterOptions reporter_options;
  reporter_options.stage = stage;
  reporter_options.min_level = flags.verbose ? LogLevel::kDebug : LogLevel::kInfo;
  reporter_options.cancel_requested = [] { return g_stop_requested.load(); };
  try {
    reporter_options.style = parse_progress_style(flags.progress);
  } catch (const ConfigError& e) {
    std::cerr << "hos-" << stage << ": error: " << e.what() << "\n";
    return kExitUsage;
  }
  ConsoleReporter reporter(reporter_options);
  try {
    if (!flags.log_file.empty()) reporter.open_log_file(flags.log_file);
    body(reporter);
    return kExitSuccess;
  } catch (const Cancelled&) {
    reporter.error("interrupted; nothing half-written was kept. Run the same command again to redo this stage.");
    return kExitInterrupted;
  } catch (const ConfigError& e) {
    reporter.error(e.what());
    return kExitUsage;
  } catch (const InputError& e) {
    reporter.error(e.what());
    return kExitBadInput;
  } catch (const OutputError& e) {
    reporter.error(e.what());
    return kExitOutputFailed;
  } catch (const StageError& e) {
    reporter.error(e.what());
    return kExitStageFailed;
  } catch (const NumericalError& e) {
    reporter.error(e.what());
    return kExitStageFailed;
  } catch (const std::exception& e) {
    reporter.error(std::string("internal error: ") + e.what());
    return kExitInternal;
  }
}

void add_common_stage_flags(CLI::App& app, CommonStageFlags& flags, const OptionSet& options) {
  const std::string& section = options.section();
  add_option_flags(app, flags, options);
  app.add_option("--config", flags.config_file, "YAML config file (its " + section + ": section is used)");
  app.add_option("--set", flags.assignments, "override an option: --set " + section + ".key=value (repeatable)");
  app.add_option("--progress", flags.progress, "auto|bar|plain|json|none");
  app.add_option("--log", flags.log_file, "log file (every message, debug included)");
  app.add_flag("--verbose", flags.verbose, "show debug messages");
  app.add_flag("--print-config", flags.print_config,
               "print the " + section +
                   " options (after --config, --set and the flags) with their documentation "
                   "and exit");
}

void add_option_flags(CLI::App& app, CommonStageFlags& flags, const OptionSet& options) {
  for (const OptionSet::Flag& spec : options.flags()) {
    const std::string doc = options.documentation(spec.key) + " (= " + options.section() + "." + spec.key +
                            (spec.fixed_value.empty() ? "" : "=" + spec.fixed_value) + ")";
    // The text goes to the option table as given, so a flag is checked and
    // parsed exactly like the same --set.
    if (spec.fixed_value.empty()) {
      app.add_option_function<std::string>(
             spec.flag,
             [&flags, spec](const std::string& text) {
               flags.short_flags.push_back({spec.flag, spec.key, text});
             },
             doc)
          ->allow_extra_args(false);
    } else {
      app.add_flag_callback(
          spec.flag,
          [&flags, spec] {
            flags.short_flags.push_back({spec.flag, spec.key, spec.fixed_value});
          },
          doc);
    }
  }
}

std::optional<int> parse_stage_command_line(
    CLI::App& app, int argc, char** argv, const CommonStageFlags& flags, OptionSet& options) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitSuccess : kExitUsage;
  }
  if (flags.print_config) return print_config(flags, options);
  return std::nullopt;
}

int print_config(const CommonStageFlags& flags, OptionSet& options) {
  // The values the stage would run with, so a --config or --set can be
  // checked before a long run.
  const auto fail = [&](const Error& e, int code) {
    std::cerr << "hos-" << options.section() << ": error: " << e.what() << "\n";
    return code;
  };
  try {
    apply_config_and_overrides(options, flags);
  } catch (const ConfigError& e) {
    return fail(e, kExitUsage);
  } catch (const InputError& e) {
    return fail(e, kExitBadInput);
  }
  std::cout << options.documented_yaml();
  return kExitSuccess;
}

}  // namespace hos::apps
