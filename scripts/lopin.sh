#!/usr/bin/env bash
# Runs `lopin` with the given arguments (none: the explorer on two-blocks). After the README's
# test command this is the binary that command built and tested (it records its path in
# target/lopin-tested), as long as no source file is newer than it, so nothing is compiled
# again: a plain `cargo run -p lopin` resolves the dependencies' features without the other
# workspace members and the mpi feature, and would compile about 76 crates a second time.
# Otherwise (a fresh clone, or sources edited since) it builds and runs `lopin` with cargo.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
marker="$ROOT/target/lopin-tested"
if [ -f "$marker" ]; then
    exe="$(cat "$marker")"
    if [ -x "$exe" ]; then
        newer="$(cd "$ROOT" && find Cargo.toml Cargo.lock model core reference judge explorer app assets \
            -newer "$exe" -type f -print -quit)"
        if [ -z "$newer" ]; then
            exec "$exe" "$@"
        fi
    fi
fi
exec cargo run --release -q --manifest-path "$ROOT/Cargo.toml" -p lopin -- "$@"
