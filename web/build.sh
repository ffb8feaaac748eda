#!/usr/bin/env bash
# Builds the workbench for the browser: the library compiled to WebAssembly (web/, profile
# `wasm`), bound by wasm-bindgen (the CLI's version must equal the crate's, pinned here and in
# web/Cargo.toml), and written into the book's sources:
#   book/src/owb-web/owb_web.js       wasm-bindgen's loader (a classic script: global wasm_bindgen)
#   book/src/owb-web/owb_web_wasm.js  the module itself, base64 in a classic script, so the book
#                                     works from any static host and opened as a local file
#                                     (browsers refuse to fetch a .wasm from file://)
#   book/src/owb-web/owb_web.wasm     the module as a file, fetched and compiled while it streams
#                                     in where the book is served
#   book/src/owb-web/owb_web_worker.js the Web Worker's source (loader + web/worker.js), a string
# Prints the sizes (the budget is 1 MB gzipped).
set -euo pipefail
cd "$(dirname "$0")/.."
WASM_BINDGEN_VERSION=0.2.130
rustup target add wasm32-unknown-unknown >/dev/null 2>&1 || true
if ! wasm-bindgen --version 2>/dev/null | grep -q "$WASM_BINDGEN_VERSION"; then
  # not --locked: the CLI's own lock file names a webpki-roots the registry no longer has
  cargo install wasm-bindgen-cli --version "$WASM_BINDGEN_VERSION"
fi
cargo build --locked -p owb-web --target wasm32-unknown-unknown --profile wasm
out=book/src/owb-web
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
wasm-bindgen --target no-modules --no-typescript --remove-name-section --remove-producers-section --out-dir "$tmp" \
  "${CARGO_TARGET_DIR:-target}/wasm32-unknown-unknown/wasm/owb_web.wasm"
mkdir -p "$out"
cp "$tmp/owb_web.js" "$out/owb_web.js"
cp "$tmp/owb_web_bg.wasm" "$out/owb_web.wasm"
{
  printf '// The workbench compiled to WebAssembly (web/build.sh), base64: loads from file:// too.\n'
  printf 'window.OWB_WASM_BASE64 = "'
  base64 -w0 "$out/owb_web.wasm"
  printf '";\n'
} > "$out/owb_web_wasm.js"
# the Web Worker's source (the loader and web/worker.js's message loop) as a string in a classic
# script: the page makes the worker from a Blob, which needs no fetch, so file:// works too
cat "$out/owb_web.js" web/worker.js > "$tmp/worker.js"
node -e 'const fs = require("fs"); process.stdout.write("// The Web Worker of the workbench (web/build.sh): its source as a string.\nwindow.OWB_WORKER_SOURCE = " + JSON.stringify(fs.readFileSync(process.argv[1], "utf8")) + ";\n");' "$tmp/worker.js" > "$out/owb_web_worker.js"
raw=$(stat -c %s "$out/owb_web.wasm")
gz=$(gzip -9c "$out/owb_web.wasm" | wc -c)
echo "owb_web.wasm: $raw bytes, $gz bytes gzipped (budget 1 MB gzipped)"
if [ "$gz" -gt 1000000 ]; then
  echo "the WebAssembly module is over its budget of 1 MB gzipped" >&2
  exit 1
fi
