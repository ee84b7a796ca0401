#include "floorcast/core/file_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

#include "floorcast/core/limits.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

using FileId = std::pair<dev_t, ino_t>;

/// The running command's inputs (CommandFiles) and the output folders it owns.
struct Tracking {
  std::mutex mutex;
  int scopes = 0;
  std::map<FileId, std::string> inputs;
  std::vector<std::string> owned;  ///< canonical paths of owned output folders
};

Tracking& tracking() {
  static Tracking t;
  return t;
}

std::string canonical_or_self(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? path : p.string();
}

bool below(const std::string& path, const std::string& folder) {
  return path.size() > folder.size() && path.compare(0, folder.size(), folder) == 0 && path[folder.size()] == '/';
}

void note_input(const std::string& path, const struct stat& st) {
  Tracking& t = tracking();
  std::lock_guard<std::mutex> lock(t.mutex);
  if (t.scopes == 0) return;
  if (!t.owned.empty()) {
    const std::string c = canonical_or_self(path);
    for (const std::string& o : t.owned) {
      if (below(c, o)) return;
    }
  }
  t.inputs.emplace(FileId{st.st_dev, st.st_ino}, path);
}

/// The input path recorded for this file, or empty.
std::string input_named(const struct stat& st) {
  Tracking& t = tracking();
  std::lock_guard<std::mutex> lock(t.mutex);
  const auto it = t.inputs.find(FileId{st.st_dev, st.st_ino});
  return it == t.inputs.end() ? std::string() : it->second;
}

/// What a file that is not a regular one is, for messages.
std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

/// stat() of an input, refusing what is not a regular file without opening it.
struct stat stat_input(const std::string& path, bool check_size = true) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOENT) throw InputError(path + ": no such file");
    throw InputError(path + ": cannot read: " + io_error_text(err));
  }
  if (S_ISDIR(st.st_mode)) throw InputError(path + ": is a folder, expected a file");
  if (!S_ISREG(st.st_mode)) {
    throw InputError(path + ": is " + kind_of(st.st_mode) +
                     ", not a regular file; floorcast reads regular files only (\"-\" reads standard input where a "
                     "command takes one file)");
  }
  if (check_size) check_limit("max_file_bytes", static_cast<double>(st.st_size), path + ": file size", "bytes");
  return st;
}

/// Reads everything from `fd` up to the file-size limit.
std::string read_all(int fd, const std::string& path, std::size_t expected) {
  const double limit = input_limits().max_file_bytes;
  std::string text;
  text.reserve(expected);
  std::vector<char> chunk(1 << 16);
  while (true) {
    const ssize_t got = ::read(fd, chunk.data(), chunk.size());
    if (got < 0) {
      if (errno == EINTR) continue;
      throw InputError(path + ": read error: " + io_error_text(errno));
    }
    if (got == 0) break;
    text.append(chunk.data(), static_cast<std::size_t>(got));
    if (static_cast<double>(text.size()) > limit) {
      check_limit("max_file_bytes", static_cast<double>(text.size()), path + ": read so far", "bytes");
    }
  }
  return text;
}

/// Refuses writing over `path` (not "-"): it must not exist, or be a regular file that is not
/// an input of the command.
void check_target(const std::string& path) {
  if (path.empty()) throw InputError("an output path is empty");
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    const int err = errno;
    if (err == ENOENT) return;  // a new file (whether its folder exists is found when writing)
    throw InputError(path + ": cannot write: " + io_error_text(err));
  }
  if (S_ISLNK(st.st_mode)) {
    std::error_code ec;
    const fs::path target = fs::read_symlink(path, ec);
    throw InputError(path + ": is a symbolic link" + (ec ? std::string() : " (to " + target.string() + ")") +
                     "; floorcast replaces only regular files: write to the link's target, or remove the link");
  }
  if (S_ISDIR(st.st_mode)) throw InputError(path + ": is a folder, expected a file to write");
  if (!S_ISREG(st.st_mode)) {
    throw InputError(path + ": is " + kind_of(st.st_mode) +
                     ", not a regular file; floorcast replaces only regular files (\"-\" writes to standard output "
                     "where a command writes one file)");
  }
  const std::string input = input_named(st);
  if (!input.empty()) {
    throw InputError(path + ": is an input of this command" + (input == path ? std::string() : " (the same file as " + input + ")") +
                     "; writing there would destroy it: choose another output");
  }
}

