# shellcheck shell=bash
# shellcheck disable=SC2034  # GF_ARGV and GF_COORDINATOR_PID are set for the caller
# Shared command lines for every gaitforge deployment: the Docker entrypoint
# (deploy/docker/entrypoint.sh), the Slurm jobs (deploy/slurm/*.sbatch, head-node.sh) and
# the offline check (tests/deploy/check_deploy.sh) all build their gaitforge command
# lines here, so what the check runs is what production runs. Source it; it defines
# functions and sets nothing else. Configuration comes from the environment:
#
#   GAITFORGE_BIN              directory of the binaries (default: $GAITFORGE_HOME/build/bin,
#                              else the directory of gaitforge-coordinator on PATH)
#   GAITFORGE_WRAP             command prefix for every binary, split on spaces, e.g.
#                              "apptainer exec /shared/gaitforge.sif" (default: none)
#
#   coordinator
#   GAITFORGE_DB               SQLite file on a LOCAL disk (required; never NFS)
#   GAITFORGE_LISTEN           host:port to serve on (default 127.0.0.1:50051)
#   GAITFORGE_LISTEN_INTERFACE serve on this interface's IPv4 address instead (e.g. ib0);
#                              the port is GAITFORGE_PORT (default 0: any free port)
#   GAITFORGE_ADDRESS_FILE     write "host:port" here once serving (shared storage)
#   GAITFORGE_PORT_FILE        write the bound port here once serving
#   GAITFORGE_TLS_CERT, GAITFORGE_TLS_KEY   server certificate and key (PEM)
#   GAITFORGE_TLS_CLIENT_CA    require client certificates signed by this CA
#   GAITFORGE_INSECURE=1       allow plaintext on a non-loopback listener (trusted networks)
#   GAITFORGE_TOKENS_FILE      lines "ROLE TOKEN" (client|worker|admin); the coordinator also
#                              reads GAITFORGE_{CLIENT,WORKER,ADMIN}_TOKEN itself
#   GAITFORGE_METRICS_LISTEN   host:port for Prometheus text at /metrics (plain HTTP)
#   GAITFORGE_LOG_FORMAT       text or json;  GAITFORGE_LOG_LEVEL  trace..off
#   GAITFORGE_SYNC             full or normal;  GAITFORGE_LEASE_MS  lease length in ms
#
#   worker and CLI
#   GAITFORGE_COORDINATOR      host:port of the coordinator
#   GAITFORGE_COORDINATOR_FILE read host:port from this file instead (waits until it exists)
#   GAITFORGE_TLS_CA           CA that signed the coordinator's certificate
#   GAITFORGE_CLIENT_CERT, GAITFORGE_CLIENT_KEY   client certificate, for a coordinator
#                              started with --tls-client-ca
#   GAITFORGE_TOKEN_FILE       file holding this process's token (the binaries also read
#                              GAITFORGE_WORKER_TOKEN, resp. GAITFORGE_TOKEN, themselves)
#   GAITFORGE_THREADS          worker threads (default: nproc)
#   GAITFORGE_EXIT_WHEN_IDLE   worker exits after this many idle seconds (default 0: never)
#   GAITFORGE_WORKER_ID        worker identity (default: the binary's host-pid-xxxx)
#
# Each *_argv function leaves the command line in the array GF_ARGV; extra arguments are
# appended to it.

gf_die() {
  echo "gaitforge: $*" >&2
  exit 2
}

gf_bin() {
  if [ -n "${GAITFORGE_BIN:-}" ]; then
    printf '%s\n' "$GAITFORGE_BIN"
  elif [ -n "${GAITFORGE_HOME:-}" ] && [ -x "$GAITFORGE_HOME/build/bin/gaitforge-coordinator" ]; then
    printf '%s\n' "$GAITFORGE_HOME/build/bin"
  elif command -v gaitforge-coordinator >/dev/null 2>&1; then
    dirname "$(command -v gaitforge-coordinator)"
  else
    gf_die "cannot find the gaitforge binaries: set GAITFORGE_BIN or GAITFORGE_HOME"
  fi
}

# GF_ARGV=(wrap... BIN/NAME)
gf_start_argv() {
  local bin
  bin="$(gf_bin)" || exit 2
  GF_ARGV=()
  if [ -n "${GAITFORGE_WRAP:-}" ]; then
    read -r -a GF_ARGV <<<"$GAITFORGE_WRAP"
  fi
  GF_ARGV+=("$bin/$1")
}

