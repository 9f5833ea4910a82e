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

struct Pages {
  void* address;
  std::size_t length;
};

void CL_CALLBACK release_pages(cl_mem, void* user_data) {
  const auto* pages = static_cast<Pages*>(user_data);
  munmap(pages->address, pages->length);
  delete pages;
}

}  // namespace

bool device_uses_host_memory(const cl::Context& context) {
  const auto devices = context.getInfo<CL_CONTEXT_DEVICES>();
  return !devices.empty() && (devices.front().getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU);
}

cl::Buffer huge_page_buffer(const cl::Context& context, cl_mem_flags flags, std::size_t size,
                            const void* initial) {
  // Whole small pages: the kernel backs the buffer's whole 2 MiB ranges with huge pages and the
  // tail with small ones, so nothing is reserved beyond the buffer's last small page.
  const std::size_t page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  const std::size_t length = (size + page - 1) / page * page;
  // Over-allocate by a huge page so that the buffer can start on a 2 MiB boundary.
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
  auto* pages = new Pages{reinterpret_cast<void*>(aligned), length};
  madvise(pages->address, length, MADV_HUGEPAGE);  // a hint: without it, 4 KiB pages
  if (initial != nullptr) std::memcpy(pages->address, initial, size);
  try {
    cl::Buffer buffer(context, flags | CL_MEM_USE_HOST_PTR, size, pages->address);
    const cl_int status = clSetMemObjectDestructorCallback(buffer(), release_pages, pages);
    if (status != CL_SUCCESS) throw cl::Error(status, "clSetMemObjectDestructorCallback");
    return buffer;
  } catch (...) {
    munmap(pages->address, pages->length);
    delete pages;
    throw;
  }
}

}  // namespace rvor::opencl
