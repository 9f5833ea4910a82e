// Publishing output files: publish_new never replaces a file that appeared at the target.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "rvor/atomic_file.h"
#include "rvor/error.h"
#include "support/temp_dir.h"

namespace rvor {
namespace {

std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Two runs writing into one output directory: the one that publishes second must not replace
// the first one's file (its "already exists" check was made long before).
TEST(AtomicFile, PublishNewLeavesAFileThatAppearedMeanwhile) {
  test::TempDir dir;
  const std::string target = dir.file("report.json");
  write_file_atomically(target, [](std::ostream& out) { out << "first run\n"; });
  const std::string staged = temporary_path_for(target);
  std::ofstream(staged) << "second run\n";
  try {
    publish_new(staged, target);
    FAIL() << "publish_new replaced an existing file";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("it appeared while rvor was writing"),
              std::string::npos)
        << error.what();
  }
  EXPECT_EQ(text_of(target), "first run\n");
  EXPECT_FALSE(std::filesystem::exists(staged));

  const std::string fresh = dir.file("seeds.xyz");
  const std::string staged_fresh = temporary_path_for(fresh);
  std::ofstream(staged_fresh) << "0 0\n";
  publish_new(staged_fresh, fresh);
  EXPECT_EQ(text_of(fresh), "0 0\n");
  EXPECT_FALSE(std::filesystem::exists(staged_fresh));
}

}  // namespace
}  // namespace rvor
