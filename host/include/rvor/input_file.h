#pragma once
// Opening a file the user named for reading, with one message for every reader: what the file is
// for, its path, and why it cannot be read (missing, unreadable, a directory); and reading its
// lines with a bound on their length.
#include <cstddef>
#include <functional>
#include <istream>
#include <memory>
#include <streambuf>
#include <string>
#include <string_view>

namespace rvor {

// A file open for reading, as open_input_file opens it: a std::filebuf, or for a FIFO a buffer on
// the descriptor that open_input_file opened without blocking (a second, blocking open of the
// FIFO could wait forever for a writer that already came and went).
class InputFile : public std::istream {
 public:
  explicit InputFile(std::unique_ptr<std::streambuf> buffer);
  InputFile(InputFile&& other) noexcept;
  InputFile& operator=(InputFile&&) = delete;

 private:
  std::unique_ptr<std::streambuf> buffer_;
};

// `what` names the file's role, e.g. "mesh file" or "point file". Throws rvor::Error
// "cannot read WHAT PATH: REASON". A FIFO (a named pipe, or /dev/stdin on a pipe) that nothing
// has written to yet is waited on until a writer writes or closes it, after calling the notice
// set by set_fifo_wait_notice: its open no longer blocks unseen until a writer appears.
InputFile open_input_file(const std::string& path, const std::string& what);

// open_input_file for readers that seek or read a file more than once (VDB archives, STL, whose
// kind its size tells): a pipe or a device is refused, naming `why` they need a regular file,
// rather than failing at the first seek. Checked before opening, which would wait for a writer on a
// named pipe.
InputFile open_regular_input_file(const std::string& path, const std::string& what,
                                  const std::string& why);

// The bytes of a UTF-8 byte order mark at the start of `text` (some Windows editors write one
// before the first line): 3, or 0 where there is none.
std::size_t byte_order_mark_length(std::string_view text);

// What open_input_file calls, with the FIFO's role and path, before it waits on one: a tool says
// that it waits, rather than hang silently on a FIFO that nothing writes to. None by default.
void set_fifo_wait_notice(
    std::function<void(const std::string& what, const std::string& path)> notice);

// The longest line the text readers accept. Their lines hold a few numbers; without a bound a
// file with no line ends (a binary file, /dev/zero) would be read whole into memory first.
inline constexpr std::size_t kMaxInputLineBytes = std::size_t{1} << 20;

// std::getline for the text readers: the next line of `in` without its line end, which is "\n",
// "\r\n" or a lone "\r" (false at the end of the input); line 1 without a UTF-8 byte order mark.
// Throws rvor::Error "PATH:NUMBER: ..." for a line longer than kMaxInputLineBytes, `number` being
// that line's number.
bool read_input_line(std::istream& in, std::string& line, const std::string& path, long number);

}  // namespace rvor
