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

struct Pages {
  void* address;
  std::size_t size;
};

void CL_CALLBACK release_pages(cl_mem, void* user_data) {
  const auto* pages = static_cast<Pages*>(user_data);
  unmap_huge_pages(pages->address, pages->size);
  delete pages;
}

}  // namespace

void* map_huge_pages(std::size_t size) {
  const std::size_t length = mapped_length(size);
  // Over-allocate by a huge page so that the block can start on a 2 MiB boundary.
  const std::size_t mapped = length + kHugePage;
  void* region = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (region == MAP_FAILED)
    throw Error("cannot allocate " + std::to_string(size) + " bytes of host memory for a device " +
                "buffer: " + std::strerror(errno));
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
  auto* pages = new Pages{map_huge_pages(size), size};
  if (initial != nullptr) std::memcpy(pages->address, initial, size);
  try {
    cl::Buffer buffer(context, flags | CL_MEM_USE_HOST_PTR, size, pages->address);
    const cl_int status = clSetMemObjectDestructorCallback(buffer(), release_pages, pages);
    if (status != CL_SUCCESS) throw cl::Error(status, "clSetMemObjectDestructorCallback");
    return buffer;
  } catch (...) {
    unmap_huge_pages(pages->address, pages->size);
    delete pages;
    throw;
  }
}

}  // namespace rvor::opencl
