#!/usr/bin/env bash
# A small private CA for gaitforge, with openssl (docs/deploy.md, "TLS and tokens").
#
#   make-certs.sh ca DIR                          DIR/ca.crt, DIR/ca.key (10 years)
#   make-certs.sh server CA_DIR OUT_DIR NAME SAN...
#                                                 OUT_DIR/server.crt, server.key (1 year);
#                                                 SAN items like DNS:head-node IP:10.0.0.5
#   make-certs.sh client CA_DIR OUT_DIR NAME      OUT_DIR/NAME.crt, NAME.key (for
#                                                 --tls-client-ca; 1 year)
#
# Keys are EC P-256 and written with mode 0600. Workers and clients need only ca.crt
# (--tls-ca). Keep ca.key off shared storage if you can; whoever has it can mint a
# certificate the workers will trust.
set -euo pipefail
umask 077

usage() {
  sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

cmd="${1:-}"
[ -n "$cmd" ] || usage
shift
command -v openssl >/dev/null || { echo "make-certs.sh: openssl is not installed" >&2; exit 1; }

sign() {  # CA_DIR CSR OUT_CRT EXTFILE
  openssl x509 -req -in "$2" -CA "$1/ca.crt" -CAkey "$1/ca.key" -CAcreateserial \
    -out "$3" -days 365 -sha256 -extfile "$4" 2>/dev/null
}

case "$cmd" in
  ca)
    [ $# -eq 1 ] || usage
    dir="$1"
    mkdir -p "$dir"
    openssl ecparam -name prime256v1 -genkey -noout -out "$dir/ca.key"
    openssl req -x509 -new -key "$dir/ca.key" -sha256 -days 3650 -subj "/CN=gaitforge test CA" \
      -addext "basicConstraints=critical,CA:TRUE" -addext "keyUsage=critical,keyCertSign,cRLSign" \
      -out "$dir/ca.crt"
    chmod 0644 "$dir/ca.crt"
    echo "$dir/ca.crt $dir/ca.key"
    ;;
  server)
    [ $# -ge 4 ] || usage
    ca="$1" out="$2" name="$3"
    shift 3
    san="$(IFS=,; echo "$*")"
    mkdir -p "$out"
    tmp="$(mktemp -d)"
    trap 'rm -rf "$tmp"' EXIT
    openssl ecparam -name prime256v1 -genkey -noout -out "$out/server.key"
    openssl req -new -key "$out/server.key" -subj "/CN=$name" -out "$tmp/server.csr"
    printf '%s\n' "basicConstraints=CA:FALSE" "keyUsage=critical,digitalSignature,keyEncipherment" \
      "extendedKeyUsage=serverAuth" "subjectAltName=$san" >"$tmp/ext"
    sign "$ca" "$tmp/server.csr" "$out/server.crt" "$tmp/ext"
    chmod 0644 "$out/server.crt"
    echo "$out/server.crt $out/server.key ($san)"
    ;;
  client)
    [ $# -eq 3 ] || usage
    ca="$1" out="$2" name="$3"
    mkdir -p "$out"
    tmp="$(mktemp -d)"
    trap 'rm -rf "$tmp"' EXIT
    openssl ecparam -name prime256v1 -genkey -noout -out "$out/$name.key"
    openssl req -new -key "$out/$name.key" -subj "/CN=$name" -out "$tmp/client.csr"
    printf '%s\n' "basicConstraints=CA:FALSE" "keyUsage=critical,digitalSignature" \
      "extendedKeyUsage=clientAuth" >"$tmp/ext"
    sign "$ca" "$tmp/client.csr" "$out/$name.crt" "$tmp/ext"
    chmod 0644 "$out/$name.crt"
    echo "$out/$name.crt $out/$name.key"
    ;;
  *) usage ;;
esac
