#pragma once
// Device buffers in host memory backed by transparent huge pages, for devices that share the
// host's memory (PoCL on the CPU) (internal). The kernels read the per-voxel arrays (hundreds of
// MB at 256^3) at scattered bricks; with 4 KiB pages nearly every brick a relaxation touches is
// another TLB entry. Measured in docs/scheme.md ("Memory").
#include <cstddef>

#include "opencl_runtime.h"

namespace rvor::opencl {

// Whether buffers of the context's device live in host memory (a CPU device).
bool device_uses_host_memory(const cl::Context& context);

// A buffer of `size` bytes (flags: CL_MEM_READ_ONLY or CL_MEM_READ_WRITE) on pages allocated
// here, 2 MiB aligned and advised for huge pages (its whole 2 MiB ranges get them), holding a copy
// of `initial` when given (else zeros); the pages are released with the buffer. Throws rvor::Error
// when the memory cannot be had.
cl::Buffer huge_page_buffer(const cl::Context& context, cl_mem_flags flags, std::size_t size,
                            const void* initial);

}  // namespace rvor::opencl
