#include "floorcast/core/file_io.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "floorcast/core/limits.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {

std::string read_text_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading: " + std::strerror(errno));
  // Read in chunks up to the limit: a device or pipe without end (/dev/zero) stops there.
  const double limit = input_limits().max_file_bytes;
  std::string text;
  std::vector<char> chunk(1 << 16);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const std::streamsize got = in.gcount();
    if (got <= 0) break;
    text.append(chunk.data(), static_cast<std::size_t>(got));
    if (static_cast<double>(text.size()) > limit) {
      check_limit("max_file_bytes", static_cast<double>(text.size()), path + ": file has more than", "bytes");
    }
  }
  if (in.bad()) throw InputError(path + ": read error");
  return text;
}

void write_text_file_atomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot open for writing: " + std::strerror(errno));
    out << text;
    out.flush();
    if (!out) throw InputError(path + ": write error");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot move the written file into place: " + reason);
  }
}

void create_directories_or_throw(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec || !std::filesystem::is_directory(path)) {
    throw InputError(path + ": cannot create directory" + (ec ? ": " + ec.message() : std::string()));
  }
}

}  // namespace floorcast
