// SPDX-License-Identifier: Apache-2.0
#pragma once
/// Runs the built `rbfmuscle` executable as a subprocess for integration
/// tests, capturing its exit code, stdout and stderr.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rbfmuscle::test {

struct HostResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Replaces every `from` in `text` by `to`, left to right (a `to` that contains `from` is not
/// replaced again).
inline void replaceAll(std::string& text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

/// Runs `rbfmuscle ARGS` (with `environment`, e.g. "OMP_NUM_THREADS=1", set for it); logs go
/// to BINARY_DIR/test_out/GROUP/NAME_log/{stdout,stderr}.
inline HostResult runHost(const std::string& args, const std::string& group, const std::string& name,
                          const std::string& environment = "") {
  namespace fs = std::filesystem;
  const fs::path binary = fs::path(RBFMUSCLE_BINARY_DIR) / "bin/rbfmuscle";
  const fs::path logs = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out" / group / (name + "_log");
  fs::create_directories(logs);
  const std::string command = (environment.empty() ? "" : "env " + environment + " ") + "'" + binary.string() + "' " + args + " >'" + (logs / "stdout").string() +
                              "' 2>'" + (logs / "stderr").string() + "'";
  const int status = std::system(command.c_str());
  HostResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = readText(logs / "stdout");
  result.err = readText(logs / "stderr");
  return result;
}

}  // namespace rbfmuscle::test
