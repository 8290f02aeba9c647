#!/usr/bin/env bash
# Writes docs/benchmarks.md on stdout: runs each bench of BLOCKWORLD (a release binary, first
# argument) and puts its table under a heading, with the machine named once at the top.
# `make benchmarks` runs it; PEERS=1 adds `bench peers` (after `make peers`).
set -euo pipefail
bw=${1:?usage: bench/report.sh path/to/release/blockworld}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# name|heading|command (arguments of `blockworld bench`)
benches=(
  "render|Render|render"
  "generate|Generate|generate"
  "vision|Vision|vision"
  "recognize|Recognize|recognize"
  "settle|Settle|settle"
  "scale|Scale|scale"
)
if [ "${PEERS:-0}" = 1 ]; then
  benches+=("peers|Peer ratios|peers")
fi
for b in "${benches[@]}"; do
  IFS='|' read -r name _ args <<<"$b"
  echo "bench $args ..." >&2
  # shellcheck disable=SC2086
  "$bw" bench $args >"$out/$name.txt" 2>"$out/$name.err" || {
    echo "bench $args failed:" >&2; cat "$out/$name.err" >&2; exit 2; }
done

cat bench/benchmarks_intro.md
echo
echo '```text'
grep -m1 '^machine:' "$out/render.txt"
grep -m1 '^renderer:' "$out/render.txt" || true
echo "blockworld $("$bw" --version | cut -d' ' -f2-), release build"
echo '```'
for b in "${benches[@]}"; do
  IFS='|' read -r name heading args <<<"$b"
  echo
  echo "## $heading"
  echo
  echo "\`blockworld bench $args\`:"
  echo
  echo '```text'
  grep -v -E '^(machine:|renderer|build:)' "$out/$name.txt" | sed -e '/./,$!d'
  echo '```'
done
echo
bench/report_index.sh "$bw"
if [ "${PEERS:-0}" != 1 ]; then
  echo
  echo "## Peer ratios"
  echo
  echo 'Not run for this page: `make peers`, then `PEERS=1 make benchmarks` adds the table.'
fi
