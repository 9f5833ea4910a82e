// read_input_line, the line reader of the seed and surface-mesh files: its line ends.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "rvor/input_file.h"

namespace rvor {
namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  std::string line;
  for (long number = 1; read_input_line(in, line, "text", number); ++number) lines.push_back(line);
  return lines;
}

// LF, CRLF and a lone CR (classic Mac OS files, once read as one line) each end a line, in any
// mix; "\r\r\n" is a line and an empty one; a last line needs no end.
TEST(InputLines, EndAtLfCrlfOrALoneCr) {
  const std::vector<std::string> two{"0.1 0.2", "0.3 0.4"};
  EXPECT_EQ(lines_of("0.1 0.2\n0.3 0.4\n"), two);
  EXPECT_EQ(lines_of("0.1 0.2\r\n0.3 0.4\r\n"), two);
  EXPECT_EQ(lines_of("0.1 0.2\r0.3 0.4\r"), two);
  EXPECT_EQ(lines_of("0.1 0.2\r0.3 0.4"), two);
  EXPECT_EQ(lines_of("a\r\r\nb\n\rc"), (std::vector<std::string>{"a", "", "b", "", "c"}));
  EXPECT_EQ(lines_of("\r"), std::vector<std::string>{""});
  EXPECT_TRUE(lines_of("").empty());
}

}  // namespace
}  // namespace rvor
