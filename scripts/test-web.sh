#!/usr/bin/env bash
# The browser test of the web explorer (CI runs it from .ci/run): builds dist/
# (scripts/build-web.sh), serves it on a free port of 127.0.0.1, and runs web/e2e/explorer.cjs
# in headless Chromium: first converged solve drawn (screenshot not blank), friction slider
# moves re-solved warm and converged, no console errors. Screenshots and timings go to
# target/web-e2e/ (MOVES slider moves, default 3; scripts/bench-web.sh takes more).
set -euo pipefail
cd "$(dirname "$0")/.."
export WEB_BROWSER=1
if [ "${1:-}" != "--no-build" ]; then
    ./scripts/build-web.sh
fi
source scripts/web-tools.sh
OUT="${WEB_E2E_OUT:-target/web-e2e}"
mkdir -p "$OUT"
PORT=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
python3 -m http.server --bind 127.0.0.1 --directory dist "$PORT" >"$OUT/server.log" 2>&1 &
SERVER=$!
trap 'kill $SERVER 2>/dev/null || true' EXIT
for _ in $(seq 50); do
    python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$PORT/')" 2>/dev/null && break
    sleep 0.1
done
node web/e2e/explorer.cjs "http://127.0.0.1:$PORT/" "$OUT" "${MOVES:-3}"
