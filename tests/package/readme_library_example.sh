#!/usr/bin/env bash
# The README's "Using the library" is what a user of the installed package writes: this installs
# the build into a temporary prefix, makes a project of the section's CMake lines and of its C++
# snippets (the #include lines first, the rest as the body of main, in order), builds it against
# the package with find_package(rvor) and runs it. Fails when the package does not configure or
# link, or when the README's code no longer compiles or throws.
# Usage: readme_library_example.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
source_dir=$1
build_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --install "$build_dir" --prefix "$work/prefix" >/dev/null

# The fenced blocks of the section, by language.
section() {
  awk '/^## Using the library/ {on = 1; next} /^## / {on = 0} on' "$source_dir/README.md"
}
blocks() {
  section | awk -v lang="$1" '
    $0 == "```" lang {inside = 1; next}
    /^```/ {inside = 0; next}
    inside'
}

mkdir -p "$work/app"
{
  echo "cmake_minimum_required(VERSION 3.16)"
  echo "project(readme_example CXX)"
  echo "add_executable(app main.cpp)"
} >"$work/app/CMakeLists.txt"
blocks cmake >>"$work/app/CMakeLists.txt"
{
  blocks cpp | grep '^#include'
  echo "int main() {"
  blocks cpp | grep -v '^#include'
  echo "  return 0;"
  echo "}"
} >"$work/app/main.cpp"

if ! grep -q 'find_package(rvor' "$work/app/CMakeLists.txt" || ! grep -q 'rvor::' "$work/app/main.cpp"; then
  echo "readme_library_example.sh: no CMake or C++ code found under '## Using the library'" >&2
  exit 1
fi

# No C++ standard in the project, as the README has none; C++14 stands for a compiler whose default
# it is (clang 14): the package itself must ask for the C++17 its headers need.
cmake -S "$work/app" -B "$work/app/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_STANDARD=14 >"$work/configure.log" 2>&1 ||
  { cat "$work/configure.log" >&2; exit 1; }
cmake --build "$work/app/build" >"$work/build.log" 2>&1 ||
  { cat "$work/app/main.cpp" "$work/build.log" >&2; exit 1; }
"$work/app/build/app"
echo "readme_library_example.sh: the README's library code builds against the installed package and runs"
