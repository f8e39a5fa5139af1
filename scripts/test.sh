#!/usr/bin/env bash
# Builds gaitforge (installing missing packages) and runs every test: unit, integration,
# end-to-end (real coordinator and worker processes on loopback, the deploy check) and
# chaos (faults injected, network namespaces). Extra arguments go to ctest, e.g.
# ./scripts/test.sh -L unit, or ./scripts/test.sh -LE chaos to skip the chaos tests;
# ./scripts/test.sh -L slow runs the checks too slow for CI (label slow).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
cd build
# Tests labelled `slow` (minutes each; CI keeps under 30 minutes) run only when asked for
# (./scripts/test.sh -L slow): `slow` joins any -LE given.
args=() exclude="" asked_slow=0
while (($#)); do
  case "$1" in
    -LE) exclude="$2"; shift 2 ;;
    *) [[ "$1" == *slow* ]] && asked_slow=1; args+=("$1"); shift ;;
  esac
done
if ((asked_slow)); then
  [[ -n "$exclude" ]] && args+=(-LE "$exclude")
else
  args+=(-LE "${exclude:+$exclude|}slow")
fi
ctest --output-on-failure -j "$(nproc)" "${args[@]}"
