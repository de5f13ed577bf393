#!/usr/bin/env bash
# Records two-blocks to out/two-blocks.rrd and opens it in the real Rerun viewer (the `rerun`
# tool of rerun-sdk, installed by scripts/install-readers.sh) under Xvfb with software
# rendering, bound to loopback, and saves a screenshot of the viewer to docs/src/figures/rerun.png.
set -euo pipefail
cd "$(dirname "$0")/.."
readers="$(./scripts/install-readers.sh)"
mkdir -p out docs
cargo build --release -q -p lopin
target/release/lopin run two-blocks --window whole --rerun out/two-blocks.rrd >/dev/null
scratch="$(mktemp -d)"
export XDG_CONFIG_HOME="$scratch/config" XDG_DATA_HOME="$scratch/data" XDG_RUNTIME_DIR="$scratch/run"
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
"$readers/rerun" analytics disable >/dev/null
Xvfb :96 -screen 0 2000x1300x24 -nolisten tcp >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb 2>/dev/null || true' EXIT
export DISPLAY=:96
unset WAYLAND_DISPLAY
sleep 1
# the viewer may exit non-zero after saving the screenshot; the file is what counts
timeout 180 "$readers/rerun" --bind 127.0.0.1 out/two-blocks.rrd \
    --window-size 1600x1000 --screenshot-to "$scratch/shot.png" >"$scratch/viewer.log" 2>&1 || true
[ -s "$scratch/shot.png" ] || { echo "no screenshot; viewer log:"; tail -20 "$scratch/viewer.log"; exit 1; }
convert "$scratch/shot.png" -resize 1600x1000 docs/src/figures/rerun.png
echo "docs/src/figures/rerun.png written"
