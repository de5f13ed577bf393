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
$sudo apt-get update -qq >&2
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    libopenmpi-dev openmpi-bin libclang-dev clang >&2
