#!/usr/bin/env bash
# Builds the user guide (docs/, an mdBook) into docs/book/, installing mdBook first if it is
# missing (cargo install, cached outside the repository like the web tools). The book's links
# are checked by app/tests/user_guide.rs; mdBook itself refuses a table of contents naming a
# page that does not exist.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
TOOLS="${LOPIN_DOC_TOOLS:-$HOME/.cache/lopin-doc-tools}"
MDBOOK_VERSION=0.5.4
if ! "$TOOLS/bin/mdbook" --version 2>/dev/null | grep -qx "mdbook v$MDBOOK_VERSION"; then
    echo "docs: cargo install mdbook $MDBOOK_VERSION (a minute or two, once)"
    cargo install -q mdbook --version "=$MDBOOK_VERSION" --no-default-features --root "$TOOLS"
fi
rm -rf "$ROOT/docs/book"
if ! out="$("$TOOLS/bin/mdbook" build "$ROOT/docs" 2>&1)"; then
    echo "$out" >&2
    echo "docs: mdbook build failed" >&2
    exit 1
fi
# a warning (a page it could not render, a broken include) fails the build too
if echo "$out" | grep -E "WARN|ERROR" >&2; then
    echo "docs: mdbook build warned" >&2
    exit 1
fi
test -f "$ROOT/docs/book/index.html" || { echo "docs: mdbook build wrote no docs/book/index.html" >&2; exit 1; }
pages=$(find "$ROOT/docs/book" -name '*.html' | wc -l)
echo "docs: the user guide is in docs/book/ ($pages pages)"
