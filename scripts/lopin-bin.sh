#!/usr/bin/env bash
# Prints the path of the `lopin` binary that the README's test command builds (`cargo test
# --release --workspace $LOPIN_FEATURES`), building it first if it is not built yet (after that
# command there is nothing to build). CI's steps after the tests run this binary instead of
# `cargo build -p lopin`: a build of one package resolves the dependencies' features without the
# other members and the dev-dependencies, so it would compile 74 crates (egui, eframe, parts of
# the rerun SDK, lopin-core) a second time.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck disable=SC2086  # LOPIN_FEATURES holds several arguments (CI: the mpi feature)
cargo test --release -q --workspace ${LOPIN_FEATURES:-} --no-run --message-format=json \
    | python3 -c '
import json, subprocess, sys
found = []
for line in sys.stdin:
    m = json.loads(line)
    t = m.get("target", {})
    # the binary itself, not its unit-test harness (also a "bin" target named lopin, listed
    # before or after it depending on build order)
    if (m.get("reason") == "compiler-artifact" and t.get("name") == "lopin"
            and t.get("kind") == ["bin"] and not m.get("profile", {}).get("test")):
        found.append(m["executable"])
if not found:
    sys.exit("lopin-bin: the workspace test build has no lopin binary")
exe = found[-1]
# a wrong pick would pass the smoke runs silently (a test harness takes any argument as a filter)
version = subprocess.run([exe, "--version"], capture_output=True, text=True).stdout
if not version.startswith("lopin "):
    sys.exit(f"lopin-bin: {exe} is not the lopin binary (--version printed {version!r})")
print(exe)
'