std::atomic<unsigned> temp_counter{0};

std::string temporary_name(const std::string& path) {
  const fs::path p(path);
  std::string name = p.filename().string();
  if (name.size() > 180) name = name.substr(0, 180);
  // The target's extension is kept at the end: libraries that write by name (libtiff, OpenEXR)
  // choose the format from it.
  const std::string tmp = "." + name + "." + std::to_string(::getpid()) + "." + std::to_string(temp_counter++) + ".tmp" +
                          p.extension().string();
  return (p.parent_path() / tmp).string();
}

void write_fd(int fd, const char* data, std::size_t bytes, const std::string& what) {
  while (bytes > 0) {
    const ssize_t n = ::write(fd, data, bytes);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw InputError(what + ": cannot write: " + io_error_text(errno));
    }
    data += n;
    bytes -= static_cast<std::size_t>(n);
  }
}

}  // namespace

std::string io_error_text(int err) {
  switch (err) {
    case ENOSPC: return "no space left on the device (disk full)";
    case EDQUOT: return "disk quota exceeded";
    case EFBIG: return "file too large (the file system's or the process's file-size limit)";
    case EROFS: return "read-only file system";
    case EACCES:
    case EPERM: return "permission denied";
    case ENOENT: return "no such file or folder";
    case ENOTDIR: return "a part of the path is not a folder";
    case EIO: return "input/output error";
    default: return std::strerror(err);
  }
}

std::string input_name(const std::string& path) { return path == "-" ? std::string("standard input") : path; }

std::string read_text_file(const std::string& path) {
  if (path == "-") {
    struct stat st {};
    if (::fstat(0, &st) == 0 && S_ISREG(st.st_mode)) note_input("-", st);
    return read_all(0, "standard input", 0);
  }
  const struct stat st = stat_input(path);
  // O_NONBLOCK: if the path was replaced by a FIFO since stat(), open() still does not wait.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) throw InputError(path + ": cannot open for reading: " + io_error_text(errno));
  struct stat now {};
  if (::fstat(fd, &now) != 0 || !S_ISREG(now.st_mode) || now.st_ino != st.st_ino || now.st_dev != st.st_dev) {
    ::close(fd);
    throw InputError(path + ": changed while it was opened (no longer the regular file it was)");
  }
  note_input(path, now);
  try {
    std::string text = read_all(fd, path, static_cast<std::size_t>(now.st_size));
    ::close(fd);
    return text;
  } catch (...) {
    ::close(fd);
    throw;
  }
}

void check_input_file(const std::string& path, bool check_size) {
  if (path == "-") throw InputError("- (standard input): this reader needs a named file");
  note_input(path, stat_input(path, check_size));
}

void check_output_path(const std::string& path) {
  if (path == "-") return;
  check_target(path);
}

void check_distinct_outputs(const std::vector<std::string>& paths) {
  std::vector<std::pair<std::string, std::string>> seen;  // canonical, as given
  std::map<FileId, std::string> ids;
  for (const std::string& p : paths) {
    if (p.empty()) continue;
    const std::string c = p == "-" ? p : canonical_or_self(p);
    for (const auto& [other_c, other] : seen) {
      if (other_c == c) throw InputError(p + ": names the same file as the output " + other + "; give each output its own file");
    }
    seen.emplace_back(c, p);
    struct stat st {};
    if (p != "-" && ::stat(p.c_str(), &st) == 0) {
      const auto [it, fresh] = ids.emplace(FileId{st.st_dev, st.st_ino}, p);
      if (!fresh) throw InputError(p + ": is the same file as the output " + it->second + "; give each output its own file");
    }
  }
}

void write_text_file_atomic(const std::string& path, const std::string& text) {
  AtomicFileWriter w(path);
  w.write(text);
  w.commit();
}

