#!/usr/bin/env bash
# The independent readers the export tests use: meshio (VTU) and the `rerun` command-line tool
# of the Python package rerun-sdk at exactly the rerun crate's version, and SciPy (an independent
# shock response spectrum), in a virtual environment under target/readers-venv (reused when
# already complete). Prints the environment's bin folder.
set -euo pipefail
cd "$(dirname "$0")/.."
RERUN_VERSION="$(sed -n 's/^rerun = { version = "=\([0-9.]*\)".*/\1/p' app/Cargo.toml)"
[ -n "$RERUN_VERSION" ] || { echo "install-readers: cannot read the rerun version from app/Cargo.toml" >&2; exit 1; }
VENV=target/readers-venv
STAMP="$VENV/.lopin-readers-$RERUN_VERSION-scipy"
if [ ! -f "$STAMP" ]; then
  rm -rf "$VENV"
  python3 -m venv "$VENV" >&2
  "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check \
    "rerun-sdk==$RERUN_VERSION" "meshio==5.3.5" "numpy<3" "scipy==1.17.1" >&2
  touch "$STAMP"
fi
echo "$(pwd)/$VENV/bin"
