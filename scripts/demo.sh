#!/usr/bin/env bash
# The main job on built-in data: a cavity around a well, meshed, certified,
# written as orthomesh-demo/demo.vtu (ParaView), demo.svg (picture), demo.json.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo run --quiet --bin orthomesh -- demo --out-dir orthomesh-demo "$@"
