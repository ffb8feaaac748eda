#!/usr/bin/env bash
# The book's preprocessor: the workbench's mdbook-owb (`cargo build --release --bins`), from
# CARGO_TARGET_DIR when it is set, else from the repository's target/.
here="$(cd "$(dirname "$0")" && pwd)"
exec "${CARGO_TARGET_DIR:-$here/../target}/release/mdbook-owb" "$@"
