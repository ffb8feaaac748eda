#!/usr/bin/env bash
# What each exact command finishes within the default time budget (10 s): the whole `owb`
# process on dense random integer plants (entries −9…9, seed 1), orders 20, 40, 60, 80, 100,
# 150, 200; a command is not tried at larger orders once it ran out of budget. Prints one line
# per run: command, order, seconds, and "ok" or "budget". By hand (not in CI); the README's
# "Commands" section reports a run.
#   bash tests/bench/within_budget.sh [path/to/owb]
set -uo pipefail
owb=${1:-target/release/owb}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$dir" <<'PY'
import random, sys
random.seed(1)
for n in (20, 40, 60, 80, 100, 150, 200):
    row = lambda: " ".join(str(random.randint(-9, 9)) for _ in range(n))
    open(f"{sys.argv[1]}/a{n}", "w").write("[" + "; ".join(row() for _ in range(n)) + "]")
    open(f"{sys.argv[1]}/c{n}", "w").write("[" + row() + "]")
    open(f"{sys.argv[1]}/b{n}", "w").write("[" + "; ".join(str(random.randint(-9, 9)) for _ in range(n)) + "]")
PY
only=${ONLY:-}
commands=("observe" "canonical" "gain --repeated 1 --summary" "gain --repeated 1"
          "feedback --repeated 1" "discrete --poly" "discrete --deadbeat"
          "reduced --repeated 1" "detectable --repeated 1" "control")
echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
for cmd in "${commands[@]}"; do
  [ -n "$only" ] && [ "$cmd" != "$only" ] && continue
  for n in 20 40 60 80 100 150 200; do
    case "$cmd" in
      feedback*) plant=(--a "$(cat "$dir/a$n")" --b "$(cat "$dir/b$n")") ;;
      # both gains designed from their polynomials: observer (s + 1)ⁿ, feedback (s + 2)ⁿ
      control) plant=(--a "$(cat "$dir/a$n")" --b "$(cat "$dir/b$n")" --c "$(cat "$dir/c$n")"
                      --observer-poly "(s + 1)^$n" --feedback-poly "(s + 2)^$n") ;;
      *) plant=(--a "$(cat "$dir/a$n")" --c "$(cat "$dir/c$n")") ;;
    esac
    # a discrete design: every pole at z = 1/2
    run=$cmd
    [ "$cmd" = "discrete --poly" ] && run=discrete && plant+=(--poly "(z - 1/2)^$n")
    start=$(date +%s.%N)
    # shellcheck disable=SC2086
    "$owb" $run "${plant[@]}" >/dev/null 2>"$dir/err"
    rc=$?
    took=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.2f}')" "$start" "$(date +%s.%N)")
    if grep -q "time budget" "$dir/err"; then verdict=budget; elif [ $rc -eq 0 ]; then verdict=ok; else verdict="exit $rc: $(head -c 120 "$dir/err")"; fi
    echo "$cmd | $n | $took s | $verdict"
    [ "$verdict" = ok ] || break
  done
done
