#!/usr/bin/env bash
# Wall time of each test binary, for docs/testing.md "Wall time": the unit tests of the library
# and of the binary (`--lib`, `--bins`) and each integration test binary (tests/*.rs).
#
#   scripts/test_times.sh                  every binary, slowest first, as a Markdown table
#   scripts/test_times.sh vision --lib     only these
#
# It builds the test binaries first (`cargo test --lib --bins --tests --no-run`), so the times
# are of the tests alone, not of compiling them. It sets the variables `make test` sets, so a missing GPU
# adapter, Slurm cluster or manifest validator fails instead of skipping (run
# `scripts/slurm_local.sh up` first). CARGO_TEST_ARGS passes flags to cargo test (`--release`).
# A binary whose tests fail is marked `FAILED` in the table and the script exits 1.
set -euo pipefail
cd "$(dirname "$0")/.."

export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/blockworld-xdg}"
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
export BLOCKWORLD_REQUIRE_GPU=1 BLOCKWORLD_REQUIRE_SLURM=1 BLOCKWORLD_REQUIRE_K8S_VALIDATE=1
cargo_args=(${CARGO_TEST_ARGS:-})

if [ "$#" -gt 0 ]; then
    names=("$@")
else
    names=(--lib --bins)
    for f in tests/*.rs; do names+=("$(basename "$f" .rs)"); done
fi

cargo test "${cargo_args[@]}" --lib --bins --tests --no-run --quiet

rows=$(mktemp)
trap 'rm -f "$rows"' EXIT
failed=0
for name in "${names[@]}"; do
    case "$name" in
        --lib) target=(--lib) label="unit tests of src/ (--lib)" ;;
        --bins) target=(--bins) label="unit tests of the binary (--bins)" ;;
        *) target=(--test "$name") label="\`tests/$name.rs\`" ;;
    esac
    log="target/test-times/${name#--}.log"
    mkdir -p target/test-times
    start=$(date +%s.%N)
    if cargo test "${cargo_args[@]}" --quiet "${target[@]}" >"$log" 2>&1; then
        status=ok
    else
        status=FAILED
        failed=1
    fi
    end=$(date +%s.%N)
    passed=$(grep -Eo '[0-9]+ passed' "$log" | awk '{s += $1} END {print s + 0}')
    ignored=$(grep -Eo '[0-9]+ ignored' "$log" | awk '{s += $1} END {print s + 0}')
    seconds=$(echo "$end - $start" | bc)
    printf '%s\t%s\t%s\t%s\t%s\n' "$seconds" "$label" "$passed" "$ignored" "$status" >>"$rows"
    printf '%7.1f s  %s (%s)\n' "$seconds" "$name" "$status" >&2
done

echo "| test binary | wall time (s) | tests passed | ignored | result |"
echo "|---|---:|---:|---:|---|"
sort -t$'\t' -k1,1 -g -r "$rows" | while IFS=$'\t' read -r s label passed ignored status; do
    printf '| %s | %.1f | %s | %s | %s |\n' "$label" "$s" "$passed" "$ignored" "$status"
done
total=$(awk -F'\t' '{s += $1} END {printf "%.0f", s}' "$rows")
echo
echo "Total: ${total} s for ${#names[@]} binaries on $(nproc) cores ($(uname -m)); logs in target/test-times/."
exit "$failed"
