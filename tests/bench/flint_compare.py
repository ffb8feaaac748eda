#!/usr/bin/env python3
"""The user path against python-flint, on the same matrices in one run (not part of cargo test).

    cargo build --release && pip install python-flint && python3 tests/bench/flint_compare.py [n …]

For each order n: the dense random integer matrix of the criterion benchmarks (xorshift, seed 7,
entries in [−9, 9]), C = e1ᵀ, all observer poles at −1. Timed, best of three:
  * `owb gain --a A --c C --repeated 1 --method ackermann --json`, the whole process: parsing,
    the exact gain with every derivation step (O_n, det(sI − A), q_n, K, A − KC, the exact check
    of the achieved polynomial) and the JSON written out;
  * the same with --summary (no intermediate matrices);
  * python-flint's bare exact gain K = P(A) O_n⁻¹ e_n (fmpq_mat solve and Horner), nothing else;
  * python-flint's characteristic polynomial of A (fmpz_mat.charpoly), for the kernel table.
The gains are compared entry by entry.
"""
import json, subprocess, sys, time
from math import comb
from pathlib import Path

import flint

ROOT = Path(__file__).resolve().parents[2]
OWB = ROOT / "target" / "release" / "owb"


def dense_random(n, seed=7):
    mask = (1 << 64) - 1
    state = ((seed * 0x9E3779B97F4A7C15) & mask) | 1
    rows = []
    for _ in range(n):
        row = []
        for _ in range(n):
            state ^= (state << 13) & mask
            state ^= state >> 7
            state ^= (state << 17) & mask
            row.append(state % 19 - 9)
        rows.append(row)
    return rows


def best(f, runs=3):
    times, out = [], None
    for _ in range(runs):
        t = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t)
    return min(times), out


def owb_gain(a, n, *extra):
    text = "[" + "; ".join(" ".join(map(str, r)) for r in a) + "]"
    c = "[" + " ".join(["1"] + ["0"] * (n - 1)) + "]"
    args = [str(OWB), "gain", "--a", text, "--c", c, "--repeated", "1",
            "--method", "ackermann", "--json", *extra]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def flint_gain(a, n):
    aq = flint.fmpq_mat(a)
    row = flint.fmpq_mat(1, n, [1] + [0] * (n - 1))
    rows = [row]
    for _ in range(1, n):
        rows.append(rows[-1] * aq)
    o = flint.fmpq_mat(n, n, [x for r in rows for x in r.entries()])
    q = o.solve(flint.fmpq_mat(n, 1, [0] * (n - 1) + [1]))
    acc = flint.fmpq_mat(n, 1, [0] * n)
    for k in range(n, -1, -1):  # P(s) = (s + 1)^n, coefficient of s^k is C(n, k)
        acc = aq * acc + q * comb(n, k)
    return acc


def main():
    orders = [int(x) for x in sys.argv[1:]] or [20, 30, 60, 80]
    print("| n | owb gain --json (whole process) | with --summary | python-flint bare gain "
          "| python-flint charpoly | gains equal |")
    print("|---|---|---|---|---|---|")
    for n in orders:
        a = dense_random(n)
        t_owb, out = best(lambda: owb_gain(a, n))
        t_sum, _ = best(lambda: owb_gain(a, n, "--summary"))
        t_fl, k = best(lambda: flint_gain(a, n))
        t_cp, _ = best(lambda: flint.fmpz_mat(a).charpoly(), runs=20)
        equal = [str(x) for x in k.entries()] == [r[0] for r in out["gain"]]
        print(f"| {n} | {t_owb:.3f} s | {t_sum:.3f} s | {t_fl:.3f} s | {t_cp * 1e3:.2f} ms | {equal} |")


if __name__ == "__main__":
    main()
