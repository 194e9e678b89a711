// Exit codes of every hos executable (documented in README.md).
#pragma once

namespace hos {

enum ExitCode : int {
  kExitSuccess = 0,
  kExitUsage = 2,         // bad command line or configuration (ConfigError)
  kExitBadInput = 3,      // missing, unreadable or malformed input (InputError)
  kExitStageFailed = 4,   // a stage could not produce its result (StageError, NumericalError)
  kExitOutputFailed = 5,  // an output (or a temporary folder, TMPDIR) could not be written (OutputError)
  kExitInternal = 70,     // an unexpected error (a bug)
  kExitInterrupted = 130  // stopped by SIGINT/SIGTERM (Cancelled)
};

}  // namespace hos
