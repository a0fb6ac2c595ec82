// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Stopping cleanly on SIGINT (Ctrl-C) and SIGTERM.
///
/// The host calls installInterruptHandling() first thing, before any other thread starts: it
/// blocks both signals in every thread and starts one watcher thread that waits for them. On
/// the first signal the watcher only records it; the main thread notices at its next check
/// (throwIfInterrupted(): before each component's initialisation, before each frame and each
/// component update, after each fit round) and unwinds with Interrupted, which removes the
/// run's staging directory `OUTDIR.partial-PID` (StagedDirectory) unless --keep-partial asked
/// to keep it; main() then prints one line and exits with 128 + the signal number (130 for
/// SIGINT, 143 for SIGTERM), after markInterruptHandled().
///
/// Work that cannot check in between (one long component step, a fit inside a component's
/// initialisation) is cut short by the watcher: when the main thread has not finished
/// unwinding within the grace period (kInterruptGraceSeconds), or at a second signal, the
/// watcher removes every path registered with InterruptCleanup (again unless --keep-partial),
/// prints one line and ends the process with the same exit code (_exit: no destructor runs).
#include <stdexcept>
#include <string>

namespace rbfmuscle {

/// Seconds the watcher gives the main thread to unwind after a signal before it cleans up and
/// ends the process itself.
inline constexpr double kInterruptGraceSeconds = 2.0;

/// Thrown by throwIfInterrupted(); main() turns it into exit code getExitCode().
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal_number);
  int getSignal() const { return signal_; }
  /// 128 + signal: 130 for SIGINT, 143 for SIGTERM.
  int getExitCode() const { return 128 + signal_; }

 private:
  int signal_;
};

/// "SIGINT", "SIGTERM" or "signal N".
std::string describeSignal(int signal_number);

/// Blocks SIGINT and SIGTERM in the calling thread (and so in every thread started after it)
/// and starts the watcher thread. Call once, before any other thread exists. With
/// `keep_partial` staged output is left in place on an interruption (its path is printed).
void installInterruptHandling(bool keep_partial);

/// True once SIGINT or SIGTERM arrived (false when handling is not installed).
bool isInterruptRequested();
/// The first signal received (0 when none).
int getInterruptSignal();
/// True when --keep-partial was given to installInterruptHandling.
bool isKeepPartialRequested();
/// Throws Interrupted when a signal arrived.
void throwIfInterrupted();
/// Tells the watcher that the main thread has unwound and is about to exit: it then neither
/// cleans up nor ends the process.
void markInterruptHandled();

/// Registers a file or directory that the watcher removes if it has to end the process
/// itself (see the file comment); unregistered on destruction. Removal is recursive.
class InterruptCleanup {
 public:
  explicit InterruptCleanup(std::string path);
  ~InterruptCleanup();
  InterruptCleanup(const InterruptCleanup&) = delete;
  InterruptCleanup& operator=(const InterruptCleanup&) = delete;

 private:
  std::string path_;
};

}  // namespace rbfmuscle
