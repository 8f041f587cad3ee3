#!/usr/bin/env bash
# The FFI under valgrind's memcheck: the CGAL shim's tests (tests/ffi.rs:
# every entry point, every C++ throw) and the hand-built known answers
# (CGAL and HiGHS through the whole pipeline). Fails on any memory error or
# definite leak that valgrind reports. Usage: bash scripts/valgrind.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
command -v valgrind >/dev/null || { echo "valgrind is missing (scripts/setup.sh installs it)" >&2; exit 1; }
for t in ffi known_answers; do
  exe=$(cargo test --test "$t" --no-run --message-format=json 2>/dev/null |
    python3 -c 'import json,sys
for l in sys.stdin:
    m = json.loads(l)
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["target"]["kind"] == ["test"]:
        print(m["executable"])')
  echo "valgrind: $t ($exe)" >&2
  valgrind --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=definite \
    --show-leak-kinds=definite --quiet "$exe" --test-threads=1 -q
done
echo "valgrind: no errors" >&2
