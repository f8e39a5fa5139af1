#!/usr/bin/env bash
# Builds gaitforge (installing missing packages) and runs every test: unit, integration
# and end-to-end (real coordinator and worker processes on loopback). Extra arguments go
# to ctest, e.g. ./scripts/test.sh -L unit.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc)" "$@"
