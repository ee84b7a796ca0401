// The input and output layers (core/file_io.hpp, issue 28) and the spatial index (box_index.hpp):
// what may be read and written, what is refused and what is left behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include "common/scratch_dir.hpp"
#include "floorcast/core/box_index.hpp"
#include "floorcast/core/file_io.hpp"
#include "floorcast/core/json_text.hpp"
#include "floorcast/core/limits.hpp"
#include "floorcast/core/trajectory_io.hpp"
#include "floorcast/core/types.hpp"

namespace floorcast {
namespace {

namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Names of the temporary files (*.tmp) left in a folder.
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.find(".tmp") != std::string::npos) out.push_back(name);
  }
  return out;
}

TEST(FileIo, WritesAtomicallyAndReadsBack) {
  const test::ScratchDir dir;
  const std::string p = dir.file("a.txt");
  write_text_file_atomic(p, "one");
  write_text_file_atomic(p, "two");
  EXPECT_EQ(read_text_file(p), "two");
  EXPECT_TRUE(temporaries(dir.path()).empty());
}

TEST(FileIo, KeepsThePermissionsOfAReplacedFile) {
  const test::ScratchDir dir;
  const std::string p = dir.file("a.txt");
  write_text_file_atomic(p, "one");
  ::chmod(p.c_str(), 0600);
  write_text_file_atomic(p, "two");
  struct stat st {};
  ASSERT_EQ(::stat(p.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
}

TEST(FileIo, RefusesToReplaceWhatIsNotARegularFile) {
  const test::ScratchDir dir;
  // A FIFO: refused without opening it (opening a FIFO for writing without a reader blocks).
  const std::string fifo = dir.file("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  EXPECT_TRUE(has(error_of([&] { write_text_file_atomic(fifo, "x"); }), "FIFO"));
  EXPECT_TRUE(fs::is_fifo(fifo));
  // A symbolic link: neither the link nor its target changes.
  const std::string target = dir.file("target.txt"), link = dir.file("link.txt");
  write_text_file_atomic(target, "keep");
  fs::create_symlink(target, link);
  EXPECT_TRUE(has(error_of([&] { write_text_file_atomic(link, "x"); }), "symbolic link"));
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(read_text_file(target), "keep");
  // A folder.
  EXPECT_TRUE(has(error_of([&] { write_text_file_atomic(dir.path().string(), "x"); }), "is a folder"));
  // A missing folder is named.
  EXPECT_TRUE(has(error_of([&] { write_text_file_atomic(dir.file("no/such/file"), "x"); }), "does not exist"));
  EXPECT_TRUE(temporaries(dir.path()).empty());
}

TEST(FileIo, RefusesToReadWhatIsNotARegularFileWithoutBlocking) {
  const test::ScratchDir dir;
  const std::string fifo = dir.file("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  // No writer: opening it for reading would block forever; refused from its metadata.
  EXPECT_TRUE(has(error_of([&] { (void)read_text_file(fifo); }), "FIFO"));
  EXPECT_TRUE(has(error_of([&] { check_input_file(fifo); }), "FIFO"));
  EXPECT_TRUE(has(error_of([&] { (void)read_text_file(dir.path().string()); }), "is a folder"));
  EXPECT_TRUE(has(error_of([&] { (void)read_text_file(dir.file("none")); }), "no such file"));
  // A character device (the real /dev/null is only read, never written).
  EXPECT_TRUE(has(error_of([&] { (void)read_text_file("/dev/null"); }), "character device"));
}

TEST(FileIo, ChecksTheSizeBeforeReading) {
  const test::ScratchDir dir;
  const std::string p = dir.file("big.txt");
  write_text_file_atomic(p, std::string(5000, 'x'));
  const InputLimits saved = input_limits();
  InputLimits small = saved;
  small.max_file_bytes = 1000;
  set_input_limits(small);
  const std::string e = error_of([&] { (void)read_text_file(p); });
  set_input_limits(saved);
  EXPECT_TRUE(has(e, "max_file_bytes")) << e;
  EXPECT_TRUE(has(e, "file size: 5000 bytes")) << e;
}

TEST(FileIo, AFailedWriteLeavesNoTemporaryAndNamesTheCause) {
  const test::ScratchDir dir;
  const std::string p = dir.file("out.bin");
  // The process's file-size limit makes the write fail (EFBIG) as a full disk would (ENOSPC).
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto old_handler = ::signal(SIGXFSZ, SIG_IGN);
  rlimit small = saved;
  small.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  const std::string e = error_of([&] { write_text_file_atomic(p, std::string(100000, 'x')); });
  ::setrlimit(RLIMIT_FSIZE, &saved);
  ::signal(SIGXFSZ, old_handler);
  EXPECT_TRUE(has(e, "file too large")) << e;
  EXPECT_TRUE(has(e, p)) << e;
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(temporaries(dir.path()).empty());
  EXPECT_EQ(io_error_text(ENOSPC), "no space left on the device (disk full)");
}

TEST(FileIo, AnUncommittedWriterRemovesItsTemporary) {
  const test::ScratchDir dir;
  {
    AtomicFileWriter w(dir.file("x.npy"));
    w.write("partial");
  }
  EXPECT_FALSE(fs::exists(dir.file("x.npy")));
  EXPECT_TRUE(temporaries(dir.path()).empty());
}

TEST(FileIo, NoOutputReplacesAnInputOfTheCommand) {
  const test::ScratchDir dir;
  const std::string in = dir.file("plan.json"), hard = dir.file("hardlink.json");
  write_text_file_atomic(in, "{}");
  fs::create_hard_link(in, hard);
  {
    const CommandFiles files;
    (void)read_text_file(in);
    EXPECT_TRUE(has(error_of([&] { write_text_file_atomic(in, "x"); }), "input of this command"));
    EXPECT_TRUE(has(error_of([&] { check_output_path(hard); }), "the same file as " + in));
    write_text_file_atomic(dir.file("other.json"), "ok");
  }
  EXPECT_EQ(read_text_file(in), "{}");
  write_text_file_atomic(in, "after");  // outside a command nothing is tracked (library users)
  EXPECT_EQ(read_text_file(in), "after");
}

TEST(FileIo, FilesBelowAnOwnedOutputFolderAreNotInputs) {
  const test::ScratchDir dir;
  const fs::path run = dir.path() / "run";
  fs::create_directories(run);
  write_text_file_atomic((run / "run.json").string(), "{}");
  const CommandFiles files;
  note_owned_output_folder(run.string());
  (void)read_text_file((run / "run.json").string());
  write_text_file_atomic((run / "run.json").string(), "{\"x\": 1}");  // the run's own state
  EXPECT_EQ(read_text_file((run / "run.json").string()), "{\"x\": 1}");
}

TEST(FileIo, DistinctOutputs) {
  const test::ScratchDir dir;
  EXPECT_NO_THROW(check_distinct_outputs({dir.file("a"), dir.file("b"), "", "-"}));
  EXPECT_TRUE(has(error_of([&] { check_distinct_outputs({dir.file("a"), dir.file("sub/../a")}); }), "same file"));
  EXPECT_TRUE(has(error_of([&] { check_distinct_outputs({"-", "-"}); }), "same file"));
}

TEST(FileIo, CreatesFoldersButNotOverFiles) {
  const test::ScratchDir dir;
  create_directories_or_throw(dir.file("a/b/c"));
  EXPECT_TRUE(fs::is_directory(dir.file("a/b/c")));
  write_text_file_atomic(dir.file("f"), "x");
  EXPECT_TRUE(has(error_of([&] { create_directories_or_throw(dir.file("f")); }), "expected a folder"));
}

TEST(JsonText, DuplicateKeysAreRefusedWithTheirPosition) {
  const std::string e = error_of([] { (void)parse_json_text("{\"a\": 1,\n \"b\": {\"c\": 1, \"c\": 2}}", "x.json"); });
  EXPECT_TRUE(has(e, "x.json:2:")) << e;
  EXPECT_TRUE(has(e, "duplicate key \"c\"")) << e;
  EXPECT_NO_THROW((void)parse_json_text("{\"a\": {\"c\": 1}, \"b\": {\"c\": 2}, \"l\": [{\"c\": 1}, {\"c\": 2}]}", "ok"));
  EXPECT_THROW((void)parse_ordered_json_text("{\"a\": 1, \"a\": 1}", "x"), InputError);
}

TEST(JsonText, ByteOrderMark) {
  std::string t = "\xEF\xBB\xBF" "0,1";
  EXPECT_TRUE(strip_utf8_bom(t));
  EXPECT_EQ(t, "0,1");
  EXPECT_FALSE(strip_utf8_bom(t));
}

TEST(Trajectory, PositionsBeyondTheCoordinateRangeAreRefused) {
  EXPECT_NO_THROW((void)parse_tum("0 1 2 0 0 0 0 1\n", "t.tum"));
  EXPECT_TRUE(has(error_of([] { (void)parse_tum("0 1e300 2 0 0 0 0 1\n", "t.tum"); }), "beyond"));
  EXPECT_NO_THROW((void)parse_tum("\xEF\xBB\xBF" "0 1 2 0 0 0 0 1\n", "t.tum"));
}

// The R-tree against a scan over every box, on random boxes: the same ids, ascending.
TEST(BoxIndex, QueriesEqualABruteForceScan) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(0.0, 100.0), size(0.0, 5.0);
  std::vector<IndexBox> boxes(3000);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    IndexBox& b = boxes[i];
    b.xmin = pos(rng);
    b.ymin = pos(rng);
    b.xmax = b.xmin + size(rng);
    b.ymax = b.ymin + (i % 7 == 0 ? 0.0 : size(rng));  // some degenerate (axis-parallel segments)
  }
  boxes[5] = {1.0, 1.0, 1.0, 1.0};  // a point
  const BoxIndex index(boxes);
  EXPECT_EQ(index.size(), boxes.size());
  for (int q = 0; q < 300; ++q) {
    const IndexBox query{pos(rng), pos(rng), 0.0, 0.0};
    const IndexBox qb{query.xmin, query.ymin, query.xmin + size(rng) * 2.0, query.ymin + size(rng) * 2.0};
    std::vector<std::uint32_t> want;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const IndexBox& b = boxes[i];
      if (b.xmin <= qb.xmax && b.xmax >= qb.xmin && b.ymin <= qb.ymax && b.ymax >= qb.ymin) want.push_back(static_cast<std::uint32_t>(i));
    }
    EXPECT_EQ(index.query(qb), want);
  }
  // Touching counts; NaN finds nothing.
  EXPECT_EQ(index.query({0.0, 0.0, 1.0, 1.0}).front(), 5u);
  EXPECT_TRUE(index.query({std::nan(""), 0.0, 1.0, 1.0}).empty());
}

}  // namespace
}  // namespace floorcast
