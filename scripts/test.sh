#!/usr/bin/env bash
# The test suite: Rust unit, integration and property tests, then the meshes
# the tests wrote, read back by the readers users run (vtk, pyvista, meshio),
# the simulator decks they wrote run by OPM Flow, then the FFI tests under
# valgrind.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
python3 -m pip install -q --disable-pip-version-check -r scripts/requirements-readers.txt
# One clean pass, not an edit loop: incremental caches would only fill the disk.
export CARGO_INCREMENTAL=0
export ORTHOMESH_TEST_OUT="$PWD/target/test-meshes"
rm -rf "$ORTHOMESH_TEST_OUT" && mkdir -p "$ORTHOMESH_TEST_OUT"
cargo test --all-targets --features pure-rust "$@"
cargo test --doc --features pure-rust "$@"
# The build without CGAL: the pure-Rust backend alone runs every test.
cargo test --all-targets --no-default-features --features pure-rust "$@"
python3 tests/readers.py "$ORTHOMESH_TEST_OUT"
python3 tests/decks.py "$ORTHOMESH_TEST_OUT"
bash scripts/valgrind.sh
