#!/usr/bin/env bash
# Installs what the web build and the browser test need on a fresh Debian machine, skipping what
# is already there, and prints nothing but progress lines. Sourced by build-web.sh and
# test-web.sh; sets WEB_TOOLS (a cache outside the repository, reused between runs).
#
# - Debian's second Rust toolchain for the browser (rustc-web, cargo-web, rust-web-src: std
#   sources for -Zbuild-std) and wasm-ld (lld-22): rustup's toolchain has no wasm32 std.
# - wasm-bindgen-cli at exactly the wasm-bindgen version of Cargo.lock (cargo install, cached).
# - node and npm (Debian's if none), binaryen@132 from npm for wasm-opt (Debian's binaryen 108
#   writes modules browsers reject), and with WEB_BROWSER=1 chromium and playwright-core.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WEB_TOOLS="${LOPIN_WEB_TOOLS:-$HOME/.cache/lopin-web-tools}"
mkdir -p "$WEB_TOOLS"

apt_install() {
    local missing=()
    for p in "$@"; do
        dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo=sudo
    echo "web tools: apt-get install ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -q >/dev/null
    $sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
}

apt_install rustc-web cargo-web rust-web-src lld-22
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    apt_install nodejs npm
fi
if [ "${WEB_BROWSER:-0}" = 1 ]; then
    apt_install chromium fonts-dejavu-core
fi

# wasm-bindgen-cli must match the library version the lockfile pins
WASM_BINDGEN_VERSION="$(awk '/^name = "wasm-bindgen"$/ {getline; gsub(/version = |"/, ""); print; exit}' "$ROOT/Cargo.lock")"
if [ -z "$WASM_BINDGEN_VERSION" ]; then
    echo "web tools: no wasm-bindgen in Cargo.lock" >&2
    exit 1
fi
if ! "$WEB_TOOLS/bin/wasm-bindgen" --version 2>/dev/null | grep -qx "wasm-bindgen $WASM_BINDGEN_VERSION"; then
    echo "web tools: cargo install wasm-bindgen-cli $WASM_BINDGEN_VERSION (a few minutes, once)"
    # without --locked: its lockfile pins a crate version the registry index here lacks
    cargo install -q wasm-bindgen-cli --version "=$WASM_BINDGEN_VERSION" --root "$WEB_TOOLS"
fi

# npm packages, pinned, in the cache
npm_pkgs=("binaryen@132.0.0")
[ "${WEB_BROWSER:-0}" = 1 ] && npm_pkgs+=("playwright-core@1.61.0")
need_npm=0
for p in "${npm_pkgs[@]}"; do
    name="${p%@*}"
    want="${p##*@}"
    have="$(node -p "require('$WEB_TOOLS/npm/node_modules/$name/package.json').version" 2>/dev/null || true)"
    [ "$have" = "$want" ] || need_npm=1
done
if [ "$need_npm" = 1 ]; then
    echo "web tools: npm install ${npm_pkgs[*]}"
    mkdir -p "$WEB_TOOLS/npm"
    npm install --silent --no-audit --no-fund --prefix "$WEB_TOOLS/npm" "${npm_pkgs[@]}" >/dev/null
fi
export WEB_TOOLS

# serve_dist LOG: serves dist/ on a free port of 127.0.0.1 until the calling script exits; sets
# PORT once the server answers.
serve_dist() {
    PORT=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
    python3 -m http.server --bind 127.0.0.1 --directory "$ROOT/dist" "$PORT" >"$1" 2>&1 &
    local server=$!
    trap "kill $server 2>/dev/null || true" EXIT
    for _ in $(seq 50); do
        python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$PORT/')" 2>/dev/null && return 0
        sleep 0.1
    done
    echo "web: the server of dist/ does not answer on 127.0.0.1:$PORT" >&2
    return 1
}
