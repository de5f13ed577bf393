#!/usr/bin/env bash
# Builds the web explorer (scripts/build-web.sh) and serves dist/ on http://127.0.0.1:PORT
# (default 8080) until interrupted. Pass --no-build to serve the existing dist/.
set -euo pipefail
cd "$(dirname "$0")/.."
PORT="${PORT:-8080}"
if [ "${1:-}" != "--no-build" ]; then
    ./scripts/build-web.sh
fi
[ -f dist/index.html ] || { echo "dist/ is not built: run scripts/build-web.sh" >&2; exit 1; }
echo "Lopin web explorer: open http://127.0.0.1:$PORT/ (Ctrl-C stops)"
exec python3 -m http.server --bind 127.0.0.1 --directory dist "$PORT"
