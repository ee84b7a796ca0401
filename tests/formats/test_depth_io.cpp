// Depth maps made elsewhere (bring your own depth), numpy .npy arrays, PLY clouds, colour images
// in scan folders: round trips, the naming rules of a depth folder, repairs and refusals.
#include <gtest/gtest.h>

#include "common/scratch_dir.hpp"

#include <cmath>
#include <filesystem>
#include <memory>

#include "floorcast/core/depth_io.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/module.hpp"
#include "floorcast/core/ply_io.hpp"
#include "floorcast/core/scan_io.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

class Formats : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_ = std::make_unique<test::ScratchDir>();
    dir_ = scratch_->path();
  }
  void TearDown() override { scratch_.reset(); }
  std::unique_ptr<test::ScratchDir> scratch_;
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

cv::Mat ramp(int rows, int cols) {
  cv::Mat d(rows, cols, CV_32F);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) d.at<float>(r, c) = 0.5f + 0.013f * static_cast<float>(r) + 0.0071f * static_cast<float>(c);
  d.at<float>(0, 0) = 0.0f;  // no return
  return d;
}

TEST_F(Formats, NpyRoundTripAndHeader) {
  const cv::Mat d = ramp(7, 5);
  write_npy(path("a.npy"), d);
  const NpyArray a = read_npy(path("a.npy"));
  EXPECT_EQ(a.dtype, "<f4");
  ASSERT_EQ(a.shape.size(), 2u);
  EXPECT_EQ(a.shape[0], 7u);
  EXPECT_EQ(a.shape[1], 5u);
  // numpy's header layout: magic, version 1.0, header padded to a multiple of 64 ending in '\n'.
  const std::string bytes = read_text_file(path("a.npy"));
  const std::size_t header = static_cast<unsigned char>(bytes[8]) | static_cast<unsigned char>(bytes[9]) << 8;
  EXPECT_EQ((10 + header) % 64, 0u);
  EXPECT_EQ(bytes[10 + header - 1], '\n');
  EXPECT_NE(bytes.find("'shape': (7, 5)"), std::string::npos);
  const cv::Mat back = read_depth_file(path("a.npy"));
  EXPECT_EQ(cv::norm(back, d, cv::NORM_INF), 0.0);
  // 3-D volumes and 1-D shapes in numpy's spelling.
  write_npy(path("v.npy"), {2, 3, 4}, std::vector<float>(24, 1.5f));
  EXPECT_NE(read_text_file(path("v.npy")).find("'shape': (2, 3, 4)"), std::string::npos);
  write_npy(path("w.npy"), {3}, {1.0f, 2.0f, 3.0f});
  EXPECT_NE(read_text_file(path("w.npy")).find("'shape': (3,)"), std::string::npos);
  EXPECT_THROW(write_npy(path("x.npy"), {2, 2}, {1.0f}), InputError);
}

TEST_F(Formats, NpyRefusals) {
  EXPECT_THROW(parse_npy("not numpy", "x"), InputError);
  std::string bytes = npy_bytes(ramp(3, 3));
  EXPECT_THROW(parse_npy(bytes.substr(0, bytes.size() - 4), "truncated"), InputError);
  std::string fortran = bytes;
  fortran.replace(fortran.find("False"), 5, "True ");
  EXPECT_THROW(parse_npy(fortran, "fortran"), InputError);
  std::string big_endian = bytes;
  big_endian.replace(big_endian.find("<f4"), 3, ">f4");
  EXPECT_THROW(parse_npy(big_endian, "big endian"), InputError);
  write_npy(path("u8.npy"), cv::Mat(2, 2, CV_8U, cv::Scalar(3)));
  EXPECT_THROW(read_depth_file(path("u8.npy")), InputError);  // 8-bit holds no metric depth
  write_npy(path("cube.npy"), {2, 3, 4}, std::vector<float>(24, 1.0f));
  EXPECT_THROW(read_depth_file(path("cube.npy")), InputError);
}

