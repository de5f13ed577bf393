#!/usr/bin/env bash
# The browser test of the web explorer (CI runs it from .ci/run): builds dist/
# (scripts/build-web.sh), serves it on a free port of 127.0.0.1, and runs web/e2e/explorer.cjs
# in headless Chromium: first converged solve drawn (screenshot not blank), friction slider
# moves re-solved warm and converged, no console errors. Screenshots and timings go to
# target/web-e2e/ (MOVES slider moves, default 3; scripts/bench-web.sh takes more). Then the
# same page under seeded random use (`explorer.cjs --random`: LOPIN_UI_SEED, at most
# LOPIN_UI_CLICKS actions and LOPIN_UI_SECONDS seconds), again with no console error.
set -euo pipefail
cd "$(dirname "$0")/.."
export WEB_BROWSER=1
if [ "${1:-}" != "--no-build" ]; then
    ./scripts/build-web.sh
fi
source scripts/web-tools.sh
OUT="${WEB_E2E_OUT:-target/web-e2e}"
mkdir -p "$OUT"
serve_dist "$OUT/server.log"
node web/e2e/explorer.cjs "http://127.0.0.1:$PORT/" "$OUT" "${MOVES:-3}"
node web/e2e/explorer.cjs --random "http://127.0.0.1:$PORT/" "$OUT"
