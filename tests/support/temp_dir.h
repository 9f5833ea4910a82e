#pragma once
// A fresh directory under the system temp dir, removed with its contents at scope exit.
#include <string>

namespace rvor::test {

class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// Writes text to a file (test inputs).
void write_text(const std::string& path, const std::string& text);
std::string read_text(const std::string& path);

}  // namespace rvor::test
