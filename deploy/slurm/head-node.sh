#!/usr/bin/env bash
# The Slurm head-node variant: the coordinator runs by hand on the login (or a service)
# node, outside Slurm, and only the workers are jobs (deploy/slurm/workers.sbatch, which
# finds it through the same address file). Use it when a coordinator job cannot run as
# long as your studies, and your site allows a light, long-running process there (the
# coordinator uses little CPU; ask your admins).
#
#   GAITFORGE_LISTEN_INTERFACE=ib0 deploy/slurm/head-node.sh start
#   deploy/slurm/head-node.sh status | stop
#
# The database goes to GAITFORGE_DB (default /var/tmp/$USER/gaitforge/gaitforge.db: a
# local disk of this node; never $HOME or other NFS). The address is written to
# $GAITFORGE_SHARED/coordinator.address, where the workers look for it. Same environment
# as coordinator.sbatch for TLS and tokens (GAITFORGE_TLS_CERT/KEY or GAITFORGE_INSECURE=1,
# GAITFORGE_TOKENS_FILE).
set -euo pipefail

export GAITFORGE_HOME="${GAITFORGE_HOME:-$(cd "$(dirname "$0")/../.." && pwd)}"
# shellcheck source=deploy/lib/gaitforge.sh
source "$GAITFORGE_HOME/deploy/lib/gaitforge.sh"

shared="${GAITFORGE_SHARED:-$GAITFORGE_HOME/runs/slurm}"
export GAITFORGE_DB="${GAITFORGE_DB:-/var/tmp/${USER:-$(id -un)}/gaitforge/gaitforge.db}"
export GAITFORGE_ADDRESS_FILE="$shared/coordinator.address"
export GAITFORGE_PORT="${GAITFORGE_PORT:-50051}"
if [ -z "${GAITFORGE_TOKENS_FILE:-}" ] && [ -f "$shared/tokens" ]; then
  export GAITFORGE_TOKENS_FILE="$shared/tokens"
fi
state_dir="$(dirname "$GAITFORGE_DB")"
pid_file="$state_dir/coordinator.pid"
log_file="$state_dir/coordinator.log"

running_pid() {
  local pid
  [ -f "$pid_file" ] || return 1
  pid="$(cat "$pid_file")"
  kill -0 "$pid" 2>/dev/null || return 1
  printf '%s\n' "$pid"
}

case "${1:-}" in
  start)
    if pid="$(running_pid)"; then
      echo "gaitforge: coordinator already running (pid $pid), at $(cat "$GAITFORGE_ADDRESS_FILE" 2>/dev/null)"
      exit 0
    fi
    : "${GAITFORGE_LISTEN_INTERFACE:?set GAITFORGE_LISTEN_INTERFACE to the network the workers use, e.g. ib0}"
    mkdir -p "$state_dir" "$shared"
    rm -f "$GAITFORGE_ADDRESS_FILE"
    gf_coordinator_argv
    echo "gaitforge: ${GF_ARGV[*]}" >>"$log_file"
    # Detached from this terminal: logging out does not stop it.
    nohup setsid "${GF_ARGV[@]}" >>"$log_file" 2>&1 </dev/null &
    echo $! >"$pid_file"
    if addr="$(gf_wait_for_file "$GAITFORGE_ADDRESS_FILE" 30)"; then
      echo "gaitforge: coordinator pid $(cat "$pid_file") serving at $addr (log: $log_file)"
    else
      echo "gaitforge: the coordinator did not start; see $log_file" >&2
      tail -n 20 "$log_file" >&2
      exit 1
    fi
    ;;
  stop)
    if pid="$(running_pid)"; then
      kill -TERM "$pid"
      for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
      if kill -0 "$pid" 2>/dev/null; then
        echo "gaitforge: coordinator $pid still running after 10 s" >&2
        exit 1
      fi
      echo "gaitforge: coordinator $pid stopped"
    else
      echo "gaitforge: no coordinator running"
    fi
    rm -f "$pid_file" "$GAITFORGE_ADDRESS_FILE"
    ;;
  status)
    if pid="$(running_pid)"; then
      echo "gaitforge: coordinator pid $pid at $(cat "$GAITFORGE_ADDRESS_FILE" 2>/dev/null), database $GAITFORGE_DB"
    else
      echo "gaitforge: no coordinator running"
      exit 3
    fi
    ;;
  *)
    echo "usage: $0 start|stop|status" >&2
    exit 2
    ;;
esac