void create_directories_or_throw(const std::string& path) {
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec)) {
    struct stat st {};
    const std::string what = ::stat(path.c_str(), &st) == 0 ? kind_of(st.st_mode) : std::string("not a folder");
    throw InputError(path + ": exists and is " + (what == "not a regular file" ? std::string("a file") : what) +
                     ", expected a folder for the output");
  }
  fs::create_directories(path, ec);
  if (ec || !fs::is_directory(path)) {
    throw InputError(path + ": cannot create the folder" + (ec ? ": " + io_error_text(ec.value()) : std::string()));
  }
}

AtomicFileWriter::AtomicFileWriter(std::string path) : path_(std::move(path)) {
  if (path_ == "-") {
    stdout_ = true;
    std::cout.flush();
    std::fflush(stdout);
    return;
  }
  check_target(path_);
  tmp_ = temporary_name(path_);
  fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0666);
  if (fd_ < 0) {
    const int err = errno;
    const fs::path folder = fs::path(path_).parent_path();
    std::error_code ec;
    if (err == ENOENT && !folder.empty() && !fs::is_directory(folder, ec)) {
      throw InputError(path_ + ": cannot write: the folder " + folder.string() + " does not exist");
    }
    throw InputError(path_ + ": cannot write: " + io_error_text(err));
  }
  // A replaced file keeps its permissions.
  struct stat st {};
  if (::stat(path_.c_str(), &st) == 0 && S_ISREG(st.st_mode)) (void)::fchmod(fd_, st.st_mode & 07777);
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !tmp_.empty()) ::unlink(tmp_.c_str());
}

void AtomicFileWriter::write(const void* data, std::size_t bytes) {
  if (committed_) throw InputError(path_ + ": written after it was closed");
  if (stdout_) {
    write_fd(1, static_cast<const char*>(data), bytes, "standard output");
    return;
  }
  if (fd_ < 0) throw InputError(path_ + ": the temporary file was released to another writer");
  try {
    write_fd(fd_, static_cast<const char*>(data), bytes, path_);
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    ::unlink(tmp_.c_str());
    tmp_.clear();
    throw;
  }
}

const std::string& AtomicFileWriter::release_temporary_path() {
  if (stdout_) throw InputError("- (standard output): this writer needs a named file");
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  return tmp_;
}

void AtomicFileWriter::commit() {
  if (committed_) return;
  if (stdout_) {
    committed_ = true;
    return;
  }
  if (tmp_.empty()) throw InputError(path_ + ": the write failed earlier");
  auto fail = [this](const std::string& what, int err) {
    ::unlink(tmp_.c_str());
    tmp_.clear();
    throw InputError(path_ + ": " + what + ": " + io_error_text(err));
  };
  if (fd_ >= 0) {
    const int fd = fd_;
    fd_ = -1;
    // Network and quota-limited file systems report some write errors only when the file closes.
    if (::close(fd) != 0) fail("cannot write", errno);
  }
  check_target(path_);  // again: the target may have changed while we wrote
  if (::rename(tmp_.c_str(), path_.c_str()) != 0) fail("cannot move the written file into place", errno);
  committed_ = true;
}

CommandFiles::CommandFiles() {
  Tracking& t = tracking();
  std::lock_guard<std::mutex> lock(t.mutex);
  ++t.scopes;
}

CommandFiles::~CommandFiles() {
  Tracking& t = tracking();
  std::lock_guard<std::mutex> lock(t.mutex);
  if (--t.scopes == 0) {
    t.inputs.clear();
    t.owned.clear();
  }
}

void note_owned_output_folder(const std::string& dir) {
  const std::string c = canonical_or_self(dir);
  Tracking& t = tracking();
  std::lock_guard<std::mutex> lock(t.mutex);
  if (t.scopes == 0) return;
  for (const std::string& o : t.owned) {
    if (o == c) return;
  }
  t.owned.push_back(c);
  // What was read below it before (a run folder's own run.json, read to decide whether to resume
  // or to merge into it) is the command's state too.
  for (auto it = t.inputs.begin(); it != t.inputs.end();) {
    it = below(canonical_or_self(it->second), c) ? t.inputs.erase(it) : std::next(it);
  }
}

}  // namespace floorcast