gf_coordinator_argv() {
  [ -n "${GAITFORGE_DB:-}" ] || gf_die "GAITFORGE_DB is not set (a SQLite file on a local disk)"
  gf_start_argv gaitforge-coordinator
  GF_ARGV+=(--db "$GAITFORGE_DB")
  if [ -n "${GAITFORGE_LISTEN_INTERFACE:-}" ]; then
    # The host comes from the interface, the port from --listen.
    GF_ARGV+=(--listen-interface "$GAITFORGE_LISTEN_INTERFACE" --listen "0.0.0.0:${GAITFORGE_PORT:-0}")
  else
    GF_ARGV+=(--listen "${GAITFORGE_LISTEN:-127.0.0.1:50051}")
  fi
  [ -z "${GAITFORGE_ADDRESS_FILE:-}" ] || GF_ARGV+=(--address-file "$GAITFORGE_ADDRESS_FILE")
  [ -z "${GAITFORGE_PORT_FILE:-}" ] || GF_ARGV+=(--port-file "$GAITFORGE_PORT_FILE")
  [ -z "${GAITFORGE_TLS_CERT:-}" ] || GF_ARGV+=(--tls-cert "$GAITFORGE_TLS_CERT")
  [ -z "${GAITFORGE_TLS_KEY:-}" ] || GF_ARGV+=(--tls-key "$GAITFORGE_TLS_KEY")
  [ -z "${GAITFORGE_TLS_CLIENT_CA:-}" ] || GF_ARGV+=(--tls-client-ca "$GAITFORGE_TLS_CLIENT_CA")
  [ "${GAITFORGE_INSECURE:-0}" != 1 ] || GF_ARGV+=(--insecure)
  [ -z "${GAITFORGE_TOKENS_FILE:-}" ] || GF_ARGV+=(--tokens-file "$GAITFORGE_TOKENS_FILE")
  [ -z "${GAITFORGE_METRICS_LISTEN:-}" ] || GF_ARGV+=(--metrics-listen "$GAITFORGE_METRICS_LISTEN")
  [ -z "${GAITFORGE_LOG_FORMAT:-}" ] || GF_ARGV+=(--log-format "$GAITFORGE_LOG_FORMAT")
  [ -z "${GAITFORGE_LOG_LEVEL:-}" ] || GF_ARGV+=(--log-level "$GAITFORGE_LOG_LEVEL")
  [ -z "${GAITFORGE_SYNC:-}" ] || GF_ARGV+=(--sync "$GAITFORGE_SYNC")
  [ -z "${GAITFORGE_LEASE_MS:-}" ] || GF_ARGV+=(--lease-ms "$GAITFORGE_LEASE_MS")
  GF_ARGV+=("$@")
}

# --coordinator-file wins over --coordinator.
gf_client_target_args() {
  if [ -n "${GAITFORGE_COORDINATOR_FILE:-}" ]; then
    GF_ARGV+=(--coordinator-file "$GAITFORGE_COORDINATOR_FILE")
  elif [ -n "${GAITFORGE_COORDINATOR:-}" ]; then
    GF_ARGV+=(--coordinator "$GAITFORGE_COORDINATOR")
  fi
  gf_client_tls_args
}

gf_client_tls_args() {
  [ -z "${GAITFORGE_TLS_CA:-}" ] || GF_ARGV+=(--tls-ca "$GAITFORGE_TLS_CA")
  [ -z "${GAITFORGE_CLIENT_CERT:-}" ] || GF_ARGV+=(--tls-cert "$GAITFORGE_CLIENT_CERT")
  [ -z "${GAITFORGE_CLIENT_KEY:-}" ] || GF_ARGV+=(--tls-key "$GAITFORGE_CLIENT_KEY")
  [ -z "${GAITFORGE_TOKEN_FILE:-}" ] || GF_ARGV+=(--token-file "$GAITFORGE_TOKEN_FILE")
}

gf_worker_argv() {
  local threads="${GAITFORGE_THREADS:-}"
  [ -n "$threads" ] || threads="$(nproc)"
  gf_start_argv gaitforge-worker
  gf_client_target_args
  GF_ARGV+=(--threads "$threads")
  [ "${GAITFORGE_EXIT_WHEN_IDLE:-0}" = 0 ] || GF_ARGV+=(--exit-when-idle "$GAITFORGE_EXIT_WHEN_IDLE")
  [ -z "${GAITFORGE_WORKER_ID:-}" ] || GF_ARGV+=(--worker-id "$GAITFORGE_WORKER_ID")
  [ -z "${GAITFORGE_LOG_LEVEL:-}" ] || GF_ARGV+=(--log-level "$GAITFORGE_LOG_LEVEL")
  GF_ARGV+=("$@")
}

