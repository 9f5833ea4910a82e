#!/usr/bin/env bash
# The README's "Using the tool" against the tool: every default that `rvor voronoi --help` shows
# (OPTION TYPE=DEFAULT) is the one the README's option table gives on that option's row; and its
# "Layout" names every top-level folder of the source tree; and the first example of its "Using
# the tool" block runs as written (build/bin/rvor being RVOR), in a fresh directory; and its table
# of report.json's keys names exactly those a run writes, and each .vtu's arrays are named where
# the README describes that file.
# Usage: readme_agrees.sh RVOR README.md
set -euo pipefail
rvor=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")  # absolute: the example runs elsewhere
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

# The tree's top-level folders (not hidden ones, nor the build's or a run's outputs, which
# .gitignore keeps out: tracked files only where this is a git checkout).
source_dir=$(dirname "$readme")
if git -C "$source_dir" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  folders=$(git -C "$source_dir" ls-files | sed -n 's|^\([^./][^/]*\)/.*|\1|p' | sort -u)
else
  folders=$(find "$source_dir" -mindepth 1 -maxdepth 1 -type d ! -name '.*' ! -name 'build*' \
    ! -name 'rvor-out*' ! -name 'out*' -printf '%f\n' | sort)
fi
layout=$(awk '/^## Layout/ {on = 1; next} /^## / {on = 0} on' "$readme")
for folder in $folders; do
  if ! grep -qF -- "| \`$folder/\` |" <<<"$layout"; then
    echo "README: \"Layout\" does not name the folder $folder/" >&2
    failed=1
  fi
done

# The first example: the lines of the sh block up to its first blank line, on the CPU reference
# (what is checked is the command line and its files; it runs where no OpenCL device is).
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
awk '/^## Using the tool/ {on = 1; next} /^## / {if (on) done = 1; on = 0}
  on && !done && $0 == "```sh" {inside = 1; next}
  inside && /^$/ {inside = 0; done = 1}
  inside' "$readme" |
  sed "s|build/bin/rvor|\"\$RVOR\"|g" >"$work/example.sh"
if ! (cd "$work" && RVOR=$rvor RVOR_DEVICE=cpu bash -e example.sh >log 2>&1 && [ -s out/uniform/probe.csv ]); then
  echo "README: the first example of \"Using the tool\" fails as written:" >&2
  cat "$work/example.sh" "$work/log" >&2
  failed=1
fi

# report.json against the README's table of its keys: a run with every optional part (probes, both
# duals, a metric mesh) writes exactly the keys the table names. A row's first cell lists keys,
# the later ones relative to the first one's parent ("`timings.canvas`, `total`").
cat >"$work/m.mesh" <<'MESH'
MeshVersionFormatted 2
Dimension 3
Vertices
4
0 0 0 0
2 0 0 0
0 2 0 0
0 0 2 0
Tetrahedra
1
1 2 3 4 0
End
MESH
cat >"$work/m.sol" <<'SOL'
MeshVersionFormatted 2
Dimension 3
SolAtVertices
4
1 3
4 0 1 0 0 1
1 0 1 0 0 1
1 0 4 0 0 1
1 0 1 0 0 4
End
SOL
printf '0.5 0.5 0.5\n5 5 5\n' >"$work/probes.xyz"
if ! (cd "$work" && RVOR_DEVICE=cpu "$rvor" voronoi --quiet --domain box:0,0,0,1,1,1 \
  --metric-mesh m.mesh --metric-file m.sol --resolution 12 --random-seeds 12 --dual both \
  --probe probes.xyz --vtu --out keys >log 2>&1); then
  echo "README: the report.json run failed:" >&2
  cat "$work/log" >&2
  failed=1
elif ! /usr/bin/python3 - "$readme" "$work/keys/report.json" <<'PY'; then
import json, os, re, sys

readme, report = open(sys.argv[1]).read(), json.load(open(sys.argv[2]))
if "`report.json`, key by key" not in readme:
    sys.exit("README: no table of report.json's keys (\"`report.json`, key by key\")")
section = readme.split("`report.json`, key by key", 1)[1].split("\n\n| key |", 1)[1]
documented = set()
for row in re.findall(r"^\| (`[^|]*`) \|", section.split("\n\n", 1)[0], re.M):
    names = re.findall(r"`([^`]+)`", row)
    parent = names[0].rpartition(".")[0]
    documented |= {names[0]} | {(parent + "." if parent else "") + n for n in names[1:]}


def leaves(value, prefix=""):
    for key, inner in value.items():
        if isinstance(inner, dict):
            yield from leaves(inner, prefix + key + ".")
        else:
            yield prefix + key


written = set(leaves(report))
for key in sorted(written - documented):
    print(f"README: report.json's key {key} is not in its table", file=sys.stderr)
for key in sorted(documented - written):
    print(f"README: the report.json table names {key}, which the run did not write", file=sys.stderr)
# Each .vtu's arrays, named in the README's paragraph that describes that file ("`dual.vtu`: ...").
undescribed = []
paragraphs = readme.split("\n\n")
for name in report["outputs"]:
    if not name.endswith(".vtu"):
        continue
    header = open(os.path.join(os.path.dirname(sys.argv[2]), name), "rb").read(1 << 16)
    header = header.split(b"<AppendedData", 1)[0].decode()
    arrays = set(re.findall(r'Name="([^"]+)"', header)) - {"connectivity", "offsets", "types"}
    text = " ".join(p for p in paragraphs if f"`{name}`:" in p)
    undescribed += [f"{name}'s array {a}" for a in sorted(arrays) if f"`{a}`" not in text]
for what in undescribed:
    print(f"README: no paragraph describing its file names {what}", file=sys.stderr)
sys.exit(written != documented or bool(undescribed))
PY
  failed=1
fi

[ "$failed" -eq 0 ] && echo "readme_agrees.sh: the README agrees with the tool"
exit "$failed"