TEST_F(Formats, DepthFileRoundTripsInEveryFormat) {
  const cv::Mat d = ramp(24, 32);
  for (const char* ext : {".npy", ".tif", ".tiff", ".exr"}) {
    const std::string p = path(std::string("d") + ext);
    write_depth_file(p, d);
    const cv::Mat back = read_depth_file(p);
    ASSERT_EQ(back.size(), d.size()) << ext;
    EXPECT_EQ(cv::norm(back, d, cv::NORM_INF), 0.0) << ext;  // float32 exactly
  }
  write_depth_file(path("d.png"), d);  // 16-bit millimetres
  const cv::Mat mm = read_depth_file(path("d.png"));
  EXPECT_LE(cv::norm(mm, d, cv::NORM_INF), 0.0005 + 1e-6);
  EXPECT_EQ(mm.at<float>(0, 0), 0.0f);
  // Units: a 16-bit map in centimetres.
  DepthFileOptions cm;
  cm.integer_unit_m = 0.01;
  write_depth_file(path("cm.png"), d, cm);
  EXPECT_LE(cv::norm(read_depth_file(path("cm.png"), cm), d, cv::NORM_INF), 0.005 + 1e-6);
  EXPECT_THROW(read_depth_file(path("d.jpg")), InputError);
  EXPECT_THROW(write_depth_file(path("d.bmp"), d), InputError);
  EXPECT_NE(module_path("floorcast_depthio").find("floorcast_depthio.so"), std::string::npos);
}

