#!/usr/bin/env bash
# Ships KaTeX's stylesheet, fonts and script with the book (no CDN at reading time). The version matches
# the KaTeX bundled in mdbook-katex 0.10.0 (katex-rs 0.4.6: KaTeX 0.16.4). Taken from the npm
# registry, pinned.
set -euo pipefail
cd "$(dirname "$0")"
KATEX_VERSION=0.16.4
# The stylesheet goes to book/katex/ (book.toml's additional-css, relative to the book root);
# the fonts to src/katex/fonts/, which mdBook copies beside it in the output (katex/fonts/).
if [ -f katex/katex.min.css ] && [ -f src/katex/katex.min.js ] && grep -q "$KATEX_VERSION" src/katex/VERSION 2>/dev/null; then
  exit 0
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
(cd "$tmp" && npm pack --silent "katex@$KATEX_VERSION" >/dev/null)
tar -xzf "$tmp/katex-$KATEX_VERSION.tgz" -C "$tmp"
rm -rf src/katex katex
mkdir -p src/katex katex
cp "$tmp/package/dist/katex.min.css" katex/
cp -r "$tmp/package/dist/fonts" src/katex/
# the script typesets the feedback and derivations the browser computes (owb-web/owb.js)
cp "$tmp/package/dist/katex.min.js" src/katex/
echo "$KATEX_VERSION" > src/katex/VERSION
