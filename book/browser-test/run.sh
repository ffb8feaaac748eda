#!/usr/bin/env bash
# The course book in a real browser (Debian's Chromium, playwright-core from npm, pinned in
# package-lock.json; no browser download). Needs the built book (mdbook build book, after
# web/build.sh) and target/release/owb. Installs Chromium with apt-get when it is missing.
set -euo pipefail
cd "$(dirname "$0")"
if ! command -v chromium >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ]; then apt=(apt-get); else apt=(sudo apt-get); fi
  DEBIAN_FRONTEND=noninteractive "${apt[@]}" update -q >/dev/null
  DEBIAN_FRONTEND=noninteractive "${apt[@]}" install -y -q --no-install-recommends chromium >/dev/null
fi
chromium --version
npm ci --no-audit --no-fund --silent
node test.mjs
