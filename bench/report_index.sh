#!/usr/bin/env bash
# Prints the "Report index" section of docs/benchmarks.md on stdout: how fast the index of a
# 10,000-scene `blockworld report` opens from the file system in headless Chromium
# (bench/report_load.js, docs/report.md "Speed"). bench/report.sh runs it after the benches.
#
#   bench/report_index.sh path/to/blockworld
#
# The dataset is `generate --count 10000 --seed 1 --views ne --size 64x60`; set
# BLOCKWORLD_REPORT_DATASET to a folder holding that dataset to skip generating it. Without
# node, Chromium or playwright-core (`make setup`) the section says so and nothing is run.
set -euo pipefail
bw=${1:?usage: bench/report_index.sh path/to/blockworld}
here=$(cd "$(dirname "$0")" && pwd)
gen_args=(--count 10000 --seed 1 --views ne --size 64x60)

echo "## Report index"
echo
playwright=${BLOCKWORLD_PLAYWRIGHT_CORE:-$here/../target/playwright/node_modules/playwright-core}
chromium=${BLOCKWORLD_CHROMIUM:-/usr/bin/chromium}
if ! command -v node >/dev/null || [ ! -x "$chromium" ] || [ ! -d "$playwright" ]; then
  echo 'Not run for this page: it needs node, Chromium and playwright-core (`make setup`).'
  exit 0
fi

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
dataset=${BLOCKWORLD_REPORT_DATASET:-}
if [ -z "$dataset" ]; then
  dataset=$out/dataset
  echo "generate ${gen_args[*]} ..." >&2
  "$bw" generate "${gen_args[@]}" -o "$dataset" >/dev/null 2>"$out/generate.err" || {
    echo "generate failed:" >&2; cat "$out/generate.err" >&2; exit 2; }
fi
echo "report ..." >&2
start=$EPOCHREALTIME
"$bw" report "$dataset" -o "$out/site" >/dev/null 2>"$out/report.err" || {
  echo "report failed:" >&2; cat "$out/report.err" >&2; exit 2; }
build_s=$(awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }')
case "$bw" in *release*) build=release ;; *debug*) build=debug ;; *) build=given ;; esac
echo "report_load.js ..." >&2
node "$here/report_load.js" "$out/site" 5 >"$out/load.json"

echo "The index of \`blockworld report\` on"
echo "\`generate ${gen_args[*]}\`, opened from the file system in headless"
echo "Chromium by \`node bench/report_load.js SITE 5\` (a fresh profile per run): the load event,"
echo "and the first page of the grid drawn with every thumbnail in the 1280 x 900 window decoded"
echo "(docs/report.md \"Speed\")."
echo
echo '```text'
node -e '
const r = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
const f = (m) => m.median + " / " + m.max;
console.log("| scenes | page size | thumbnails in the window | load event, ms (median / slowest of 5) | first page shown, ms (median / slowest of 5) | report build, s (" + process.argv[3] + " build) |");
console.log("|---|---|---|---|---|---|");
console.log("| " + [r.scenes, r.page_size, r.thumbs_in_window, f(r.load_ms), f(r.shown_ms),
  process.argv[2]].join(" | ") + " |");
console.log("runs: load " + r.load_ms.runs.join(", ") + " ms; shown " + r.shown_ms.runs.join(", ") + " ms");
' "$out/load.json" "$build_s" "$build"
echo '```'
