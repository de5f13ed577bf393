#!/usr/bin/env bash
# Installs gmsh, which meshes the .geo scripts of assets/meshes/ and the polyhedral granular
# material (`[granular_poly]`, `lopin mesh granular`) with tetrahedra: Debian's `gmsh` package
# where apt is available, else the PyPI wheel into target/gmsh-venv (its `gmsh` program is then
# printed, for LOPIN_GMSH). Prints nothing when gmsh is on the PATH already. Needs root (or sudo)
# for apt.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v gmsh >/dev/null 2>&1 && exit 0
if command -v apt-get >/dev/null 2>&1; then
    sudo=""
    [ "$(id -u)" -ne 0 ] && sudo=sudo
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -q >/dev/null
    $sudo apt-get install -y -q --no-install-recommends gmsh >/dev/null
    echo "installed: gmsh $(gmsh --version 2>&1)" >&2
    exit 0
fi
python3 -m venv target/gmsh-venv
target/gmsh-venv/bin/pip install -q gmsh
echo "$PWD/target/gmsh-venv/bin/gmsh"
