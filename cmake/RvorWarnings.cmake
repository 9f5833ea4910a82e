# Warnings are errors in project code; third-party headers come in as SYSTEM includes.
function(rvor_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Werror
                         -Wno-error=deprecated-declarations)
endfunction()

# Declares one component library of rvor with its sources.
function(rvor_component name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_include_directories(${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/host/include>
    $<INSTALL_INTERFACE:include>)
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
  # The public headers are C++17 (std::optional, inline variables): a project that links the
  # installed package gets C++17 whatever its compiler's default (clang 14's is C++14).
  target_compile_features(${name} PUBLIC cxx_std_17)
  rvor_set_warnings(${name})
endfunction()
