#!/usr/bin/env bash
# What each command finishes within the default time budget (10 s): the whole `owb` process on
# dense random integer plants (entries −9…9, seed 1), orders 20, 40, 60, 80, 100, 150, 200; a
# command is not tried at larger orders once it ran out of budget or failed. Prints one line per
# run: command, order, seconds, and "ok", "budget", the error, or "too long" (a matrix whose
# text exceeds Linux's 128 KiB for one argument). The float commands take the comparison
# script's plants: `zoh` the integer A with B the random column and T = 1/(10n); `kalman` A,
# B = G = I, C the first n/2 states, unit noises; `dlqe` A/n (as in
# tests/bench/flint_compare.py --float) with the same C and unit noises; `optimal` the first
# two states measured, at orders 5 to 20, with A and with A/n (entries near 1, what an f64 gain
# can place; orders 10 to 30). By hand (not in CI);
# the README's "Commands" section reports a run.
#   bash tests/bench/within_budget.sh [path/to/owb]
set -uo pipefail
owb=${1:-target/release/owb}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$dir" <<'PY'
import random, sys
random.seed(1)
text = lambda rows: "[" + "; ".join(" ".join(r) for r in rows) + "]"
# `optimal`'s small orders drawn after the others: the larger plants stay those of earlier runs
for n in (20, 40, 60, 80, 100, 150, 200, 5, 8, 10, 12, 15, 25, 30):
    draw = lambda: [str(random.randint(-9, 9)) for _ in range(n)]
    a = [draw() for _ in range(n)]
    c, b = draw(), draw()
    files = {"a": text(a), "c": text([c]), "b": text([[x] for x in b]),
             # the float commands' plants: A/n, the identity, the first n/2 states measured
             "s": text([[f"{x}/{n}" if x != "0" else "0" for x in r] for r in a]),
             "i": text([["1" if i == j else "0" for j in range(n)] for i in range(n)]),
             "ik": text([["1" if i == j else "0" for j in range(n // 2)] for i in range(n // 2)]),
             "ck": text([["1" if i == j else "0" for j in range(n)] for i in range(n // 2)]),
             # `optimal`: the first two states measured
             "co": text([["1" if i == j else "0" for j in range(n)] for i in range(2)])}
    for name, content in files.items():
        open(f"{sys.argv[1]}/{name}{n}", "w").write(content)
PY
only=${ONLY:-}
commands=("observe" "canonical" "gain --repeated 1 --summary" "gain --repeated 1"
          "feedback --repeated 1" "discrete --poly" "discrete --deadbeat"
          "reduced --repeated 1" "detectable --repeated 1" "control" "perfect"
          "zoh" "kalman" "dlqe" "optimal" "optimal A/n")
echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
for cmd in "${commands[@]}"; do
  [ -n "$only" ] && [ "$cmd" != "$only" ] && continue
  orders="20 40 60 80 100 150 200"
  [ "$cmd" = optimal ] && orders="5 8 10 12 15 20"
  [ "$cmd" = "optimal A/n" ] && orders="10 12 15 20 25 30"
  for n in $orders; do
    case "$cmd" in
      feedback*) plant=(--a "$(cat "$dir/a$n")" --b "$(cat "$dir/b$n")") ;;
      # both gains designed from their polynomials: observer (s + 1)ⁿ, feedback (s + 2)ⁿ
      control) plant=(--a "$(cat "$dir/a$n")" --b "$(cat "$dir/b$n")" --c "$(cat "$dir/c$n")"
                      --observer-poly "(s + 1)^$n" --feedback-poly "(s + 2)^$n") ;;
      perfect) plant=(--a "$(cat "$dir/a$n")" --b "$(cat "$dir/b$n")" --c "$(cat "$dir/c$n")") ;;
      zoh) plant=(--a "$(cat "$dir/a$n")" --b "$(cat "$dir/b$n")" --period "1/$((10 * n))") ;;
      kalman) plant=(--a "$(cat "$dir/a$n")" --b "$(cat "$dir/i$n")" --c "$(cat "$dir/ck$n")"
                     --input-noise "$(cat "$dir/i$n")" --output-noise "$(cat "$dir/ik$n")") ;;
      # minimum-norm gains (J1) for (s + 1)ⁿ from the default 40 seeded starts, whose search
      # stops starting new ones after its own --time-limit (10 s)
      optimal) plant=(--a "$(cat "$dir/a$n")" --c "$(cat "$dir/co$n")" --repeated 1) ;;
      "optimal A/n") plant=(--a "$(cat "$dir/s$n")" --c "$(cat "$dir/co$n")" --repeated 1) ;;
      dlqe) plant=(--a "$(cat "$dir/s$n")" --c "$(cat "$dir/ck$n")" --qn "$(cat "$dir/i$n")"
                   --rn "$(cat "$dir/ik$n")") ;;
      *) plant=(--a "$(cat "$dir/a$n")" --c "$(cat "$dir/c$n")") ;;
    esac
    longest=0
    for word in "${plant[@]}"; do [ ${#word} -gt $longest ] && longest=${#word}; done
    if [ "$longest" -ge 131072 ]; then echo "$cmd | $n | | too long"; break; fi
    # a discrete design: every pole at z = 1/2
    run=$cmd
    [ "$cmd" = "discrete --poly" ] && run=discrete && plant+=(--poly "(z - 1/2)^$n")
    [ "$cmd" = "optimal A/n" ] && run=optimal
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
