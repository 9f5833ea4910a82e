#include "rvor/input_file.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <utility>

#include "rvor/error.h"

namespace rvor {

namespace {

std::function<void(const std::string&, const std::string&)>& fifo_wait_notice() {
  static std::function<void(const std::string&, const std::string&)> notice;
  return notice;
}

// Reads a descriptor the buffer owns. A failed read throws std::ios_base::failure with errno
// kept, as std::filebuf does (read_input_line reports it, naming the file).
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int fd) : fd_(fd) {}
  DescriptorBuffer(const DescriptorBuffer&) = delete;
  DescriptorBuffer& operator=(const DescriptorBuffer&) = delete;
  ~DescriptorBuffer() override { close(fd_); }

 protected:
  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    ssize_t got = 0;
    do got = read(fd_, data_, sizeof data_);
    while (got < 0 && errno == EINTR);
    if (got < 0) {
      const int error = errno;
      std::ios_base::failure failure("read failed",
                                     std::error_code(error, std::generic_category()));
      errno = error;
      throw failure;
    }
    if (got == 0) return traits_type::eof();
    setg(data_, data_, data_ + got);
    return traits_type::to_int_type(*gptr());
  }

 private:
  int fd_;
  char data_[1 << 16];
};

// A FIFO opened without blocking: a named one with no writer would block the open, silently,
// until one appears. Where nothing is there to read yet, the notice is given and the wait is for
// the first data or for a writer's close (poll reports neither before a writer came: a read would
// see the end of the file at once); then reads block as usual and end where the last writer
// closes.
std::unique_ptr<std::streambuf> open_fifo(const std::string& path, const std::string& what) {
  const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw Error("cannot read " + what + " " + path + ": " + std::strerror(errno));
  auto buffer = std::make_unique<DescriptorBuffer>(fd);
  pollfd ready{fd, POLLIN, 0};
  // A writer that was blocked in its open wakes with this one and writes within the grace: no
  // notice for it.
  constexpr int kGraceMilliseconds = 200;
  if (poll(&ready, 1, kGraceMilliseconds) == 0) {
    if (fifo_wait_notice()) fifo_wait_notice()(what, path);
    while (poll(&ready, 1, -1) < 0 && errno == EINTR) {
    }
  }
  const int flags = fcntl(fd, F_GETFL);
  if (flags < 0 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) < 0)
    throw Error("cannot read " + what + " " + path + ": " + std::strerror(errno));
  return buffer;
}

}  // namespace

InputFile::InputFile(std::unique_ptr<std::streambuf> buffer)
    : std::istream(buffer.get()), buffer_(std::move(buffer)) {}

InputFile::InputFile(InputFile&& other) noexcept
    : std::istream(std::move(other)), buffer_(std::move(other.buffer_)) {
  set_rdbuf(buffer_.get());
}

void set_fifo_wait_notice(
    std::function<void(const std::string& what, const std::string& path)> notice) {
  fifo_wait_notice() = std::move(notice);
}

InputFile open_input_file(const std::string& path, const std::string& what) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw Error("cannot read " + what + " " + path + ": it is a directory");
  struct stat status {};
  if (stat(path.c_str(), &status) == 0 && S_ISFIFO(status.st_mode))
    return InputFile(open_fifo(path, what));
  auto buffer = std::make_unique<std::filebuf>();
  if (!buffer->open(path, std::ios::in | std::ios::binary))
    throw Error("cannot read " + what + " " + path + ": " + std::strerror(errno));
  return InputFile(std::move(buffer));
}

InputFile open_regular_input_file(const std::string& path, const std::string& what,
                                  const std::string& why) {
  std::error_code error;
  const std::filesystem::file_type type = std::filesystem::status(path, error).type();
  if (!error && type != std::filesystem::file_type::regular &&
      type != std::filesystem::file_type::directory)  // open_input_file names a directory
    throw Error("cannot read " + what + " " + path + ": not a regular file (" +
                (type == std::filesystem::file_type::fifo ? "a pipe" : "a device or special file") +
                ": " + why + "; save it to a file first)");
  return open_input_file(path, what);
}

std::size_t byte_order_mark_length(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
}

namespace {

// The file buffer throws where the system's read fails (EIO, or /proc/self/mem), with a message
// that names no file.
// `peek`: the byte is left to be read next.
int next_byte(std::streambuf& buffer, const std::string& path, long number, bool peek = false) {
  try {
    return peek ? buffer.sgetc() : buffer.sbumpc();
  } catch (const std::ios_base::failure& failure) {
    throw Error("cannot read " + path + " at line " + std::to_string(number) + ": " +
                (errno != 0 ? std::strerror(errno) : failure.what()));
  }
}

// read_input_line without the byte order mark's removal.
bool read_raw_line(std::istream& in, std::string& line, const std::string& path, long number) {
  line.clear();
  errno = 0;  // next_byte's message reads it: only a failed read sets it in the loop
  std::streambuf* buffer = in.rdbuf();
  for (;;) {
    const int c = next_byte(*buffer, path, number);
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return !line.empty();
    }
    if (c == '\n') return true;
    if (c == '\r') {  // CRLF, or CR alone: the line ends of classic Mac OS files
      if (next_byte(*buffer, path, number, true) == '\n') buffer->sbumpc();
      return true;
    }
    if (line.size() == kMaxInputLineBytes)
      throw Error(path + ":" + std::to_string(number) + ": a line longer than " +
                  std::to_string(kMaxInputLineBytes >> 20) +
                  " MiB (a binary file, or not the file meant?)");
    line.push_back(static_cast<char>(c));
  }
}

}  // namespace

bool read_input_line(std::istream& in, std::string& line, const std::string& path, long number) {
  if (!read_raw_line(in, line, path, number)) return false;
  // Kept, a byte order mark made the OBJ reader skip the first line and the OFF reader miss its
  // header.
  if (number == 1) line.erase(0, byte_order_mark_length(line));
  return true;
}

}  // namespace rvor
