#!/usr/bin/env bash
# Runs fuzz targets (fuzz/fuzz_targets) with cargo-fuzz on nightly, each for
# SECONDS (default 1800), seeded from fuzz/seeds/<target> and the malformed
# inputs of tests/corpus; new inputs go to fuzz/out/<target>, crashes to
# fuzz/artifacts/<target>. Usage: scripts/fuzz.sh [SECONDS] [TARGET...];
# FUZZ_ARGS adds libFuzzer flags (say "-fork=1 -ignore_crashes=1" to go on
# past failures and collect them all).
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-1800}
shift || true
targets=${*:-poly edg grdecl tetgen pipeline}
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
for t in $targets; do
    mkdir -p "fuzz/out/$t"
    seeds=("fuzz/out/$t" tests/corpus)
    if [ -d "fuzz/seeds/$t" ]; then seeds+=("fuzz/seeds/$t"); fi
    echo "fuzz $t for $secs s"
    # No sanitizer: the crate forbids unsafe code outside its FFI (which
    # scripts/valgrind.sh checks), and ASan's runtime clashes with the one
    # gcc links into HiGHS' C++ here. Panics and timeouts are what is sought.
    cargo +nightly fuzz run --sanitizer none "$t" "${seeds[@]}" -- \
        -max_total_time="$secs" -rss_limit_mb=4096 -timeout=60 -print_final_stats=1 ${FUZZ_ARGS:-} > "fuzz/out/$t.log" 2>&1 ||
        echo "fuzz $t: stopped on a failure (fuzz/out/$t.log, fuzz/artifacts/$t)"
    grep -E "^(Done|stat::number_of_executed_units|==[0-9]+== ERROR|thread .* panicked)" "fuzz/out/$t.log" | tail -n 4 || true
done
