// Reproduces docs/scheme.md's first-touch figures ("Faster first solves"): how long the first
// write to 470 MB of fresh anonymous memory takes with and without madvise(MADV_HUGEPAGE) (the
// advice rvor gives its device buffers on PoCL, host/src/opencl/host_pages.cpp), and a copy onto
// memory already touched. Build and run (run it twice: on a virtual machine the first run also
// pays for the host backing the memory):
//   c++ -O2 -std=c++17 docs/measurements/huge_page_first_touch.cpp -o /tmp/first_touch
//   /tmp/first_touch          # with the advice
//   /tmp/first_touch small    # without it
#include <sys/mman.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

namespace {

constexpr std::size_t kBytes = std::size_t{470} << 20, kHugePage = std::size_t{2} << 20;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Fresh pages, 2 MiB aligned, advised for huge pages unless `small`.
char* fresh_pages(bool small) {
  void* region =
      mmap(nullptr, kBytes + kHugePage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (region == MAP_FAILED) return nullptr;
  const auto start = reinterpret_cast<std::uintptr_t>(region);
  char* aligned = reinterpret_cast<char*>((start + kHugePage - 1) / kHugePage * kHugePage);
  if (!small) madvise(aligned, kBytes, MADV_HUGEPAGE);
  return aligned;
}

}  // namespace

int main(int argc, char**) {
  const bool small = argc > 1;
  const std::vector<char> source(kBytes, 1);
  char* touched = fresh_pages(small);
  char* copied = fresh_pages(small);
  if (touched == nullptr || copied == nullptr) return 1;
  auto start = std::chrono::steady_clock::now();
  std::memset(touched, 0, kBytes);
  const double first_touch = seconds_since(start);
  start = std::chrono::steady_clock::now();
  std::memcpy(touched, source.data(), kBytes);
  const double copy_onto_touched = seconds_since(start);
  start = std::chrono::steady_clock::now();
  std::memcpy(copied, source.data(), kBytes);
  const double copy_onto_fresh = seconds_since(start);
  std::printf("%s pages: first touch %.3f s, copy onto touched %.3f s, copy onto fresh %.3f s\n",
              small ? "small" : "huge", first_touch, copy_onto_touched, copy_onto_fresh);
  return 0;
}
