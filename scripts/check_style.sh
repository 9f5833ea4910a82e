#!/usr/bin/env bash
# The style checks of the README's Standards, run by ctest (test `style`):
#   - every C++ and OpenCL source is formatted by .clang-format (clang-format 14, Debian 12's);
#     fix with: git ls-files '*.cpp' '*.h' '*.cl' '*.clh' | xargs clang-format -i
#   - every shell script passes shellcheck.
# Lists what fails and exits non-zero.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
for tool in clang-format shellcheck; do
  if ! command -v "$tool" >/dev/null; then
    echo "check_style.sh: $tool is not installed (scripts/install-deps.sh installs it)" >&2
    exit 1
  fi
done

# Tracked files matching the patterns; outside a git checkout (an unpacked archive), every such
# file of the tree but the build folder.
list_files() {
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    git ls-files -z "$@"
  else
    local pattern names=()
    for pattern in "$@"; do names+=(-o -name "$pattern"); done
    find . -path ./build -prune -o -type f \( "${names[@]:1}" \) -print0
  fi
}

failed=0
unformatted=()
sources=0
while IFS= read -r -d '' file; do
  sources=$((sources + 1))
  clang-format --dry-run --Werror "$file" >/dev/null 2>&1 || unformatted+=("$file")
done < <(list_files '*.cpp' '*.h' '*.cl' '*.clh')
if [ ${#unformatted[@]} -gt 0 ]; then
  echo "not formatted by .clang-format (run clang-format -i on them):" >&2
  printf '  %s\n' "${unformatted[@]}" >&2
  failed=1
fi

scripts=()
while IFS= read -r -d '' file; do scripts+=("$file"); done < <(list_files '*.sh')
[ -f .ci/run ] && scripts+=(.ci/run)
if ! shellcheck "${scripts[@]}"; then
  failed=1
fi

[ "$failed" -eq 0 ] || exit 1
echo "check_style.sh: $sources sources formatted, ${#scripts[@]} shell scripts pass shellcheck"
