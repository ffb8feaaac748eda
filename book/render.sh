#!/usr/bin/env bash
# Renders chosen pages of the built book (book/book) to PNG with headless Chromium — Debian's
# `chromium` package, installed here if missing — so math, tables and figures can be looked at
# as a reader sees them. Usage: bash book/render.sh [page …] (default: a few chapters).
set -euo pipefail
cd "$(dirname "$0")"
if ! command -v chromium >/dev/null; then
  apt-get update -qq && apt-get install -y -qq chromium >/dev/null
fi
mkdir -p screenshots
pages=("$@")
[ ${#pages[@]} -gt 0 ] || pages=(gains polynomials multi-output kalman perfect)
for page in "${pages[@]}"; do
  chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1280,2400 \
    --virtual-time-budget=3000 --screenshot="screenshots/$page.png" "file://$PWD/book/$page.html" 2>/dev/null
  echo "screenshots/$page.png"
done
