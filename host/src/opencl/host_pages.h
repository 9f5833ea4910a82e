#pragma once
// Device buffers in host memory backed by transparent huge pages, for devices that share the
// host's memory (PoCL on the CPU) (internal). The kernels read the per-voxel arrays (hundreds of
// MB at 256^3) at scattered bricks; with 4 KiB pages nearly every brick a relaxation touches is
// another TLB entry. Measured in docs/scheme.md ("Memory").
#include <cstddef>
#include <cstring>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "opencl_runtime.h"

namespace rvor::opencl {

// Buffers from this size on live on huge pages where the device uses host memory.
constexpr std::size_t kHugePageBufferBytes = std::size_t{4} << 20;

// Whether buffers of the context's device live in host memory (a CPU device).
bool device_uses_host_memory(const cl::Context& context);

// `size` bytes of zeros, 2 MiB aligned and advised for huge pages before any is touched (their
// pages are first touched by whoever writes them); nullptr when the memory cannot be had.
// unmap_huge_pages(address, size) gives them back.
void* map_huge_pages(std::size_t size) noexcept;
void unmap_huge_pages(void* address, std::size_t size) noexcept;

// An allocator whose blocks of kHugePageBufferBytes and more are map_huge_pages's (smaller ones
// plain aligned new): a vector that will become a device buffer is filled on the pages the buffer
// keeps (adopting_buffer), with no second copy of it in memory. Its blocks come zeroed and
// resize() leaves new elements as the block holds them (default-initialised, not written), so a
// fresh vector sized by resize(n) is all zeros without a zeroing pass over its pages; beware that
// elements dropped by a shrink and exposed again by a resize keep their old values.
template <typename T>
struct HugePageAllocator {
  static_assert(std::is_trivially_copyable<T>::value, "blocks hold plain data");
  using value_type = T;
  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= kHugePageBufferBytes) {
      void* pages = map_huge_pages(bytes);
      if (pages == nullptr) throw std::bad_alloc();
      return static_cast<T*>(pages);
    }
    void* block = ::operator new (bytes, std::align_val_t{alignof(T)});
    std::memset(block, 0, bytes);  // as mapped pages are
    return static_cast<T*>(block);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= kHugePageBufferBytes)
      unmap_huge_pages(p, bytes);
    else
      ::operator delete (p, std::align_val_t{alignof(T)});
  }
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Arguments>
  void construct(U* p, Arguments&&... arguments) {
    ::new (static_cast<void*>(p)) U(std::forward<Arguments>(arguments)...);
  }
  template <typename U>
  bool operator==(const HugePageAllocator<U>&) const noexcept {
    return true;
  }
  template <typename U>
  bool operator!=(const HugePageAllocator<U>&) const noexcept {
    return false;
  }
};

template <typename T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

// A buffer of `size` bytes (flags: CL_MEM_READ_ONLY or CL_MEM_READ_WRITE) on pages allocated
// here, 2 MiB aligned and advised for huge pages (its whole 2 MiB ranges get them), holding a copy
// of `initial` when given (else zeros); the pages are released with the buffer. Throws rvor::Error
// when the memory cannot be had.
cl::Buffer huge_page_buffer(const cl::Context& context, cl_mem_flags flags, std::size_t size,
                            const void* initial);

// A buffer (for a device in host memory) on the memory of `data`, which it takes over: the vector
// lives until the buffer is released.
template <typename T>
cl::Buffer adopting_buffer(const cl::Context& context, cl_mem_flags flags,
                           HugePageVector<T>&& data) {
  auto* owner = new HugePageVector<T>(std::move(data));
  try {
    cl::Buffer buffer(context, flags | CL_MEM_USE_HOST_PTR, owner->size() * sizeof(T),
                      owner->data());
    const cl_int status = clSetMemObjectDestructorCallback(
        buffer(), [](cl_mem, void* vector) { delete static_cast<HugePageVector<T>*>(vector); },
        owner);
    if (status != CL_SUCCESS) throw cl::Error(status, "clSetMemObjectDestructorCallback");
    return buffer;
  } catch (...) {
    delete owner;
    throw;
  }
}

}  // namespace rvor::opencl