Scan two_view_scan(int w, int h) {
  Scan s;
  s.sensor = "test";
  for (int k = 0; k < 2; ++k) {
    DepthView v;
    v.view_index = k;
    v.intrinsics = {w, h, 0.6 * w, 0.6 * w, (w - 1) / 2.0, (h - 1) / 2.0};
    v.T_scan_camera.linear() = Eigen::AngleAxisd(k * 1.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
    v.rgb = cv::Mat(h, w, CV_8UC3, cv::Scalar(10 + k, 120, 200));
    s.views.push_back(v);
  }
  return s;
}

TEST_F(Formats, ScanFolderWithColourOnlyAndDepthFolder) {
  // A scan folder of colour images only (what a phone app and an offline depth network give).
  save_scan(path("scan"), two_view_scan(32, 24));
  EXPECT_TRUE(fs::exists(path("scan/view_000_rgb.png")));
  EXPECT_FALSE(fs::exists(path("scan/view_000_depth.png")));
  EXPECT_THROW(load_scan(path("scan")), InputError);  // observe needs depth from somewhere
  ScanLoadOptions lo;
  lo.require_depth = false;
  lo.load_rgb = true;
  Scan s = load_scan(path("scan"), lo);
  ASSERT_EQ(s.views.size(), 2u);
  EXPECT_EQ(s.views[1].rgb.at<cv::Vec3b>(3, 4), cv::Vec3b(11, 120, 200));
  EXPECT_EQ(s.views[0].rgb_file, "view_000_rgb.png");
  EXPECT_TRUE(s.views[0].depth_m.empty());

  // Depth maps named after the colour image, the view, or view_NNN_depth; any format.
  fs::create_directories(path("depth"));
  const cv::Mat d0 = ramp(24, 32), d1 = 2.0f * ramp(24, 32);
  write_depth_file(path("depth/view_000_rgb.npy"), d0);
  write_depth_file(path("depth/view_001.exr"), d1);
  const DepthDirectoryReport rep = load_depth_directory(s, path("depth"));
  EXPECT_EQ(rep.files.size(), 2u);
  EXPECT_TRUE(rep.repairs.empty());
  EXPECT_EQ(cv::norm(s.views[0].depth_m, d0, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(s.views[1].depth_m, d1, cv::NORM_INF), 0.0);

  // Two candidates for one view: refused (which one did the user mean?).
  write_depth_file(path("depth/view_001_depth.tif"), d1);
  Scan s2 = load_scan(path("scan"), lo);
  EXPECT_THROW(load_depth_directory(s2, path("depth")), InputError);
  fs::remove(path("depth/view_001_depth.tif"));
  // A missing map names what was looked for.
  fs::remove(path("depth/view_001.exr"));
  try {
    load_depth_directory(s2, path("depth"));
    FAIL() << "missing depth map accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("view_001_rgb.npy"), std::string::npos) << e.what();
  }
}

TEST_F(Formats, DepthFolderRepairsAndRefusals) {
  save_scan(path("scan"), two_view_scan(32, 24));
  ScanLoadOptions lo;
  lo.require_depth = false;
  fs::create_directories(path("depth"));
  // Half resolution, same aspect: resampled (nearest) and reported; NaN and negatives dropped.
  cv::Mat half = ramp(12, 16);
  half.at<float>(5, 5) = NAN;
  half.at<float>(6, 6) = -1.0f;
  write_depth_file(path("depth/view_000.npy"), half);
  // A range map: converted to z-depth.
  cv::Mat range(24, 32, CV_32F, cv::Scalar(3.0f));
  write_depth_file(path("depth/view_001.tif"), range);
  Scan s = load_scan(path("scan"), lo);
  DepthFileOptions o;
  o.kind = DepthKind::kRange;
  const DepthDirectoryReport rep = load_depth_directory(s, path("depth"), o);
  ASSERT_EQ(rep.repairs.size(), 2u);
  EXPECT_NE(rep.repairs[0].find("resampled 16x12 -> 32x24"), std::string::npos) << rep.repairs[0];
  EXPECT_NE(rep.repairs[1].find("2 NaN"), std::string::npos) << rep.repairs[1];
  EXPECT_EQ(s.views[0].depth_m.at<float>(11, 11), 0.0f);  // from the NaN cell (5, 5)
  const DepthView& v = s.views[1];
  // Range 3 m along the ray of pixel (u, v) is z = 3 / sqrt(1 + x^2 + y^2).
  const double x = (0 - v.intrinsics.cx_px) / v.intrinsics.fx_px, y = (0 - v.intrinsics.cy_px) / v.intrinsics.fy_px;
  EXPECT_NEAR(v.depth_m.at<float>(0, 0), 3.0 / std::sqrt(1 + x * x + y * y), 1e-5);
  EXPECT_LT(v.depth_m.at<float>(0, 0), v.depth_m.at<float>(12, 16));
  // Another aspect ratio: refused.
  write_depth_file(path("depth/view_000.npy"), ramp(24, 24));
  Scan s3 = load_scan(path("scan"), lo);
  EXPECT_THROW(load_depth_directory(s3, path("depth")), InputError);
  // Nothing valid: refused.
  write_depth_file(path("depth/view_000.npy"), cv::Mat(24, 32, CV_32F, cv::Scalar(0.0f)));
  Scan s4 = load_scan(path("scan"), lo);
  EXPECT_THROW(load_depth_directory(s4, path("depth")), InputError);
  EXPECT_THROW(parse_depth_kind("disparity"), InputError);
}

TEST_F(Formats, PlyRoundTrip) {
  PlyCloud c;
  for (int i = 0; i < 50; ++i) {
    c.points_m.emplace_back(0.1f * i, -0.2f * i, 1.5f);
    c.colours_rgb.push_back({static_cast<std::uint8_t>(i), 7, 250});
  }
  write_ply(path("c.ply"), c, {"frame: test"});
  const std::string bytes = read_text_file(path("c.ply"));
  EXPECT_EQ(bytes.rfind("ply\nformat binary_little_endian 1.0\ncomment frame: test\nelement vertex 50\n", 0), 0u);
  const PlyCloud back = read_ply(path("c.ply"));
  ASSERT_EQ(back.points_m.size(), 50u);
  for (int i = 0; i < 50; ++i) {
    EXPECT_EQ(back.points_m[i], c.points_m[i]);
    EXPECT_EQ(back.colours_rgb[i], c.colours_rgb[i]);
  }
  c.colours_rgb.pop_back();
  EXPECT_THROW(write_ply(path("bad.ply"), c), InputError);
  write_text_file_atomic(path("ascii.ply"), "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
                                            "property double z\nend_header\n1 2 3\n4 5 6\n");
  EXPECT_EQ(read_ply(path("ascii.ply")).points_m[1], Eigen::Vector3f(4, 5, 6));
}

}  // namespace
}  // namespace floorcast
