#include "host_pages.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>

#include "rvor/error.h"

namespace rvor::opencl {

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;

// Whole small pages: the kernel backs the mapping's whole 2 MiB ranges with huge pages and the
// tail with small ones, so nothing is reserved beyond the last small page.
std::size_t mapped_length(std::size_t size) {
  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  return (size + page - 1) / page * page;
}

}  // namespace

void* map_huge_pages(std::size_t size) noexcept {
  const std::size_t length = mapped_length(size);
  // Over-allocate by a huge page so that the block can start on a 2 MiB boundary.
  const std::size_t mapped = length + kHugePage;
  void* region = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (region == MAP_FAILED) return nullptr;
  const auto start = reinterpret_cast<std::uintptr_t>(region);
  const std::uintptr_t aligned = (start + kHugePage - 1) / kHugePage * kHugePage;
  if (aligned > start) munmap(region, aligned - start);
  if (const std::size_t tail = start + mapped - (aligned + length); tail > 0)
    munmap(reinterpret_cast<void*>(aligned + length), tail);
  void* address = reinterpret_cast<void*>(aligned);
  madvise(address, length, MADV_HUGEPAGE);  // a hint: without it, 4 KiB pages
  return address;
}

void unmap_huge_pages(void* address, std::size_t size) noexcept {
  munmap(address, mapped_length(size));
}

bool device_uses_host_memory(const cl::Context& context) {
  const auto devices = context.getInfo<CL_CONTEXT_DEVICES>();
  return !devices.empty() && (devices.front().getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU);
}

cl::Buffer huge_page_buffer(const cl::Context& context, cl_mem_flags flags, std::size_t size,
                            const void* initial) {
  HugePageVector<unsigned char> bytes;
  try {
    bytes.resize(size);  // zeros, left to the device's first writes to touch
  } catch (const std::bad_alloc&) {
    throw Error("cannot allocate " + std::to_string(size) + " bytes of host memory for a device " +
                "buffer: " + std::strerror(errno));
  }
  if (initial != nullptr) std::memcpy(bytes.data(), initial, size);
  return adopting_buffer(context, flags, std::move(bytes));
}

}  // namespace rvor::opencl
