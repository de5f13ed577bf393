#!/usr/bin/env bash
# Starts the real `lopin` binary in a real window under Xvfb (software rendering) and either
#   smoke [SCENE]   : waits for the window, takes a screenshot (out/explorer-smoke.png) and
#                     checks that the 3D view is drawn (enough colormap-coloured pixels, not just
#                     the background); without SCENE, `lopin` as the README starts it;
#   measure [SCENE] : runs `lopin view SCENE --measure` (default two-blocks; SCENE may be a result
#                     folder; a run folder with stored fields (`lopin run --out DIR --fields`) is
#                     measured orbiting the camera and scrubbing the time steps: first picture,
#                     frame interval, time to a step's picture, peak memory):
#                     time from the start to the first converged picture, then stays idle while the
#                     background study stores the friction slider's range, then moves the
#                     slider 8 times (stored values and values between them); time to the
#                     first and to the converged picture of each move, frame intervals idle /
#                     background study / re-solving; prints the JSON
#                     (out/explorer-measure.json) and a summary table.
# LOPIN_BIN: the `lopin` binary to run (default: built here with LOPIN_FEATURES).
# Needs: xvfb xauth mesa-vulkan-drivers libvulkan1 imagemagick xdotool (scripts/install-gui-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-smoke}"
scene="${2:-}"
mkdir -p out
# the binary: $LOPIN_BIN where the caller has one (the test command passes the one its test build
# made, scripts/lopin-bin.sh, so nothing is compiled twice), else built here
if [ -n "${LOPIN_BIN:-}" ]; then
    bin="$LOPIN_BIN"
else
    # shellcheck disable=SC2086  # LOPIN_FEATURES holds several arguments (CI: the mpi feature)
    cargo build --release -q -p lopin ${LOPIN_FEATURES:-}
    bin=target/release/lopin
fi

display=:97
Xvfb "$display" -screen 0 1600x1000x24 -nolisten tcp -extension Composite >/tmp/lopin-xvfb.log 2>&1 &
xvfb=$!
app=""
cleanup() {
    [ -n "$app" ] && kill "$app" 2>/dev/null || true
    kill "$xvfb" 2>/dev/null || true
}
trap cleanup EXIT
export DISPLAY="$display"
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR="$(mktemp -d)"
    export XDG_RUNTIME_DIR
fi
unset WAYLAND_DISPLAY
for _ in $(seq 50); do xdotool getdisplaygeometry >/dev/null 2>&1 && break; sleep 0.1; done

if [ "$mode" = measure ]; then
    timeout "${LOPIN_MEASURE_TIMEOUT:-300}" "$bin" view "${scene:-two-blocks}" --measure out/explorer-measure.json >/dev/null
    python3 - out/explorer-measure.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
def row(name, key, scale=1.0, unit="s"):
    s = d[key]
    print(f"| {name} ({unit}) | {s['count']} | {s['median'] * scale:.3f} | {s['p90'] * scale:.3f} | {s['max'] * scale:.3f} |")
if "scrubs" in d:
    # a run opened from its stored fields: orbit, scrub, memory
    print(f"open → first picture: {d['open_to_first_picture_s']:.2f} s (reading the folder included)")
    print(f"surface triangles: {d['triangles']}")
    mem = d.get("peak_memory_bytes")
    if mem is not None:
        print(f"peak resident memory: {mem / 2**30:.2f} GiB")
    print("| | n | median | p90 | max |")
    print("|---|---|---|---|---|")
    row("frame interval while the camera orbits", "orbit_frame_interval_s")
    row("scrub → mesh of the new step built", "scrub_built_s")
    row("scrub → picture of the new step presented", "scrub_picture_s")
    sys.exit(0)
o = d.get("open_to_first_converged_s")
if o is not None:
    print(f"open → first converged picture: {o:.2f} s (loading the scene or folder included)")
print(f"background study: {d['study_wait_s']:.1f} s idle before the moves")
print("| | n | median | p90 | max |")
print("|---|---|---|---|---|")
row("slider move → first picture of the new value, presented", "first_picture_s")
row("slider move → first picture built", "first_picture_built_s")
row("slider move → converged picture, all moves", "converged_picture_s")
row("slider move → converged picture, stored values", "converged_picture_stored_s")
row("slider move → converged picture, refined values", "converged_picture_refined_s")
row("frame interval idle", "frame_interval_idle_s")
row("frame interval while the background study solves", "frame_interval_background_study_s")
row("frame interval while re-solving", "frame_interval_while_solving_s")
row("UI-thread work per frame, background study", "ui_thread_ms_per_frame_background_study", 1.0, "ms")
row("eframe's time per frame outside acquire and present, idle", "frame_cpu_ms_idle", 1.0, "ms")
print()
print("| f | stored | start | iterations | first picture (s) | converged picture (s) |")
print("|---|---|---|---|---|---|")
for m in d["moves"]:
    f = lambda x: "—" if x is None else f"{x:.3f}"
    b = m.get("between")
    start = f"{b[0]:.3f}–{b[1]:.3f}" if b else f(m['start'])
    print(f"| {m['value']:.3f} | {m['stored']} | {start} | {m['iterations']} | {f(m['first_picture_s'])} | {f(m['converged_picture_s'])} |")
PY
    exit 0
fi

if [ -n "$scene" ]; then
    "$bin" view "$scene" >/tmp/lopin-explorer.log 2>&1 &
else
    "$bin" >/tmp/lopin-explorer.log 2>&1 &
fi
app=$!
if ! timeout 60 xdotool search --sync --name "Lopin" >/dev/null; then
    echo "smoke: no Lopin window within 60 s"; cat /tmp/lopin-explorer.log; exit 1
fi
# the first solve of two-blocks converges in well under a second; give software rendering time
shot=out/explorer-smoke.png
ok=0
frac=""
# retried each second while the first picture comes: only the outcome is printed
for attempt in $(seq 30); do
    sleep 1
    kill -0 "$app" 2>/dev/null || { echo "smoke: lopin exited"; cat /tmp/lopin-explorer.log; exit 1; }
    /usr/bin/import -window root "$shot"
    # 3D view: between the 250 px left panel and the 340 px right panel
    # the coloured fraction, printed as a percentage; the status says whether it is enough (a
    # failed capture is retried like a blank one)
    if frac="$(/usr/bin/convert "$shot" -crop 500x400+420+220 +repage -depth 8 rgb:- | python3 -c '
import sys
d = sys.stdin.buffer.read()
n = len(d) // 3
coloured = sum(1 for i in range(0, 3 * n, 3) if max(d[i:i+3]) - min(d[i:i+3]) > 40)
f = coloured / max(n, 1)
print(f"{f:.1%}")
sys.exit(0 if f > 0.05 else 1)')"; then
        ok=1
        break
    fi
done
if [ "$ok" != 1 ]; then
    echo "smoke: the 3D view stayed blank (${frac:-none} of it coloured after 30 s)"
    cat /tmp/lopin-explorer.log
    exit 1
fi
echo "smoke: $frac of the 3D view is colormap-coloured, after $attempt s"
kill -0 "$app" || { echo "smoke: lopin exited"; exit 1; }
echo "smoke: screenshot in $shot"
