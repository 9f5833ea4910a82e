// Publishing output files: link_new never replaces a file that appeared at the target; the
// temporaries' names give back their process.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "rvor/atomic_file.h"
#include "rvor/error.h"
#include "rvor/seeds.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

namespace rvor {
namespace {

// A FIFO (or a device: as root, /dev/full became a regular file) at an output's path is not
// replaced: an error names it, and it stays what it was.
TEST(AtomicFile, ADeviceOrFifoAtThePathIsNeverReplaced) {
  test::TempDir dir;
  const std::string fifo = dir.file("seeds.xyz");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string message = test::error_of([&] { write_xyz(fifo, {Vec3(0, 0, 0)}, 3); });
  EXPECT_NE(message.find("cannot write " + fifo + ": it is a FIFO"), std::string::npos) << message;
  const std::string staged = temporary_path_for(fifo);
  std::ofstream(staged) << "staged\n";
  EXPECT_NE(test::error_of([&] { publish_temporary(staged, fifo); }).find("it is a FIFO"),
            std::string::npos);
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  EXPECT_FALSE(std::filesystem::exists(staged));
}

// Two runs writing into one output directory: the one that publishes second must not replace
// the first one's file (its "already exists" check was made long before).
TEST(AtomicFile, LinkNewLeavesAFileThatAppearedMeanwhile) {
  test::TempDir dir;
  const std::string target = dir.file("report.json");
  write_file_atomically(target, [](std::ostream& out) { out << "first run\n"; });
  const std::string staged = temporary_path_for(target);
  std::ofstream(staged) << "second run\n";
  try {
    link_new(staged, target);
    FAIL() << "link_new replaced an existing file";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("it appeared while rvor was writing"),
              std::string::npos)
        << error.what();
  }
  EXPECT_EQ(test::read_text(target), "first run\n");
  EXPECT_EQ(test::read_text(staged), "second run\n");  // the caller's, to remove or retry

  const std::string fresh = dir.file("seeds.xyz");
  link_new(staged, fresh);
  EXPECT_EQ(test::read_text(fresh), "second run\n");
  EXPECT_TRUE(std::filesystem::exists(staged));  // a hard link here: the staged name stays
}

// A killed run's temporaries are told from a live run's by the process id in their names: the
// cleanup of `rvor voronoi --out` parses what temporary_path_for built.
// A write that cannot be published says why where that is plain ("rename from temporary file
// failed" was all it said), and leaves no temporary behind.
TEST(AtomicFile, APathThatCannotTakeTheFileSaysWhy) {
  test::TempDir dir;
  const auto message_of = [](const std::string& path) {
    return test::error_of(
        [&] { write_file_atomically(path, [](std::ostream& out) { out << "x"; }); });
  };
  std::filesystem::create_directory(dir.file("taken"));
  EXPECT_EQ(message_of(dir.file("taken")),
            "cannot write " + dir.file("taken") + ": it is a directory");
  EXPECT_NE(message_of("").find("cannot write '': "), std::string::npos);
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path()))
    ++entries;
  EXPECT_EQ(entries, 1u);  // the directory alone
}

// write_xyz writes only what read_xyz reads back (a NaN point was written, then refused).
TEST(AtomicFile, PointFilesHoldOnlyFinitePoints) {
  test::TempDir dir;
  EXPECT_THROW(write_xyz(dir.file("p.xyz"), {Vec3(0, 0, 0), Vec3(std::nan(""), 1, 2)}, 3), Error);
  EXPECT_FALSE(std::filesystem::exists(dir.file("p.xyz")));
  // z is not written in 2D, so it need not be finite there.
  write_xyz(dir.file("q.xyz"), {Vec3(0.5, 1, std::nan(""))}, 2);
  EXPECT_EQ(read_xyz(dir.file("q.xyz"), 2).front(), Vec3(0.5, 1, 0));
}

TEST(AtomicFile, TemporaryNamesGiveBackTheirProcess) {
  const std::string name =
      std::filesystem::path(temporary_path_for("/some/dir/outputs-host")).filename().string();
  EXPECT_EQ(temporary_owner(name, "outputs-host"), std::optional<long>(getpid())) << name;
  EXPECT_EQ(temporary_owner(name, "outputs-other"), std::nullopt);
  for (const std::string other :
       {".outputs-host.tmp-", ".outputs-host.tmp-12", ".outputs-host.tmp-12-",
        ".outputs-host.tmp--5", ".outputs-host.tmp-a1-5", ".outputs-host.tmp-12-5x",
        ".outputs-host.tmp-1234567890-5", "outputs-host.tmp-12-5"})
    EXPECT_EQ(temporary_owner(other, "outputs-host"), std::nullopt) << other;
  EXPECT_EQ(temporary_owner(".outputs-host.tmp-42-7", "outputs-host"), std::optional<long>(42));
}

}  // namespace
}  // namespace rvor
