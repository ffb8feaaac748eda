#!/usr/bin/env bash
# A fuzzing campaign, by hand (not in CI): builds the targets (nightly, cargo-fuzz), seeds the
# corpora from the project's files (seed_corpus.py), then runs each target given (default: all
# six) to RUNS executions with a 1 s timeout on inputs up to 1 KB. Findings land in
# fuzz/artifacts/<target>/; copy each to fuzz/regressions/<target>/ once fixed, and
# `cargo test` replays it. One target at a time: a parallel build or a second campaign on a
# 2-core machine turns slow moments into spurious timeouts.
#   bash fuzz/campaign.sh [target…]       RUNS=1000000 by default
set -euo pipefail
cd "$(dirname "$0")"
RUNS=${RUNS:-1000000}
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(syntax answers exercise worked_example book cli)
cargo fuzz --version 2>/dev/null | grep -q "0\.12\.0" || cargo install cargo-fuzz --version 0.12.0 --locked
cargo +nightly fuzz build -O -s none
python3 seed_corpus.py
bin=target/x86_64-unknown-linux-gnu/release
for t in "${targets[@]}"; do
  mkdir -p "artifacts/$t"
  start=$(date +%s)
  "$bin/$t" "corpus/$t" -dict=cli.dict -runs="$RUNS" -max_len=1024 -timeout=1 \
    -rss_limit_mb=2048 -close_fd_mask=1 -print_final_stats=1 \
    -artifact_prefix="artifacts/$t/" 2>&1 | tail -n 25 > "artifacts/$t.log" || true
  echo "$t: $(( $(date +%s) - start )) s, $(ls "artifacts/$t" | wc -l) artifact(s)," \
    "$(grep -o 'stat::number_of_executed_units: *[0-9]*' "artifacts/$t.log" | grep -o '[0-9]*$') executions"
done
