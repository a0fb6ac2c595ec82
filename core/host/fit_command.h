#pragma once
/// @file
/// `rbfmuscle fit`: mesh in, fitted .rbf surface (and optionally its
/// extracted mesh) out, figures as the last stdout line (one JSON object).

namespace rbfmuscle {

/// Runs `rbfmuscle fit`; argv[0] is "fit". Returns the exit code; throws
/// UsageError for a bad command line and other exceptions for bad input.
int runFitCommand(int argc, char** argv);

}  // namespace rbfmuscle
