/// @file
/// rbfmuscle: the host. Parses the command, dispatches, and turns every
/// failure into one line "rbfmuscle: error: ..." and a non-zero exit
/// (2 for a bad command line, 1 otherwise).
#include "host_commands.h"

#ifdef RBFMUSCLE_HAVE_FIT
#include "host/fit_command.h"
#endif

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  using rbfmuscle::UsageError;
  const std::vector<std::string> args(argv + (argc > 1 ? 2 : argc), argv + argc);
  const std::string command = argc > 1 ? argv[1] : "";
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
  } catch (const UsageError& error) {
    std::fprintf(stderr, "rbfmuscle: error: %s\n%s", error.what(), rbfmuscle::usageText().c_str());
    return 2;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "rbfmuscle: error: %s\n", error.what());
    return 1;
  }
}
