#!/usr/bin/env bash
# Installs the Debian 12 packages gaitforge needs, if any is missing (apt-get, as root or
# through sudo). Safe to run repeatedly: does nothing when all are present.
set -euo pipefail

PACKAGES=(
  cmake ninja-build g++ pkg-config
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libsqlite3-dev libspdlog-dev libgtest-dev libgmock-dev libeigen3-dev libode-dev
  libbenchmark-dev libyaml-cpp-dev prometheus-cpp-dev libcivetweb-dev openssl libjemalloc-dev
  # An independent build of the generic robots (workers/models/mujoco, issue 27).
  libmujoco-dev
  iproute2 nftables
  python3 python3-matplotlib python3-numpy python3-scipy python3-statsmodels
  python3-grpcio python3-protobuf python3-yaml python3-pandas
  # The dashboard's browser test (tests/dashboard): headless Chromium driven by Selenium.
  chromium chromium-driver python3-selenium
  # bench/anchors/optuna_dispatch.py: Optuna's RDB storage as the dispatch anchor.
  python3-optuna
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "gaitforge: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "gaitforge: need root or sudo to install packages" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
