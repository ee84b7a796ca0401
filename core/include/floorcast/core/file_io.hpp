// The one input layer and the one output layer of floorcast (every component's io part reads and
// writes files through these functions; docs/limits.md, "Files").
//
// Input: regular files only, or "-" for standard input. A folder, FIFO, device or socket is
// refused from its metadata, without opening it (a FIFO with no writer cannot block, /dev/zero
// is not read), and the size is checked against the limit max_file_bytes before anything is read.
//
// Output: a file is written through a temporary file in its own folder and moved into place
// when it is complete; every error path removes the temporary and names the cause ("no space left
// on the device (disk full)"). A target that exists and is not a regular file (a device, FIFO,
// socket, symbolic link or folder) is refused, and so is a target that is one of the files the
// running command read (same device and inode) while a CommandFiles scope is alive (the CLI
// opens one per command). "-" is standard output.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace floorcast {

/// Reads a whole regular file (or standard input for "-") into a string; throws InputError naming
/// the path and the reason (missing, a folder, a FIFO or device, too large, unreadable).
std::string read_text_file(const std::string& path);

/// How messages name an input: "standard input" for "-", the path otherwise.
std::string input_name(const std::string& path);

/// The checks read_text_file makes before reading, for readers that open a file by name
/// themselves (libtiff, OpenEXR): a regular file within max_file_bytes; noted as an input of the
/// running command. "-" is refused (such readers cannot read standard input). `check_size`
/// false skips the size limit (a binary cache whose sizes its reader checks field by field).
void check_input_file(const std::string& path, bool check_size = true);

/// Writes a whole file atomically (see AtomicFileWriter); "-" writes to standard output.
void write_text_file_atomic(const std::string& path, const std::string& text);

/// Throws InputError unless `path` may be written: it does not exist, or is a regular file that
/// is not an input of the running command; "-" (standard output) always may. Commands call it
/// before long work so that a wrong -o fails at once.
void check_output_path(const std::string& path);

/// Throws InputError when two of `paths` name the same file (the same path, or existing files of
/// the same device and inode): one command writing two of its outputs into one file. Empty
/// entries are ignored; "-" may appear once.
void check_distinct_outputs(const std::vector<std::string>& paths);

/// Creates a directory and its parents; throws InputError naming it on failure (including an
/// existing path that is not a folder).
void create_directories_or_throw(const std::string& path);

/// A short reason for an errno value of a file operation: "no space left on the device (disk
/// full)", "disk quota exceeded", "permission denied", ... (strerror otherwise).
std::string io_error_text(int errnum);

/// One output file written through a temporary file in the target's folder (created exclusively,
/// named .NAME.PID.N.tmp.EXT, EXT the target's extension) and renamed over the target by commit(). The constructor refuses a
/// target check_output_path refuses; write() and commit() throw InputError naming the target and
/// the cause; the destructor removes the temporary unless commit() succeeded. For "-" the bytes go
/// to standard output as they are written.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::string path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  void write(const void* data, std::size_t bytes);
  void write(const std::string& bytes) { write(bytes.data(), bytes.size()); }
  /// For a library that writes the file by name itself (libtiff, OpenEXR): closes this writer's
  /// descriptor and returns the temporary's path (an empty file) to write into before commit().
  /// Not for "-".
  const std::string& release_temporary_path();
  /// Moves the finished file into place (re-checking the target first).
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string tmp_;
  int fd_ = -1;
  bool committed_ = false;
  bool stdout_ = false;
};

/// While alive (the CLI holds one for each command), every file read through this layer is
/// remembered as an input of the command, and writing over one of them is refused. Not nestable
/// across threads: one per process at a time.
class CommandFiles {
 public:
  CommandFiles();
  ~CommandFiles();
  CommandFiles(const CommandFiles&) = delete;
  CommandFiles& operator=(const CommandFiles&) = delete;
};

/// Marks `dir` as an output folder the running command owns (a run directory it holds the lock
/// of): files read below it, before or after, are the command's own state, not inputs, so it may
/// rewrite them (a run resumed, shards merged into one of them).
void note_owned_output_folder(const std::string& dir);

}  // namespace floorcast
