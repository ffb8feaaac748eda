#!/usr/bin/env python3
"""Writes `src/bin/owb.text-order`: the functions `owb` runs, in the order the linker lays them
out (build.rs passes the list to LLD where it is the linker).

Each request below runs once under Valgrind's callgrind (names left mangled, as the linker
knows them). The list gives first the functions `owb --version` runs (every command's start),
then, request by request, the functions that request runs and none before it did, each
request's in the order callgrind names them — so the code of one command lies together, in
few of the 64 KiB windows the kernel maps at a time. The requests come in the order of the
benchmarks' tightest targets at small orders, on the benchmarks' own plants (`flint_compare.py`'s
dense random A, B = e1, C = e1ᵀ): its 10-state `gain --summary` first (issue 31's ≤ 2× FLINT),
then `zoh`, `observe`, `canonical`, and then every command on a 2-state and a 10-state plant,
text and JSON, `--help` and `verify`.

By hand (not in CI: Valgrind is not among CI's tools), after a change that moves much code, or
a new compiler or dependencies (their names carry hashes that change): about 40 seconds.

    cargo build --release && python3 tests/bench/text_order.py [target/release/owb]

A stale list costs speed, never correctness: names the program no longer has are skipped, and
the machine code is the same in any order. `--check` prints how many of the list's names the
program has, and the page faults of `owb --version` and of the 10-state `gain` benchmark,
instead of writing.
"""
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # flint_compare's plants

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LIST = os.path.join(ROOT, "src", "bin", "owb.text-order")


def plant(n):
    """The benchmarks' plant of order n (`flint_compare.py`'s dense random A, seed 7), its float
    form A/n, B = e1, C = e1ᵀ and the identity, as text."""
    from flint_compare import dense_random, matrix_text
    a = dense_random(n)
    identity = [[int(i == j) for j in range(n)] for i in range(n)]
    return {
        "a": matrix_text(a),
        "s": matrix_text([[f"{x}/{n}" if x else "0" for x in r] for r in a]),
        "b": matrix_text([[row[0]] for row in identity]),
        "c": matrix_text([identity[0]]),
        "i": matrix_text(identity),
    }


def requests():
    p = plant(10)
    # the benchmarks' own requests at n = 10 first (flint_compare.py)
    out = [
        ["gain", "--a", p["a"], "--c", p["c"], "--repeated", "1", "--method", "ackermann",
         "--summary", "--json"],
        ["gain", "--a", p["a"], "--c", p["c"], "--repeated", "1", "--summary"],
        ["zoh", "--a", p["s"], "--b", p["b"], "--period", "1/10", "--json"],
        ["observe", "--a", p["a"], "--c", p["c"], "--json"],
        ["canonical", "--a", p["a"], "--c", p["c"], "--json"],
    ]
    for n in (2, 10):
        p = plant(n)
        pair = ["--a", p["a"], "--c", p["c"]]
        per_plant = [
            ["observe", *pair],
            ["canonical", *pair],
            ["gain", *pair, "--repeated", "1"],
            ["gain", *pair, "--repeated", "1", "--summary"],
            ["feedback", "--a", p["a"], "--b", p["b"], "--repeated", "1"],
            ["discrete", *pair, "--deadbeat"],
            ["discrete", *pair, "--poles", ",".join(["1/2"] * n)],
            ["reduced", *pair, "--repeated", "1"],
            ["detectable", *pair, "--repeated", "1"],
            ["control", "--a", p["a"], "--b", p["b"], "--c", p["c"],
             "--controller-repeated", "1", "--observer-repeated", "2"],
            ["zoh", "--a", p["s"], "--b", p["b"], "--period", "1/10"],
            ["dlqe", "--a", p["s"], "--c", p["c"], "--qn", p["i"], "--rn", "[1]"],
            ["kalman", "--a", p["s"], "--b", p["i"], "--c", p["c"], "--input-noise", p["i"],
             "--output-noise", "[1]"],
        ]
        for r in per_plant:
            out += [r, r + ["--json"]]
    return out + [["--help"], ["verify"], ["check", "--help"], ["exercise", "--help"]]


# Code Valgrind cannot run (it has no AVX-512), laid out beside the sibling it runs in its
# place: the AVX-512 product tiles after the AVX2 ones (`linalg/gemm.rs`).
SIBLINGS = [(re.compile(r"4gemm16blocked_avx2_fma"), re.compile(r"4gemm(6avx512|14blocked_avx512)"))]


def with_siblings(owb, order):
    """`order` with, after each name a sibling rule names, the program's functions the rule
    adds (those not listed yet)."""
    nm = subprocess.run(["nm", owb], capture_output=True, text=True, check=True).stdout
    symbols = [line.split()[-1] for line in nm.splitlines() if line.split()]
    out = dict.fromkeys(order)
    result = {}
    for name in order:
        result[name] = None
        for trigger, sibling in SIBLINGS:
            if trigger.search(name):
                result.update(dict.fromkeys(
                    s for s in symbols if sibling.search(s) and s not in out and s not in result))
    return list(result)


def functions(owb, args, out_file):
    subprocess.run(["valgrind", "--tool=callgrind", "--demangle=no",
                    f"--callgrind-out-file={out_file}", owb, *args],
                   capture_output=True, check=False)
    names = {}  # in callgrind's order (a dict keeps it)
    with open(out_file, encoding="utf-8", errors="replace") as f:
        for line in f:
            m = re.match(r"^c?fn=\(\d+\) (\S+)$", line.strip())
            # callgrind marks a recursive call's level with 'N after the name
            name = m and re.sub(r"'\d+$", "", m.group(1))
            if name and (name.startswith("_ZN") or name.startswith("_R")):
                names[name] = None
    return list(names)


def faults(owb, args):
    """`perf stat`'s count of the page faults of one run (owb's output captured: owb takes a
    standard output opened read-write on /dev/null, as `subprocess.DEVNULL` is, for a closed
    one and stops)."""
    try:
        r = subprocess.run(["perf", "stat", "-x,", "-e", "page-faults", owb, *args],
                           capture_output=True, text=True, check=False)
    except FileNotFoundError:
        return "(no perf)"
    return r.stderr.strip().splitlines()[-1].split(",")[0]


def check(owb):
    listed = open(LIST, encoding="utf-8").read().split()
    nm = subprocess.run(["nm", owb], capture_output=True, text=True, check=True).stdout
    present = {line.split()[-1] for line in nm.splitlines() if line.split()}
    print(f"{sum(n in present for n in listed)} of the list's {len(listed)} names are in {owb}")
    print(f"page faults: --version {faults(owb, ['--version'])}, the 10-state gain benchmark "
          f"{faults(owb, requests()[0])}")


def main():
    args = [a for a in sys.argv[1:] if a != "--check"]
    owb = args[0] if args else os.path.join(ROOT, "target", "release", "owb")
    if "--check" in sys.argv:
        check(owb)
        return
    with tempfile.TemporaryDirectory() as tmp:
        out_file = os.path.join(tmp, "callgrind.out")
        order = dict.fromkeys(functions(owb, ["--version"], out_file))
        first = len(order)
        for r in requests():
            order.update(dict.fromkeys(n for n in functions(owb, r, out_file) if n not in order))
    order = with_siblings(owb, list(order))
    with open(LIST, "w", encoding="utf-8") as f:
        f.write("\n".join(order) + "\n")
    print(f"{first} functions at start, {len(order) - first} more: {LIST}")


if __name__ == "__main__":
    main()
