// End to end through the CLI: `floorcast plan generate` and `floorcast plan render`.
#include <gtest/gtest.h>

#include "common/scratch_dir.hpp"

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "floorcast/floorplans/generate.hpp"
#include "floorcast/floorplans/io.hpp"
#include "floorcast/floorplans/stats.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

/// Runs the CLI with `args`; returns its exit code. Output goes to `log`.
int run_cli(const std::string& args, const fs::path& log) {
  const std::string cmd = std::string("\"") + FLOORCAST_CLI + "\" " + args + " > \"" + log.string() + "\" 2>&1";
  const int status = std::system(cmd.c_str());
  if (status == -1) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_ = std::make_unique<test::ScratchDir>();
    dir_ = scratch_->path();
  }
  void TearDown() override { scratch_.reset(); }
  std::unique_ptr<test::ScratchDir> scratch_;
  fs::path dir_;
};

TEST_F(Cli, GenerateWritesTheSameBytesAsTheLibrary) {
  const fs::path out = dir_ / "apt.json", rooms = dir_ / "rooms.json";
  ASSERT_EQ(run_cli("plan generate --archetype apartment --seed 3 -o " + out.string() + " --rooms " + rooms.string(),
                    dir_ / "log"),
            0)
      << read_text_file((dir_ / "log").string());
  EXPECT_EQ(read_text_file(out.string()), floor_plan_to_json(generate_apartment(3).plan));
  const std::string r = read_text_file(rooms.string());
  EXPECT_NE(r.find("\"kind\": \"bedroom\""), std::string::npos);
  EXPECT_NE(r.find("\"polygon\""), std::string::npos);
}

// --campus-halls (plain, orthogonal), --no-furniture and --wall-thickness give the library's buildings with those
// parameters; misapplied
// options are refused with a non-zero exit and a message naming the option.
TEST_F(Cli, GenerateCampusHallsNoFurnitureAndWallThicknessMatchTheLibrary) {
  const fs::path out = dir_ / "campus.json";
  ASSERT_EQ(run_cli("plan generate -a campus -s 3 --campus-halls plain -o " + out.string(), dir_ / "log"), 0)
      << read_text_file((dir_ / "log").string());
  CampusParams plain;
  plain.hall_variety.enabled = false;
  EXPECT_EQ(read_text_file(out.string()), floor_plan_to_json(generate_campus(3, plain).plan));
  ASSERT_EQ(run_cli("plan generate -a campus -s 3 --campus-halls orthogonal -o " + out.string(), dir_ / "log"), 0)
      << read_text_file((dir_ / "log").string());
  CampusParams orthogonal;
  orthogonal.hall_variety.chamfer_probability = 0.0;
  const std::string orthogonal_json = floor_plan_to_json(generate_campus(3, orthogonal).plan);
  EXPECT_EQ(read_text_file(out.string()), orthogonal_json);
  EXPECT_NE(orthogonal_json, floor_plan_to_json(generate_campus(3).plan));  // seed 3 has chamfered halls
  ASSERT_EQ(run_cli("plan generate -a campus -s 3 --no-furniture -o " + out.string(), dir_ / "log"), 0)
      << read_text_file((dir_ / "log").string());
  // The same building without its obstacles.
  GeneratedBuilding b = generate_campus(3);
  ASSERT_FALSE(b.plan.obstacles.empty());
  b.plan.obstacles.clear();
  EXPECT_EQ(read_text_file(out.string()), floor_plan_to_json(b.plan));
  // --wall-thickness: the same building with every wall that thick.
  ASSERT_EQ(run_cli("plan generate -a campus -s 3 --wall-thickness 0.1 -o " + out.string(), dir_ / "log"), 0)
      << read_text_file((dir_ / "log").string());
  GeneratedBuilding thin = generate_campus(3);
  for (Wall& w : thin.plan.walls) w.thickness_m = 0.1;
  EXPECT_EQ(read_text_file(out.string()), floor_plan_to_json(thin.plan));
  EXPECT_NE(run_cli("plan generate -a campus -s 3 --wall-thickness 0 -o " + out.string(), dir_ / "log"), 0);
  EXPECT_NE(read_text_file((dir_ / "log").string()).find("--wall-thickness"), std::string::npos);
  EXPECT_NE(run_cli("plan generate -a office -s 3 --campus-halls plain -o " + out.string(), dir_ / "log"), 0);
  EXPECT_NE(read_text_file((dir_ / "log").string()).find("--campus-halls"), std::string::npos);
  EXPECT_NE(run_cli("plan generate -a campus -s 3 --campus-layout blocks --campus-halls varied -o " + out.string(),
                    dir_ / "log"),
            0);
}

TEST_F(Cli, PlanStatsPrintsOneJsonObjectPerPlanMatchingTheLibrary) {
  const std::string office = std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/office.json";
  const std::string apt = std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/apartment.json";
  ASSERT_EQ(run_cli("plan stats --json " + office + " " + apt, dir_ / "out.json"), 0)
      << read_text_file((dir_ / "out.json").string());
  const std::string text = read_text_file((dir_ / "out.json").string());
  const PlanStats lib = plan_stats(load_floor_plan(office));
  EXPECT_NE(text.find("\"walls\": " + std::to_string(lib.walls) + ","), std::string::npos) << text.substr(0, 400);
  EXPECT_NE(text.find("\"repeated_width_share\""), std::string::npos);
  EXPECT_NE(text.find("apartment.json"), std::string::npos);
  // A missing file is refused with its name and a non-zero exit.
  EXPECT_NE(run_cli("plan stats " + (dir_ / "missing.json").string(), dir_ / "log"), 0);
  EXPECT_NE(read_text_file((dir_ / "log").string()).find("missing.json"), std::string::npos);
}

TEST_F(Cli, RenderWritesPngAndSvg) {
  const std::string plan = std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/apartment.json";
  const fs::path png = dir_ / "apt.png", svg = dir_ / "apt.svg";
  ASSERT_EQ(run_cli("plan render " + plan + " -o " + png.string() + " --px-per-m 25", dir_ / "log"), 0)
      << read_text_file((dir_ / "log").string());
  const cv::Mat img = cv::imread(png.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty());
  EXPECT_GE(img.cols, 25 * 11);
  ASSERT_EQ(run_cli("plan render " + plan + " -o " + svg.string(), dir_ / "log"), 0);
  const std::string text = read_text_file(svg.string());
  EXPECT_EQ(text.rfind("<?xml", 0), 0u);
  EXPECT_NE(text.find("</svg>"), std::string::npos);
}

TEST_F(Cli, BadInputExitsWithCode2) {
  const std::string plan = std::string(FLOORCAST_SOURCE_DIR) + "/floorplans/buildings/two_rooms.json";
  EXPECT_EQ(run_cli("plan render " + plan + " -o " + (dir_ / "x.bmp").string(), dir_ / "log"), 2);
  EXPECT_NE(read_text_file((dir_ / "log").string()).find("use .png or .svg"), std::string::npos);
  EXPECT_EQ(run_cli("plan render " + plan + " -o " + (dir_ / "x.png").string() + " --px-per-m -1", dir_ / "log"), 2);
  EXPECT_EQ(run_cli("plan generate --archetype castle -o " + (dir_ / "c.json").string(), dir_ / "log"), 2);
  EXPECT_NE(read_text_file((dir_ / "log").string()).find("castle"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "c.json"));
}

}  // namespace
}  // namespace floorcast
