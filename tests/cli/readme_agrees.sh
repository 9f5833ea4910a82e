#!/usr/bin/env bash
# The README's "Using the tool" against the tool: every default that `rvor voronoi --help` shows
# (OPTION TYPE=DEFAULT) is the one the README's option table gives on that option's row.
# Usage: readme_agrees.sh RVOR README.md
set -euo pipefail
rvor=$1
readme=$2
failed=0

# The table rows of "Using the tool" that name an option.
option_rows() {
  awk '/^## Using the tool/ {on = 1; next} /^## / {on = 0} on && /^\| `--/' "$readme"
}

# --help's defaults, as the user sees them without $RVOR_DEVICE.
while read -r option value; do
  row=$(option_rows | grep -F -- "\`$option" || true)
  if [ -z "$row" ]; then
    echo "README: no row of the option table names $option" >&2
    failed=1
  elif ! grep -qE -- "default[^|]*\`?${value//./\\.}\`?([^a-z0-9_-]|$)" <<<"$row"; then
    echo "README: the row of $option does not give its default $value (rvor voronoi --help)" >&2
    failed=1
  fi
done < <(env -u RVOR_DEVICE "$rvor" voronoi --help |
  sed -nE 's/^  (--[a-z-]+) [A-Z]+(:[A-Z]+)?=([^ ]+).*/\1 \3/p')

[ "$failed" -eq 0 ] && echo "readme_agrees.sh: the README agrees with the tool"
exit "$failed"
