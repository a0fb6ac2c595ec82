// SPDX-License-Identifier: Apache-2.0
#include "framework/interrupt.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

namespace rbfmuscle {
namespace {

std::atomic<int> g_signal{0};
std::atomic<bool> g_handled{false};
std::atomic<bool> g_keep_partial{false};
std::atomic<bool> g_installed{false};

std::mutex& cleanupMutex() {
  static std::mutex* mutex = new std::mutex;  // never destroyed: the watcher may use it during exit
  return *mutex;
}
std::vector<std::string>& cleanupPaths() {
  static auto* paths = new std::vector<std::string>;
  return *paths;
}

sigset_t interruptSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

/// Removes the registered paths (or names them with --keep-partial) and ends the process.
[[noreturn]] void endProcess(int signal_number) {
  std::string done;
  {
    std::lock_guard<std::mutex> lock(cleanupMutex());
    for (const std::string& path : cleanupPaths()) {
      if (g_keep_partial) {
        done += ", partial output kept (--keep-partial): " + path;
        continue;
      }
      // The main thread may still be writing into a directory: retry a few times (capped).
      std::error_code ec;
      for (int attempt = 0; attempt < 20; ++attempt) {
        ec.clear();
        std::filesystem::remove_all(path, ec);
        if (!ec && !std::filesystem::exists(path, ec)) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      done += (std::filesystem::exists(path, ec) ? ", could not remove " : ", removed ") + path;
    }
  }
  const std::string line = "rbfmuscle: interrupted by " + describeSignal(signal_number) +
                           " during work that cannot stop in between; stopped" + (done.empty() ? ", no output written" : done) + "\n";
  (void)!::write(STDERR_FILENO, line.data(), line.size());
  ::_exit(128 + signal_number);
}

void watch() {
  const sigset_t set = interruptSignals();
  int first = 0;
  while (first == 0) {
    int received = 0;
    if (sigwait(&set, &received) == 0) first = received;
  }
  g_signal = first;
  // Grace period: the main thread checks between steps and unwinds by itself.
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::milliseconds(static_cast<long>(kInterruptGraceSeconds * 1000));
  while (std::chrono::steady_clock::now() < deadline) {
    if (g_handled) return;
    timespec wait{0, 100 * 1000 * 1000};
    if (sigtimedwait(&set, nullptr, &wait) > 0) break;  // a second signal: stop now
  }
  if (g_handled) return;
  endProcess(first);
}

}  // namespace

Interrupted::Interrupted(int signal_number)
    : std::runtime_error("interrupted by " + describeSignal(signal_number)), signal_(signal_number) {}

std::string describeSignal(int signal_number) {
  if (signal_number == SIGINT) return "SIGINT";
  if (signal_number == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal_number);
}

void installInterruptHandling(bool keep_partial) {
  g_keep_partial = keep_partial;
  if (g_installed.exchange(true)) return;
  const sigset_t set = interruptSignals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread(watch).detach();
}

bool isInterruptRequested() { return g_signal.load() != 0; }
int getInterruptSignal() { return g_signal.load(); }
bool isKeepPartialRequested() { return g_keep_partial.load(); }

void throwIfInterrupted() {
  const int signal_number = g_signal.load();
  if (signal_number != 0) throw Interrupted(signal_number);
}

void markInterruptHandled() { g_handled = true; }

InterruptCleanup::InterruptCleanup(std::string path) : path_(std::move(path)) {
  std::lock_guard<std::mutex> lock(cleanupMutex());
  cleanupPaths().push_back(path_);
}

InterruptCleanup::~InterruptCleanup() {
  std::lock_guard<std::mutex> lock(cleanupMutex());
  auto& paths = cleanupPaths();
  const auto it = std::find(paths.begin(), paths.end(), path_);
  if (it != paths.end()) paths.erase(it);
}

}  // namespace rbfmuscle
