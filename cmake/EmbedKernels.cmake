# Embeds OpenCL C sources into a static library, so nothing has to be found at run time.
# The generated function rvor::embedded_kernel_source(name) returns a file's text by file name.
set(RVOR_EMBED_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/embed_kernels_script.cmake")

function(rvor_embed_kernels target)
  set(generated "${CMAKE_CURRENT_BINARY_DIR}/embedded_kernels.cpp")
  add_custom_command(
    OUTPUT "${generated}"
    COMMAND ${CMAKE_COMMAND} "-DOUTPUT=${generated}" "-DSOURCES=${ARGN}" -P "${RVOR_EMBED_SCRIPT}"
    DEPENDS ${ARGN} "${RVOR_EMBED_SCRIPT}"
    COMMENT "Embedding OpenCL kernels"
    VERBATIM)
  add_library(${target} STATIC "${generated}")
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/host/include>)
endfunction()
