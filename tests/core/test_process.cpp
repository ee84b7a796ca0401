#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "floorcast/core/process.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

std::string folder() {
  const fs::path p = fs::path(FLOORCAST_TEST_OUT) / "process";
  fs::create_directories(p);
  return p.string();
}

TEST(Process, ExitCodesSignalsAndOutput) {
  const std::string out = folder() + "/out.txt", err = folder() + "/err.txt";
  ProcessOptions o;
  o.stdout_path = out;
  o.stderr_path = err;
  ProcessResult r = run_process({"sh", "-c", "echo hello; echo line1 >&2; echo line2 >&2; exit 0"}, o);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.exit_code, 0);
  std::ifstream f(out);
  std::string word;
  f >> word;
  EXPECT_EQ(word, "hello");
  EXPECT_EQ(file_tail(err), "line1\nline2");
  EXPECT_EQ(file_tail(err, 1), "line2");
  r = run_process({"sh", "-c", "exit 3"}, o);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.describe(0), "exited with status 3");
  r = run_process({"sh", "-c", "kill -SEGV $$"}, o);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.signal, 11);
  EXPECT_NE(r.describe(0).find("signal 11"), std::string::npos) << r.describe(0);
  r = run_process({"no-such-program-floorcast"}, o);
  EXPECT_FALSE(r.started);
  EXPECT_NE(r.describe(0).find("could not be started"), std::string::npos);
  EXPECT_EQ(file_tail(folder() + "/missing.txt"), "");
}

TEST(Process, TimeoutKillsTheWholeGroup) {
  // The shell starts a grandchild that would outlive it; the timeout takes both.
  const auto t0 = std::chrono::steady_clock::now();
  ProcessOptions o;
  o.timeout_s = 0.3;
  const ProcessResult r = run_process({"sh", "-c", "sleep 30 & sleep 30; wait"}, o);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(r.timed_out);
  EXPECT_FALSE(r.ok());
  EXPECT_LT(waited, 10.0);
  EXPECT_NE(r.describe(0.3).find("did not finish within 0.3 s"), std::string::npos) << r.describe(0.3);
}

}  // namespace
}  // namespace floorcast
