#!/usr/bin/env bash
# Benchmark of the web explorer in headless Chromium on two-blocks: LOADS page loads (default 3),
# each followed by MOVES friction-slider moves (default 8). Prints a table of page load -> first
# frame, -> first fields drawn, -> first converged solve, and slider change -> converged warm
# re-solve (as the app measures it, and click -> converged state seen in the page). Pass
# --no-build to reuse dist/. Software rendering (SwiftShader) and a shared machine: compare
# numbers within one run.
set -euo pipefail
cd "$(dirname "$0")/.."
export WEB_BROWSER=1
if [ "${1:-}" != "--no-build" ]; then
    ./scripts/build-web.sh
fi
source scripts/web-tools.sh
OUT="${WEB_BENCH_OUT:-target/web-bench}"
rm -rf "$OUT"
mkdir -p "$OUT"
serve_dist "$OUT/server.log"
for i in $(seq "${LOADS:-3}"); do
    node web/e2e/explorer.cjs "http://127.0.0.1:$PORT/${WEB_QUERY:-}" "$OUT/load-$i" "${MOVES:-8}" >/dev/null
done
python3 - "$OUT" <<'PY'
import glob, json, statistics, sys
runs = [json.load(open(f)) for f in sorted(glob.glob(sys.argv[1] + "/load-*/web-e2e.json"))]
build = json.load(open("dist/build.json"))
def row(name, xs, unit):
    xs = sorted(xs)
    print(f"| {name} | {len(xs)} | {statistics.median(xs):.{3 if unit == 's' else 0}f} | "
          f"{xs[0]:.{3 if unit == 's' else 0}f} | {xs[-1]:.{3 if unit == 's' else 0}f} | {unit} |")
print(f"web explorer, two-blocks, headless Chromium (SwiftShader WebGL2), solver in its "
      f"{runs[0].get('solver', '?')}; "
      f".wasm {build['wasm_bytes']} bytes ({build['wasm_gzip_bytes']} gzipped)\n")
print("| measure | n | median | min | max | unit |")
print("|---|---|---|---|---|---|")
row("page load -> first frame", [r["first_frame_ms"] for r in runs], "ms")
row("page load -> first fields drawn", [r["first_fields_ms"] for r in runs], "ms")
row("page load -> first converged solve (cold)", [r["first_converged_ms"] for r in runs], "ms")
row("cold solve iterations", [r["first_solve"]["iterations"] for r in runs], "it")
row("first solve: the solver's setup (build, factorize)", [r["first_solve"]["setup_s"] for r in runs], "s")
row("first solve: the solver's wall time", [r["first_solve"]["solver_s"] for r in runs], "s")
row("first solve: of which engine stages", [r["first_solve"]["engine_s"] for r in runs], "s")
moves = [m for r in runs for m in r["moves"]]
row("slider change -> converged warm re-solve (app)", [m["app_latency_s"] for m in moves], "s")
row("slider click -> converged state in the page", [m["click_to_converged_in_dom_s"] for m in moves], "s")
row("the solver's wall time of the re-solve (worker)", [m["solver_s"] for m in moves], "s")
row("of which engine stages (local + linear)", [m["engine_s"] for m in moves], "s")
row("warm re-solve iterations", [m["iterations"] for m in moves], "it")
PY