# The CLI has no --coordinator-file: the address is read here.
gf_cli_argv() {
  gf_start_argv gaitforge
  if [ -n "${GAITFORGE_COORDINATOR_FILE:-}" ]; then
    local addr
    addr="$(gf_wait_for_file "$GAITFORGE_COORDINATOR_FILE" "${GAITFORGE_WAIT_S:-30}")" || exit 4
    GF_ARGV+=(--coordinator "$addr")
  elif [ -n "${GAITFORGE_COORDINATOR:-}" ]; then
    GF_ARGV+=(--coordinator "$GAITFORGE_COORDINATOR")
  fi
  gf_client_tls_args
  GF_ARGV+=("$@")
}

# Prints the first line of FILE once it exists and is not empty; fails after TIMEOUT s.
gf_wait_for_file() {
  local file="$1" timeout="${2:-60}" waited=0 line=""
  while :; do
    if [ -s "$file" ]; then
      IFS= read -r line <"$file" || true
      [ -z "$line" ] || { printf '%s\n' "$line"; return 0; }
    fi
    if [ "$waited" -ge $((timeout * 10)) ]; then
      echo "gaitforge: no address in $file after ${timeout}s" >&2
      return 1
    fi
    sleep 0.1
    waited=$((waited + 1))
  done
}

# Starts the coordinator in the background: GF_COORDINATOR_PID.
gf_start_coordinator() {
  gf_coordinator_argv "$@"
  echo "gaitforge: ${GF_ARGV[*]}" >&2
  "${GF_ARGV[@]}" &
  GF_COORDINATOR_PID=$!
}

# Waits for PID even when a trapped signal interrupts `wait`; returns its exit status.
gf_wait_pid() {
  local pid="$1" rc=0
  while :; do
    rc=0
    wait "$pid" || rc=$?
    # 128+n from an interrupted wait while the child still runs: wait again.
    if [ "$rc" -gt 128 ] && kill -0 "$pid" 2>/dev/null; then continue; fi
    return "$rc"
  done
}

# Sends SIGTERM to PID (a drain for workers, a clean shutdown for the coordinator).
gf_term() {
  [ -z "${1:-}" ] || kill -TERM "$1" 2>/dev/null || true
}

# Copies a SQLite database consistently (the online backup API: safe while a coordinator
# writes to SRC), to DST.tmp then renamed, so DST is never half written.
gf_db_copy() {
  local src="$1" dst="$2"
  [ -f "$src" ] || return 0
  mkdir -p "$(dirname "$dst")"
  rm -f "$dst.tmp"
  if command -v sqlite3 >/dev/null 2>&1; then
    sqlite3 "$src" ".timeout 10000" ".backup '$dst.tmp'"
  else
    python3 - "$src" "$dst.tmp" <<'EOF'
import sqlite3, sys
src = sqlite3.connect(sys.argv[1], timeout=10)
dst = sqlite3.connect(sys.argv[2])
src.backup(dst)
dst.close()
src.close()
EOF
  fi
  mv -f "$dst.tmp" "$dst"
}

# Per-job server certificate for this node (hostname + the interface's address), signed
# by the CA in CA_DIR (ca.crt, ca.key). Prints the directory holding server.crt/server.key.
gf_mint_node_cert() {
  local ca_dir="$1" out_dir="$2" iface="${3:-}" ip="" here
  here="$(dirname "${BASH_SOURCE[0]}")"
  if [ -n "$iface" ]; then
    ip="$(ip -4 -o addr show dev "$iface" 2>/dev/null | awk '{split($4, a, "/"); print a[1]; exit}')"
    [ -n "$ip" ] || gf_die "interface '$iface' has no IPv4 address on $(hostname)"
  fi
  local sans=("DNS:$(hostname)" "DNS:localhost" "IP:127.0.0.1")
  [ -z "$ip" ] || sans+=("IP:$ip")
  local fqdn
  fqdn="$(hostname -f 2>/dev/null || true)"
  [ -z "$fqdn" ] || [ "$fqdn" = "$(hostname)" ] || sans+=("DNS:$fqdn")
  bash "$here/../tls/make-certs.sh" server "$ca_dir" "$out_dir" "$(hostname)" "${sans[@]}" >&2 || return 1
  printf '%s\n' "$out_dir"
}
