#!/usr/bin/env bash
# The main job on built-in data: a hybrid reservoir mesh (a Cartesian layer,
# a well, a fault through the well's cavity), its transition mesh certified,
# written as orthomesh-demo/demo.vtu (ParaView), demo.svg (picture),
# demo.json (report), demo.mesh (TOUGH2 MESH) and demo.DATA (an OPM Flow deck:
# `flow orthomesh-demo/demo.DATA` runs it).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo run --quiet --bin orthomesh -- demo --out-dir orthomesh-demo "$@"
