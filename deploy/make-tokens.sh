#!/usr/bin/env bash
# Random bearer tokens for gaitforge's three roles (client, worker, admin), 32 bytes each,
# written with mode 0600 (docs/deploy.md, "TLS and tokens").
#
#   make-tokens.sh env FILE    GAITFORGE_{CLIENT,WORKER,ADMIN}_TOKEN=... lines: Docker
#                              compose's deploy/.env, or a systemd EnvironmentFile
#   make-tokens.sh files DIR   DIR/tokens ("ROLE TOKEN" lines, for --tokens-file),
#                              DIR/worker-token and DIR/client-token (for --token-file)
#
# Refuses to overwrite existing files: rotating tokens means restarting every process.
set -euo pipefail
umask 077

token() {
  if command -v openssl >/dev/null 2>&1; then
    openssl rand -hex 32
  else
    od -An -N32 -tx1 /dev/urandom | tr -d ' \n'
    echo
  fi
}

refuse_existing() {
  for f in "$@"; do
    if [ -e "$f" ]; then
      echo "make-tokens.sh: $f exists; remove it first to make new tokens" >&2
      exit 1
    fi
  done
}

client="$(token)" worker="$(token)" admin="$(token)"
case "${1:-}" in
  env)
    [ $# -eq 2 ] || { echo "usage: $0 env FILE" >&2; exit 2; }
    refuse_existing "$2"
    mkdir -p "$(dirname "$2")"
    printf 'GAITFORGE_CLIENT_TOKEN=%s\nGAITFORGE_WORKER_TOKEN=%s\nGAITFORGE_ADMIN_TOKEN=%s\n' \
      "$client" "$worker" "$admin" >"$2"
    echo "wrote $2"
    ;;
  files)
    [ $# -eq 2 ] || { echo "usage: $0 files DIR" >&2; exit 2; }
    refuse_existing "$2/tokens" "$2/worker-token" "$2/client-token"
    mkdir -p "$2"
    printf 'client %s\nworker %s\nadmin %s\n' "$client" "$worker" "$admin" >"$2/tokens"
    printf '%s\n' "$worker" >"$2/worker-token"
    printf '%s\n' "$client" >"$2/client-token"
    echo "wrote $2/tokens, $2/worker-token, $2/client-token"
    ;;
  *)
    echo "usage: $0 env FILE | files DIR" >&2
    exit 2
    ;;
esac
