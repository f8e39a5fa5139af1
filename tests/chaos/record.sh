#!/usr/bin/env bash
# Runs both chaos tests once and saves their printed summaries (and JSON) under
# tests/chaos/results/, named by date: local-YYYYMMDD.{txt,json}, netns-YYYYMMDD.{txt,json}.
# Usage: tests/chaos/record.sh [BIN_DIR]   (default build/bin). Exit: worst of the two.
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="${1:-$here/../../build/bin}"
day="$(date +%Y%m%d)"
out="$here/results"
mkdir -p "$out"
rc=0
for t in local netns; do
  script="$here/chaos.py"; [ "$t" = netns ] && script="$here/netns.py"
  start=$(date +%s)
  /usr/bin/python3 "$script" --bin-dir "$bin" --json-out "$out/$t-$day.json" 2>&1 | tee "$out/$t-$day.txt"
  code=${PIPESTATUS[0]}
  echo "exit $code; $(( $(date +%s) - start )) s wall; $(date -u +%Y-%m-%dT%H:%M:%SZ) on $(nproc) cores" | tee -a "$out/$t-$day.txt"
  [ "$code" -ne 0 ] && [ "$code" -ne 77 ] && rc=1
done
exit $rc
