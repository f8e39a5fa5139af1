#!/usr/bin/env bash
# Installs missing packages, configures and builds gaitforge into ./build (binaries in
# build/bin). Extra arguments go to CMake, e.g. -DCMAKE_BUILD_TYPE=Debug.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
ninja -C build -j "$(nproc)"
