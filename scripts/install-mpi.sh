#!/usr/bin/env bash
# OpenMPI and the clang the `mpi` crate's bindings need (Debian packages), for `lopin`'s `mpi`
# feature and its tests under mpirun (app/tests/mpi.rs). Does nothing when mpirun and mpicc are
# there already.
set -euo pipefail
if command -v mpirun >/dev/null && command -v mpicc >/dev/null \
    && ls /usr/lib/llvm-*/lib/libclang*.so* >/dev/null 2>&1; then
    exit 0
fi
sudo=""
if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
# apt's output goes to a log, shown only when the install fails: one line when it works
log="$(mktemp)"
if ! { $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq \
    --no-install-recommends libopenmpi-dev openmpi-bin libclang-dev clang; } >"$log" 2>&1; then
    cat "$log" >&2
    echo "install-mpi: apt-get failed (above)" >&2
    exit 1
fi
rm -f "$log"
echo "installed: OpenMPI ($(mpirun --version 2>/dev/null | head -n 1)) and clang" >&2
