// `floorcast plan import` end to end: writes a valid plan and reports; errors exit with code 2.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "floorcast/floorplans/io.hpp"
#include "import_test_util.hpp"

namespace floorcast {
namespace {

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

/// A path in the temp folder unique to this process and call: ctest runs the test cases of this
/// file as separate processes in parallel, so fixed names would race.
std::string temp_path(const std::string& stem) {
  static int counter = 0;
  return (std::filesystem::temp_directory_path() /
          (stem + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++)))
      .string();
}

CliRun run_cli(const std::string& args) {
  const std::string out = temp_path("floorcast_cli_import_out") + ".txt";
  const std::string err = temp_path("floorcast_cli_import_err") + ".txt";
  const std::string cmd = std::string(FLOORCAST_CLI) + " " + args + " >" + out + " 2>" + err;
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text_file(out);
  r.err = read_text_file(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

TEST(CliImport, ImportsCleansAndWritesAValidPlan) {
  const std::string plan = temp_path("floorcast_cli_import_plan") + ".json";
  const CliRun r = run_cli("plan import " + test::data_path("csv/two_rooms_messy.csv") + " --format csv --level 2 -o " + plan);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("cleanup: walls 12 -> 6"), std::string::npos) << r.out;
  const FloorPlan p = load_floor_plan(plan);
  EXPECT_EQ(p.walls.size(), 6u);
  EXPECT_EQ(p.level, 2);

  const CliRun j = run_cli("plan import " + test::data_path("osm/building.osm") + " -f osm --level 0 --doors-closed --json -o " + plan);
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto report = nlohmann::json::parse(j.out);
  EXPECT_EQ(report["plan"]["walls"], 12);
  EXPECT_EQ(report["plan"]["doors_closed"], 4);
  // Two rooms without openings, the hall's outline walled toward unmapped space, a door node on
  // an open boundary skipped.
  EXPECT_EQ(report["notes"].size(), 3u);
  EXPECT_TRUE(report["faithfulness"]["applicable"].get<bool>());
  EXPECT_GT(report["faithfulness"]["free_share"].get<double>(), 0.95);
  EXPECT_TRUE(report["warnings"].empty());
  std::filesystem::remove(plan);
}

TEST(CliImport, ErrorsExitWithCodeTwoAndAReason) {
  const std::string plan = temp_path("floorcast_cli_import_bad") + ".json";
  const CliRun png = run_cli("plan import " + test::data_path("png/two_rooms_f3loc.png") + " --format png -o " + plan);
  EXPECT_EQ(png.exit_code, 2);
  EXPECT_NE(png.err.find("--resolution"), std::string::npos) << png.err;
  const CliRun fmt = run_cli("plan import x --format dwg -o " + plan);
  EXPECT_EQ(fmt.exit_code, 2);
  EXPECT_NE(fmt.err.find("unknown import format \"dwg\""), std::string::npos) << fmt.err;
  EXPECT_FALSE(std::filesystem::exists(plan));
}

}  // namespace
}  // namespace floorcast
