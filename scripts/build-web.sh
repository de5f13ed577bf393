#!/usr/bin/env bash
# Builds the explorer for the browser into dist/ (index.html, lopin_web.js, lopin_web_bg.wasm,
# lopin_worker.js (the solver's Web Worker),
# build.json with the sizes), installing what it needs first (scripts/web-tools.sh). The wasm
# build uses Debian's rustc-web toolchain with std built from source, in its own target folder
# (target/web), so it never disturbs the native build. Serve dist/ with scripts/serve-web.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/web-tools.sh

TARGET=wasm32-unknown-unknown
OUT=dist
echo "web: cargo build --profile web-release -p lopin-web --target $TARGET (Debian rustc-web, build-std)"
mkdir -p target/web
# 128-bit SIMD (every current browser runs it): faer's kernels vectorize through pulp
RUSTC=/usr/bin/rustc RUSTDOC=/usr/bin/rustdoc RUSTC_BOOTSTRAP=1 \
    RUSTFLAGS="-C target-feature=+simd128" \
    CARGO_UNSTABLE_BUILD_STD=std,panic_abort \
    CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_LINKER=wasm-ld-22 \
    /usr/bin/cargo build --profile web-release -p lopin-web --target "$TARGET" --target-dir target/web \
    2>&1 | tee target/web/build.log
# no clippy in Debian's web toolchain: at least, the wasm-only code builds without warnings
# (dependencies' lints are capped, so any warning left is ours)
if grep -E '^warning' target/web/build.log | grep -v -E 'future version of Rust|future-incompat'; then
    echo "web: the wasm build has warnings (above)" >&2
    exit 1
fi
RAW="target/web/$TARGET/web-release/lopin_web.wasm"

# the same module, page, worker and script as dist/ was made from: dist/ stands (wasm-bindgen
# and wasm-opt take a minute or more)
SOURCE_SHA=$(cat "$RAW" index.html web/lopin_worker.js scripts/build-web.sh | sha256sum | cut -d' ' -f1)
if [ -f "$OUT/build.json" ] && [ -f "$OUT/lopin_web_bg.wasm" ] && [ -f "$OUT/lopin_web.js" ] &&
    grep -q "\"source_sha256\": \"$SOURCE_SHA\"" "$OUT/build.json"; then
    echo "web: $OUT/ is up to date (made from this build of the module, page and worker)"
else
rm -rf "$OUT.tmp"
mkdir -p "$OUT.tmp"
"$WEB_TOOLS/bin/wasm-bindgen" --target web --no-typescript --out-dir "$OUT.tmp" "$RAW"
BINDGEN_BYTES=$(stat -c %s "$OUT.tmp/lopin_web_bg.wasm")
echo "web: wasm-opt -O2"
node "$WEB_TOOLS/npm/node_modules/binaryen/bin/wasm-opt" -O2 \
    --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext \
    --enable-mutable-globals --enable-reference-types --enable-multivalue --enable-simd \
    "$OUT.tmp/lopin_web_bg.wasm" -o "$OUT.tmp/lopin_web_bg.opt.wasm"
mv "$OUT.tmp/lopin_web_bg.opt.wasm" "$OUT.tmp/lopin_web_bg.wasm"
cp index.html web/lopin_worker.js "$OUT.tmp/"
WASM_BYTES=$(stat -c %s "$OUT.tmp/lopin_web_bg.wasm")
GZIP_BYTES=$(gzip -9 -c "$OUT.tmp/lopin_web_bg.wasm" | wc -c)
JS_BYTES=$(stat -c %s "$OUT.tmp/lopin_web.js")
cat > "$OUT.tmp/build.json" <<JSON
{
  "commit": "$(git rev-parse --short HEAD 2>/dev/null || echo unknown)",
  "wasm_bytes_after_wasm_bindgen": $BINDGEN_BYTES,
  "wasm_bytes": $WASM_BYTES,
  "wasm_gzip_bytes": $GZIP_BYTES,
  "js_bytes": $JS_BYTES,
  "source_sha256": "$SOURCE_SHA"
}
JSON
rm -rf "$OUT"
mv "$OUT.tmp" "$OUT"
fi
read -r WASM_BYTES BINDGEN_BYTES GZIP_BYTES < <(python3 -c "import json, sys; d = json.load(open(sys.argv[1])); print(d['wasm_bytes'], d['wasm_bytes_after_wasm_bindgen'], d['wasm_gzip_bytes'])" "$OUT/build.json")
LIMIT=$((8 * 1024 * 1024))
python3 -c "import sys; w, b, g = map(int, sys.argv[1:]); print(f'web: dist/lopin_web_bg.wasm {w} bytes ({w / 2**20:.2f} MiB; {b} after wasm-bindgen, {g} gzipped), budget 8 MiB')" \
    "$WASM_BYTES" "$BINDGEN_BYTES" "$GZIP_BYTES"
if [ "$WASM_BYTES" -gt "$LIMIT" ]; then
    echo "web: the .wasm exceeds the 8 MiB budget" >&2
    exit 1
fi
