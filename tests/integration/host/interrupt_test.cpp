// SPDX-License-Identifier: Apache-2.0
/// SIGINT and SIGTERM stop `rbfmuscle run` cleanly: exit code 130 / 143, no OUTDIR and no
/// OUTDIR.partial-PID left behind (or the partial directory kept with --keep-partial). The
/// host runs the main job (hip flexion, both muscles) as a child process; the signal is sent
/// once its staging directory exists and its frame loop (or its initialisation) is under way.
#include <gtest/gtest.h>

#include <fstream>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "support/run_host.h"

namespace rbfmuscle {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const fs::path kHip = fs::path(RBFMUSCLE_SOURCE_DIR) / "models/hip";

struct Child {
  pid_t pid = -1;
  fs::path err;
};

/// Starts `rbfmuscle ARGS...` with stdout and stderr in files of `dir`.
Child startHost(const std::vector<std::string>& args, const fs::path& dir) {
  Child child;
  child.err = dir / "stderr";
  const std::string binary = (fs::path(RBFMUSCLE_BINARY_DIR) / "bin/rbfmuscle").string();
  const std::string out = (dir / "stdout").string(), err = child.err.string();
  child.pid = fork();
  if (child.pid == 0) {
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(o, 1);
    dup2(e, 2);
    std::vector<char*> argv = {const_cast<char*>(binary.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
  return child;
}

/// The staging directories OUTDIR.partial-* beside `out`.
std::vector<fs::path> partials(const fs::path& out) {
  std::vector<fs::path> found;
  for (const auto& entry : fs::directory_iterator(out.parent_path()))
    if (entry.path().filename().string().rfind(out.filename().string() + ".partial-", 0) == 0) found.push_back(entry.path());
  return found;
}

/// Waits (at most `seconds`) until `ready` holds or the child exited; true when it holds.
template <class Ready>
bool waitFor(pid_t pid, double seconds, Ready ready) {
  const auto end = Clock::now() + std::chrono::milliseconds(static_cast<long>(seconds * 1000));
  while (Clock::now() < end) {
    if (ready()) return true;
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

/// Exit code of the child (or -signal when a signal ended it); kills it after `seconds`.
int waitExit(pid_t pid, double seconds) {
  const auto end = Clock::now() + std::chrono::milliseconds(static_cast<long>(seconds * 1000));
  int status = 0;
  while (Clock::now() < end) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1000;
}

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::path(RBFMUSCLE_BINARY_DIR) / "test_out/interrupt" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The main job's muscles over a long motion (the flexion 0 → 80 → 0° 40 times, 6400 frames) in
/// `dir`, so the frame loop is still running when a signal comes: the model path.
fs::path writeLongRun(const fs::path& dir) {
  std::ofstream motion(dir / "long.mot");
  motion << "long\nversion=1\nnRows=6400\nnColumns=4\ninDegrees=yes\nendheader\n"
         << "time\thip_flexion_r\thip_adduction_r\thip_rotation_r\n";
  for (int i = 0; i < 6400; ++i) motion << i / 30.0 << "\t" << std::abs(80 - (i % 160)) << "\t0\t0\n";
  std::string model = test::readText(kHip / "hip_flexion.xml");
  const std::string hip = kHip.string() + "/";
  for (const std::string from : {">meshes/", ">surfaces/", ">landmarks/", "\"hip_r.urdf"})
    test::replaceAll(model, from, from[0] == '>' ? ">" + hip + from.substr(1) : "\"" + hip + from.substr(1));
  const std::string motion_element = "motions/hip_flexion_0_80.mot";
  model.replace(model.find(motion_element), motion_element.size(), (dir / "long.mot").string());
  std::ofstream(dir / "long.xml") << model;
  return dir / "long.xml";
}

/// Runs the main job over a long motion, sends `signal_number` once the frame loop has started
/// (its first progress line) or, with `during_init`, once the staging directory exists, and
/// returns the exit code; `out` is OUTDIR.
int interruptRun(const fs::path& dir, const fs::path& out, int signal_number, bool during_init,
                 const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args = {"run", writeLongRun(dir).string(), "-o", out.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  const Child child = startHost(args, dir);
  const bool ready = waitFor(child.pid, 300 * RBFMUSCLE_TEST_TIME_SCALE, [&] {
    if (partials(out).empty()) return false;
    return during_init || test::readText(child.err).find("] frame 1/") != std::string::npos;
  });
  EXPECT_TRUE(ready) << test::readText(child.err);
  kill(child.pid, signal_number);
  return waitExit(child.pid, 60 * RBFMUSCLE_TEST_TIME_SCALE);
}

TEST(Interrupt, SigintDuringTheFrameLoopExits130AndLeavesNoPartialDirectory) {
  const fs::path dir = freshDir("sigint");
  const fs::path out = dir / "out";
  EXPECT_EQ(interruptRun(dir, out, SIGINT, false), 130) << test::readText(dir / "stderr");
  EXPECT_TRUE(partials(out).empty());
  EXPECT_FALSE(fs::exists(out));
  EXPECT_NE(test::readText(dir / "stderr").find("rbfmuscle: interrupted by SIGINT"), std::string::npos)
      << test::readText(dir / "stderr");
}

TEST(Interrupt, SigtermDuringInitialisationExits143AndLeavesNoPartialDirectory) {
  const fs::path dir = freshDir("sigterm");
  const fs::path out = dir / "out";
  EXPECT_EQ(interruptRun(dir, out, SIGTERM, true), 143) << test::readText(dir / "stderr");
  EXPECT_TRUE(partials(out).empty());
  EXPECT_FALSE(fs::exists(out));
  EXPECT_NE(test::readText(dir / "stderr").find("rbfmuscle: interrupted by SIGTERM"), std::string::npos)
      << test::readText(dir / "stderr");
}

TEST(Interrupt, KeepPartialKeepsTheStagingDirectory) {
  const fs::path dir = freshDir("keep");
  const fs::path out = dir / "out";
  EXPECT_EQ(interruptRun(dir, out, SIGINT, false, {"--keep-partial"}), 130) << test::readText(dir / "stderr");
  EXPECT_EQ(partials(out).size(), 1u);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_NE(test::readText(dir / "stderr").find("partial output kept (--keep-partial)"), std::string::npos)
      << test::readText(dir / "stderr");
}

}  // namespace
}  // namespace rbfmuscle
