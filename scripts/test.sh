#!/usr/bin/env bash
# Builds gaitforge (installing missing packages) and runs every test: unit, integration,
# end-to-end (real coordinator and worker processes on loopback, the deploy check) and
# chaos (faults injected, network namespaces). Extra arguments go to ctest, e.g.
# ./scripts/test.sh -L unit, or ./scripts/test.sh -LE chaos to skip the slow ones.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc)" "$@"
