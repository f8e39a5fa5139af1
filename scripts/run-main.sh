#!/usr/bin/env bash
# The main job: builds gaitforge (installing missing packages) and runs the paper's GA
# study on the embedded default: a local coordinator, one worker per core, and the SQLite
# file runs/gaitforge.db. Everything stays queryable afterwards (build/bin/gaitforge list).
# Arguments go to `gaitforge local`, e.g. --workers 4.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh
SPEC=${GAITFORGE_SPEC:-examples/caterpillar-ga.yaml}
exec build/bin/gaitforge local "$SPEC" "$@"
