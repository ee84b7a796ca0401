// core/image_io (libpng, netpbm) against OpenCV's imgcodecs as the independent reference.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/image_io.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

class ImageIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("floorcast_image_io_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

cv::Mat random_image(int rows, int cols, int type, int seed) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  rng.fill(m, cv::RNG::UNIFORM, 0, CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256);
  return m;
}

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.type() == b.type() && a.size() == b.size() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

TEST_F(ImageIo, WrittenPngsDecodeIdenticallyInOpenCv) {
  int seed = 1;
  for (const int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1}) {
    const cv::Mat image = random_image(37, 53, type, seed++);
    write_png(path("a.png"), image);
    const cv::Mat back = cv::imread(path("a.png"), cv::IMREAD_UNCHANGED);
    EXPECT_TRUE(same(image, back)) << "type " << type;
    EXPECT_TRUE(same(image, read_image(path("a.png")))) << "type " << type;
  }
}

TEST_F(ImageIo, OpenCvPngsReadIdentically) {
  int seed = 10;
  for (const int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1, CV_16UC3}) {
    const cv::Mat image = random_image(29, 31, type, seed++);
    ASSERT_TRUE(cv::imwrite(path("b.png"), image));
    EXPECT_TRUE(same(image, read_image(path("b.png")))) << "type " << type;
  }
}

TEST_F(ImageIo, PalettesLowBitDepthsAndGrayAlphaExpandLikeOpenCv) {
  // 1-bit gray (OpenCV writes binary images this way with IMWRITE_PNG_BILEVEL) and a palette PNG
  // written by hand: both must read as 8-bit, as OpenCV reads them.
  cv::Mat bilevel = random_image(16, 24, CV_8UC1, 3) > 127;
  ASSERT_TRUE(cv::imwrite(path("bi.png"), bilevel, {cv::IMWRITE_PNG_BILEVEL, 1}));
  EXPECT_TRUE(same(cv::imread(path("bi.png"), cv::IMREAD_UNCHANGED), read_image(path("bi.png"))));

  // A 3x2 palette image (colour type 3; red, green, blue, white), made with Python's zlib.
  const std::string hex =
      "89504e470d0a1a0a0000000d4948445200000003000000020803000000aaaa96280000000c504c5445ff000000ff00"
      "0000fffffffffb0060f60000001049444154789c636060646260666204000026000a1b1c09790000000049454e44ae"
      "426082";
  std::string bytes;
  for (std::size_t i = 0; i < hex.size(); i += 2) bytes.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  write_text_file_atomic(path("pal.png"), bytes);
  const cv::Mat reference = cv::imread(path("pal.png"), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(reference.empty());
  const cv::Mat ours = read_image(path("pal.png"));
  EXPECT_TRUE(same(reference, ours));
  ASSERT_EQ(ours.type(), CV_8UC3);
  EXPECT_EQ(ours.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 255));      // red, in BGR order
  EXPECT_EQ(ours.at<cv::Vec3b>(1, 0), cv::Vec3b(255, 255, 255));  // white
}

TEST_F(ImageIo, BinaryPgmAndPpm) {
  int seed = 20;
  for (const int type : {CV_8UC1, CV_8UC3, CV_16UC1}) {
    const cv::Mat image = random_image(11, 17, type, seed++);
    const std::string name = path(CV_MAT_CN(type) == 3 ? "c.ppm" : "c.pgm");
    ASSERT_TRUE(cv::imwrite(name, image, {cv::IMWRITE_PXM_BINARY, 1}));
    EXPECT_TRUE(same(image, read_image(name))) << "type " << type;
  }
}

TEST_F(ImageIo, BadInputIsAnInputErrorNamingTheFile) {
  write_text_file_atomic(path("junk.png"), "not an image at all");
  try {
    read_image(path("junk.png"));
    FAIL() << "junk decoded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("junk.png"), std::string::npos) << e.what();
  }
  // A PNG cut in half: libpng's error must come back as an InputError, not a crash.
  write_png(path("whole.png"), random_image(64, 64, CV_8UC3, 5));
  const std::string whole = read_text_file(path("whole.png"));
  write_text_file_atomic(path("half.png"), whole.substr(0, whole.size() / 2));
  EXPECT_THROW(read_image(path("half.png")), InputError);
  EXPECT_THROW(read_image(path("missing.png")), InputError);
  EXPECT_THROW(encode_png(cv::Mat(4, 4, CV_32FC1, cv::Scalar(1.0f))), InputError);
  // A PGM header that promises more pixels than the file holds.
  write_text_file_atomic(path("short.pgm"), "P5\n100 100\n255\nabc");
  EXPECT_THROW(read_image(path("short.pgm")), InputError);
}

}  // namespace
}  // namespace floorcast
