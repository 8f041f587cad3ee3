#!/usr/bin/env bash
# Runs fuzz targets (fuzz/fuzz_targets) with cargo-fuzz on nightly, each for
# SECONDS (default 1800), seeded from fuzz/seeds/<target> and the malformed
# inputs of tests/corpus; new inputs go to fuzz/out/<target>, crashes to
# fuzz/artifacts/<target>. Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-1800}
shift || true
targets=${*:-poly edg grdecl tetgen pipeline}
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
# The targets link HiGHS' C++ runtime, which may load before ASan's.
export ASAN_OPTIONS=verify_asan_link_order=0
for t in $targets; do
    mkdir -p "fuzz/out/$t"
    seeds=("fuzz/out/$t" tests/corpus)
    if [ -d "fuzz/seeds/$t" ]; then seeds+=("fuzz/seeds/$t"); fi
    echo "fuzz $t for $secs s"
    cargo +nightly fuzz run "$t" "${seeds[@]}" -- \
        -max_total_time="$secs" -rss_limit_mb=4096 -timeout=60 2>&1 | tail -n 40 > "fuzz/out/$t.log" ||
        echo "fuzz $t: stopped on a failure (fuzz/out/$t.log, fuzz/artifacts/$t)"
    tail -n 3 "fuzz/out/$t.log"
done
