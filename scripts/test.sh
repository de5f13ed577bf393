#!/usr/bin/env bash
# The whole test suite, from a fresh Debian machine: installs the software Vulkan driver and Xvfb
# the explorer's tests need and the independent readers the export tests check files with
# (meshio, the rerun tool) and gmsh (the meshes of assets/meshes/ and the polyhedral granular
# scenes), runs every test in an optimized build, then starts the real
# explorer in a window under Xvfb and checks its 3D view is drawn, and finally builds the web
# explorer (WebAssembly, dist/) and drives it in headless Chromium (scripts/test-web.sh), runs
# every shell block of the user guide's tutorials (scripts/tutorials.py) and builds the guide
# (scripts/build-docs.sh, mdBook).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-gui-deps.sh
./scripts/install-mpi.sh
gmsh="$(./scripts/install-gmsh.sh)"
if [ -n "$gmsh" ]; then export LOPIN_GMSH="$gmsh"; fi
readers="$(./scripts/install-readers.sh)"
export LOPIN_PYTHON="$readers/python" LOPIN_RERUN="$readers/rerun"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
chmod 700 "$XDG_RUNTIME_DIR"
# the `mpi` feature on: its tests run the binary under mpirun (app/tests/mpi.rs)
export LOPIN_FEATURES="--features lopin/mpi"
cargo test --release --workspace $LOPIN_FEATURES
# the smoke test runs the binary the tests ran (why: scripts/lopin-bin.sh)
LOPIN_BIN="$(./scripts/lopin-bin.sh)"
export LOPIN_BIN
# the Run command of the README runs this binary while no source is newer (scripts/lopin.sh)
echo "$LOPIN_BIN" > target/lopin-tested
./scripts/explorer-xvfb.sh smoke
./scripts/test-web.sh
python3 scripts/tutorials.py
./scripts/build-docs.sh
