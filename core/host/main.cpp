// SPDX-License-Identifier: Apache-2.0
/// @file
/// rbfmuscle: the host. Parses the command, dispatches, and turns every
/// failure into one line "rbfmuscle: error: ..." and a non-zero exit
/// (2 for a bad command line, 1 otherwise, 128 + the signal when stopped by SIGINT
/// or SIGTERM: 130, 143; see framework/interrupt.h).
#include "framework/interrupt.h"
#include "host_commands.h"

#ifdef RBFMUSCLE_HAVE_FIT
#include "host/fit_command.h"
#endif

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  using rbfmuscle::UsageError;
  const std::vector<std::string> args(argv + (argc > 1 ? 2 : argc), argv + argc);
  const std::string command = argc > 1 ? argv[1] : "";
  // Before any thread starts: SIGINT and SIGTERM stop the command cleanly.
  rbfmuscle::installInterruptHandling(command == "run" &&
                                      std::find(args.begin(), args.end(), "--keep-partial") != args.end());
  try {
    if (command == "-h" || command == "--help" || command == "help") {
      std::fputs(rbfmuscle::usageText().c_str(), stdout);
      return 0;
    }
    if (command == "run") return rbfmuscle::runCommand(args);
    if (command == "info") return rbfmuscle::infoCommand(args);
#ifdef RBFMUSCLE_HAVE_FIT
    // runFitCommand sees its own argv: argv[0] == "fit", then its options.
    using namespace rbfmuscle;  // runFitCommand may be declared in or out of the namespace
    if (command == "fit") return runFitCommand(argc - 1, argv + 1);
#endif
    throw UsageError(command.empty() ? "no command given" : "unknown command '" + command + "'");
  } catch (const rbfmuscle::Interrupted& error) {
    rbfmuscle::markInterruptHandled();
    // On a terminal a progress line may be open: end it first.
    std::fprintf(stderr, "%srbfmuscle: %s; stopped, %s\n", isatty(STDERR_FILENO) ? "\n" : "", error.what(),
                 rbfmuscle::isKeepPartialRequested() ? "partial output kept (--keep-partial)"
                                                     : "no output written");
    return error.getExitCode();
  } catch (const UsageError& error) {
    std::fprintf(stderr, "rbfmuscle: error: %s\n%s", error.what(), rbfmuscle::usageText().c_str());
    return 2;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "rbfmuscle: error: %s\n", error.what());
    return 1;
  }
}
