#!/usr/bin/env bash
# Entry point of the gaitforge image (deploy/docker/Dockerfile); also runs from a checkout.
#
#   coordinator [FLAGS]   gaitforge-coordinator, configured from GAITFORGE_* variables
#   worker [FLAGS]        gaitforge-worker
#   cli ARGS...           the gaitforge client (alias: gaitforge)
#   sim ARGS...           gaitforge-sim
#   healthcheck [ROLE]    exit 0 if this container's coordinator answers (or its worker lives)
#   anything else         run as a command (e.g. bash)
#
# The variables are those of deploy/lib/gaitforge.sh. Defaults here suit a container:
# the coordinator listens on 0.0.0.0:50051 with its database under /var/lib/gaitforge (a
# volume), a worker uses every CPU the container may use and talks to coordinator:50051.
# Extra FLAGS are appended to the command line.
set -euo pipefail

here="$(dirname "$(readlink -f "$0")")"
# shellcheck source=deploy/lib/gaitforge.sh
source "${GAITFORGE_LIB:-$here/../lib/gaitforge.sh}"

mode="${1:-coordinator}"
[ $# -eq 0 ] || shift

case "$mode" in
  coordinator)
    export GAITFORGE_LISTEN="${GAITFORGE_LISTEN:-0.0.0.0:50051}"
    export GAITFORGE_DB="${GAITFORGE_DB:-/var/lib/gaitforge/gaitforge.db}"
    # The coordinator creates no directories (a mistyped --db is an error); the container's
    # state directory is ours to make.
    mkdir -p "$(dirname "$GAITFORGE_DB")"
    gf_coordinator_argv "$@"
    exec "${GF_ARGV[@]}"
    ;;
  worker)
    export GAITFORGE_COORDINATOR="${GAITFORGE_COORDINATOR:-coordinator:50051}"
    gf_worker_argv "$@"
    exec "${GF_ARGV[@]}"
    ;;
  cli | gaitforge)
    gf_cli_argv "$@"
    exec "${GF_ARGV[@]}"
    ;;
  sim)
    gf_start_argv gaitforge-sim
    exec "${GF_ARGV[@]}" "$@"
    ;;
  healthcheck)
    # healthcheck [coordinator|worker]. Without an argument the role is the one PID 1 of
    # this container was started with (the image's HEALTHCHECK serves both roles).
    role="${1:-}"
    if [ -z "$role" ]; then
      role=coordinator
      if [ -r /proc/1/cmdline ] && tr '\0' ' ' </proc/1/cmdline | grep -Eq '(^| )worker( |$)'; then
        role=worker
      fi
    fi
    if [ "$role" = worker ]; then
      # Alive is healthy: a worker waiting for its coordinator is not broken.
      for comm in /proc/[0-9]*/comm; do
        if [ "$(cat "$comm" 2>/dev/null)" = "gaitforge-worke" ]; then exit 0; fi
      done
      echo "gaitforge: no gaitforge-worker process" >&2
      exit 1
    fi
    # The coordinator of this container, by its listen port: `gaitforge health`
    # (grpc.health.v1, needs no token) when the CLI has it, else `gaitforge list` with the
    # client (or admin) token. With TLS, its certificate must name localhost and
    # GAITFORGE_TLS_CA must be set in this container too.
    listen="${GAITFORGE_LISTEN:-0.0.0.0:50051}"
    export GAITFORGE_COORDINATOR="localhost:${listen##*:}"
    unset GAITFORGE_COORDINATOR_FILE
    token="${GAITFORGE_TOKEN:-${GAITFORGE_CLIENT_TOKEN:-${GAITFORGE_ADMIN_TOKEN:-}}}"
    if [ -z "$token" ] && [ -r "${GAITFORGE_TOKENS_FILE:-}" ]; then
      token="$(awk '$1 == "client" || $1 == "admin" { print $2; exit }' "$GAITFORGE_TOKENS_FILE")"
    fi
    export GAITFORGE_TOKEN="$token"
    gf_start_argv gaitforge
    if "${GF_ARGV[@]}" --help 2>&1 | grep -Eq '^ +health( |$)'; then
      gf_cli_argv health --timeout 3
    else
      gf_cli_argv list --timeout 3
    fi
    exec "${GF_ARGV[@]}" >/dev/null
    ;;
  *)
    exec "$mode" "$@"
    ;;
esac
