#pragma once
// Opening a file the user named for reading, with one message for every reader: what the file is
// for, its path, and why it cannot be read (missing, unreadable, a directory); and reading its
// lines with a bound on their length.
#include <cstddef>
#include <fstream>
#include <string>

namespace rvor {

// `what` names the file's role, e.g. "mesh file" or "point file". Throws rvor::Error
// "cannot read WHAT PATH: REASON".
std::ifstream open_input_file(const std::string& path, const std::string& what);

// The longest line the text readers accept. Their lines hold a few numbers; without a bound a
// file with no line ends (a binary file, /dev/zero) would be read whole into memory first.
inline constexpr std::size_t kMaxInputLineBytes = std::size_t{1} << 20;

// std::getline for the text readers: the next line of `in` without its line end, which is "\n",
// "\r\n" or a lone "\r" (false at the end of the input). Throws rvor::Error "PATH:NUMBER: ..." for
// a line longer than kMaxInputLineBytes, `number` being that line's number.
bool read_input_line(std::istream& in, std::string& line, const std::string& path, long number);

}  // namespace rvor
