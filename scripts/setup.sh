#!/usr/bin/env bash
# Installs the system packages orthomesh builds against (Debian/Ubuntu):
# CGAL headers (+ GMP, MPFR, Boost), cmake to build HiGHS, libclang for
# HiGHS' bindgen bindings, valgrind for scripts/valgrind.sh, OPM Flow (the
# `flow` simulator) for tests/decks.py. Idempotent: does nothing when all
# are present.
set -euo pipefail
pkgs="libcgal-dev libgmp-dev libmpfr-dev cmake libclang-dev clang g++ valgrind libopm-simulators-bin"
missing=""
for p in $pkgs; do
  dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
echo "orthomesh setup: installing$missing" >&2
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends $missing >/dev/null
