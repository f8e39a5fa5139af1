#!/usr/bin/env bash
# GAITFORGE_WRAP shim for tests/deploy/check_deploy.sh:  pending_flags.sh BINARY ARGS...
#
# Runs BINARY with ARGS unchanged when its --help lists every flag used. A flag the
# binary does not have yet is translated to what exists, or dropped, and each such step
# is logged (one line) to $GAITFORGE_PENDING_LOG, so the check can say exactly which
# deploy command lines were not run as written:
#   coordinator --address-file F   -> --port-file F.port, then "HOST:PORT" written to F
#   coordinator --listen-interface -> the interface's IPv4 address as the --listen host
#   worker --coordinator-file F    -> waits for F, then --coordinator "$(cat F)"
#   anything else missing          -> dropped (TLS, tokens, metrics, log format)
set -euo pipefail

bin="$1"
shift
name="$(basename "$bin")"
help="$("$bin" --help 2>&1 || true)"
log="${GAITFORGE_PENDING_LOG:-/dev/stderr}"

has() { grep -Eq -- "^ +--$1( |$)" <<<"$help"; }
note() { echo "$name: $*" >>"$log"; }
is_bool() { case "$1" in insecure | read-only | json | csv | help) return 0 ;; *) return 1 ;; esac; }

out=()
address_file="" iface="" listen=""
while [ $# -gt 0 ]; do
  arg="$1"
  shift
  case "$arg" in
    --*=*) flag="${arg%%=*}" value="${arg#*=}" ;;
    --*)
      flag="$arg" value=""
      if ! is_bool "${flag#--}" && [ $# -gt 0 ]; then value="$1"; shift; fi
      ;;
    *) out+=("$arg"); continue ;;
  esac
  f="${flag#--}"
  if [ "$f" = listen ]; then listen="$value"; continue; fi
  if [ "$f" = help ]; then out+=("$flag"); continue; fi
  [ "$f" != listen-interface ] || iface="$value"
  if has "$f"; then
    if is_bool "$f"; then out+=("$flag"); else out+=("$flag" "$value"); fi
    continue
  fi
  case "$name:$f" in
    gaitforge-coordinator:address-file)
      address_file="$value"
      note "--address-file $value -> --port-file $value.port (+ the shim writes HOST:PORT)"
      ;;
    gaitforge-coordinator:listen-interface)
      note "--listen-interface $value -> --listen <its IPv4>:PORT"
      ;;
    gaitforge-worker:coordinator-file)
      note "--coordinator-file $value -> --coordinator \$(cat $value) after waiting for it"
      for _ in $(seq 600); do [ -s "$value" ] && break; sleep 0.1; done
      [ -s "$value" ] || { echo "pending_flags: no address in $value" >&2; exit 4; }
      out+=(--coordinator "$(head -n 1 "$value")")
      ;;
    *)
      note "--$f dropped (not in --help yet)"
      ;;
  esac
done

host="${listen%:*}" port="${listen##*:}"
if [ -n "$iface" ]; then
  ifhost="$(ip -4 -o addr show dev "$iface" | awk '{split($4, a, "/"); print a[1]; exit}')"
  has listen-interface || listen="$ifhost:$port"
  host="$ifhost"
fi
[ -z "$listen" ] || out+=(--listen "$listen")
if [ -n "$address_file" ]; then
  out+=(--port-file "$address_file.port")
  rm -f "$address_file.port"
  (
    for _ in $(seq 600); do
      if [ -s "$address_file.port" ]; then
        echo "$host:$(cat "$address_file.port")" >"$address_file.tmp"
        mv -f "$address_file.tmp" "$address_file"
        exit 0
      fi
      sleep 0.1
    done
  ) &
fi
exec "$bin" "${out[@]}"
