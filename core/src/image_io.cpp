#include "floorcast/core/image_io.hpp"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

void write_png(const std::string& path, const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  bool ok = false;
  try {
    ok = cv::imencode(".png", image, bytes);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot encode PNG: " + e.what());
  }
  if (!ok) throw InputError(path + ": cannot encode PNG");
  write_text_file_atomic(path, std::string(bytes.begin(), bytes.end()));
}

cv::Mat read_image(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": image missing");
  cv::Mat m;
  try {
    m = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot decode the image: " + e.what());
  }
  if (m.empty()) throw InputError(path + ": cannot decode the image");
  return m;
}

}  // namespace floorcast
