#!/usr/bin/env bash
# Before/after check for refactoring: runs every `terroir` command on the bundled Sagehen DEM
# with one binary and records what it writes, or compares two such records file by file.
#
#   Scripts/compare_cli_outputs.sh record DIR [TERROIR]   # TERROIR: default build/bin/terroir
#   Scripts/compare_cli_outputs.sh compare DIR_A DIR_B
#
# `record` needs an X display for the PNGs (it starts xvfb-run -a when DISPLAY is unset).
# `compare` requires byte-identical files, except the reports' timings: in .json files every
# key naming a time or a speed (seconds, milliseconds, per second) is dropped, and in .md/.txt
# files numbers followed by a unit of time are masked. It lists every file that differs, and
# exits 1 when one does (or when a file is only in one record).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

record() {
  local out="$1" bin="${2:-$here/build/bin/terroir}"
  [[ -x "$bin" ]] || { echo "compare_cli_outputs: $bin is not an executable" >&2; exit 2; }
  bin="$(realpath "$bin")" # the commands run inside $out
  if [[ -z "${DISPLAY:-}" && -z "${TERROIR_UNDER_XVFB:-}" ]]; then
    TERROIR_UNDER_XVFB=1 exec xvfb-run -a bash "$0" record "$@"
  fi
  rm -rf "$out"
  mkdir -p "$out"
  local dem="$here/Data/sagehen_creek_ca/sagehen_dem_utm11n_10m.tif"
  [[ -f "$dem" ]] || { echo "compare_cli_outputs: $dem is missing" >&2; exit 2; }
  local log="$out/commands.log"
  run() { # NAME ARGS...: stdout of the command kept as NAME.stdout
    local name="$1"
    shift
    echo "+ terroir $*" >>"$log"
    (cd "$out" && "$bin" "$@") >"$out/$name.stdout" 2>>"$log"
  }
  run run run "$dem" --out run
  run slope slope "$dem" slope.tif --aspect aspect.tif
  run temperature temperature "$dem" temperature.tif --coldest 1 --warmest 18
  run illumination illumination "$dem" illumination.vti --mode daily --date 2025-06-21 \
    --insolation insolation.tif
  run instant illumination "$dem" shade.tif --mode instant --date 2025-12-21 --time 15:30 \
    --utc-offset -8
  run infiltration infiltration "$dem" infiltration.tif --fill 15 --slope-rule 30
  run humidity humidity "$dem" humidity.tif --standing standing.tif
  run floodfill floodfill "$dem" lakes.tif --fill-depressions --ids lake_ids.tif
  run waterflow waterflow "$dem" waterflow.vti --water 50 --max-iterations 300
  run flowacc flowacc "$dem" flowacc.tif --method mfd
  run validate validate --json validate.json --png validate.png
  run kmeans kmeans "$dem" zones.tif -k 4 --csv zones.csv
  run info info "$dem"
  run fractal fractal fractal.tif --size 128 --seed 3
  echo "recorded $(find "$out" -type f | wc -l) files in $out"
}

compare() {
  /usr/bin/python3 - "$1" "$2" <<'EOF'
import json, os, re, sys

a_dir, b_dir = sys.argv[1], sys.argv[2]
TIMING_KEY = re.compile(r"(second|_s$|_ms$|^ms$|millisecond|per_s|per_second|wall|elapsed|"
                        r"mcells|duration_s|time_s)", re.I)
TIMING_TEXT = re.compile(r"[0-9]+(\.[0-9]+)?(e[-+]?[0-9]+)? ?(s|ms|seconds|Mcells/s)\b")

def files(root):
    out = set()
    for d, _, names in os.walk(root):
        for n in names:
            out.add(os.path.relpath(os.path.join(d, n), root))
    return out

def drop_timings(o):
    if isinstance(o, dict):
        return {k: drop_timings(v) for k, v in o.items() if not TIMING_KEY.search(k)}
    if isinstance(o, list):
        return [drop_timings(v) for v in o]
    return o

def same(rel):
    pa, pb = os.path.join(a_dir, rel), os.path.join(b_dir, rel)
    ba, bb = open(pa, "rb").read(), open(pb, "rb").read()
    if ba == bb:
        return True
    if rel.endswith(".json"):
        return drop_timings(json.loads(ba)) == drop_timings(json.loads(bb))
    if rel.endswith((".md", ".txt", ".log", ".stdout")):
        def mask(t):
            lines, in_stages = [], False
            for line in TIMING_TEXT.sub("T", t.decode("utf-8", "replace")).split("\n"):
                in_stages = (in_stages and line.startswith("|")) or line.startswith(
                    "| stage | seconds")
                if in_stages:  # the stage table's second column holds seconds
                    line = re.sub(r"^(\| [^|]+ \| )[0-9.]+( \|)", r"\1T\2", line)
                lines.append(line)
            return "\n".join(lines)
        return mask(ba) == mask(bb)
    return False

fa, fb = files(a_dir), files(b_dir)
bad = 0
for rel in sorted(fa ^ fb):
    print("only in %s: %s" % (a_dir if rel in fa else b_dir, rel))
    bad += 1
for rel in sorted(fa & fb):
    if rel == "commands.log":
        continue
    if not same(rel):
        print("differs: %s" % rel)
        bad += 1
print("%d of %d files differ or are missing" % (bad, len(fa | fb)))
sys.exit(1 if bad else 0)
EOF
}

case "${1:-}" in
record) shift; record "$@" ;;
compare) shift; compare "$@" ;;
*) sed -n '2,12p' "$0" >&2; exit 2 ;;
esac
