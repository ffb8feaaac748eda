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

    python3 tests/bench/flint_compare.py --same-work [n …]

The fair table (issue 31): FLINT doing the computation owb does, not a textbook one, and CPU time
rather than wall time. For each command, owb's CPU time is the whole process's (user + system,
both threads of its multimodular characteristic polynomial counted), less owb's process floor
(the CPU time of `owb --version`); FLINT's is the CPU time of the same steps in-process:
  * gain: integer O_n, det(sI − A), one solve O_n q = e_n, Horner on integers with one
    denominator (K = P(A) x / d), and the rank-one check det(sI − A + KC) = det(sI − A) +
    C adj(sI − A) K from O_n K (one polynomial product), compared with P(s);
  * observe: integer O_n, its determinant and rank;
  * canonical: both procedures — T⁻¹ = Mᵀ O_n (M the Toeplitz matrix of det(sI − A)), T its
    inverse, A_o = T⁻¹ A T, C_o = C T; and t_n = O_n⁻¹ e_n, t_(k−1) = A t_k — compared;
  * feedback (B = e1, u = −Kx): the dual gain problem on (Aᵀ, e1ᵀ), the same steps and check;
  * discrete --deadbeat / --poles 1/2 …: the gain steps for P(z) = zⁿ / (z − 1/2)ⁿ and the check
    (the single-output error matrix is cyclic, so the dead-beat steps are n);
  * reduced (C = e1ᵀ): the gain of (A22, A12) for (s + 1)^(n−1), its check, F = A22 − L A12 and
    G = A21 − L A11 + F L;
  * detectable: the rank of O_n (an observable plant), then the gain and its check.
`--only feedback,reduced` restricts the commands (by their first word).
Best of five (min CPU time each side). The load average is printed with the table.
"""
import json, os, resource, subprocess, sys, time
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


def matrix_text(a):
    return "[" + "; ".join(" ".join(map(str, r)) for r in a) + "]"


def owb_cpu(args):
    """CPU seconds (user + system) of one owb process, and its standard output."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([str(OWB), *args], check=True, capture_output=True, text=True).stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out


def best_cpu(f, runs=5):
    times, out = [], None
    for _ in range(runs):
        t, out = f()
        times.append(t)
    return min(times), out


def in_process(f):
    def timed():
        t = time.process_time()
        out = f()
        return time.process_time() - t, out
    return timed


def observability(a, n, c=None):
    """Integer O_n = [C; CA; …] with C = e1ᵀ, or the integer row c."""
    az = flint.fmpz_mat(a)
    rows = [flint.fmpz_mat(1, n, c if c is not None else [1] + [0] * (n - 1))]
    for _ in range(1, n):
        rows.append(rows[-1] * az)
    return az, flint.fmpz_mat(n, n, [x for r in rows for x in r.entries()])


def flint_gain_same_work(a, n, c=None, p=None, scale=1):
    """K with det(sI − A + KC) = P(s)/scale for the integer polynomial P (lowest power first;
    default (s + 1)^n), C = e1ᵀ or the integer row c: owb's fraction-free steps and its check."""
    p = p if p is not None else [comb(n, k) for k in range(n + 1)]
    az, o = observability(a, n, c)
    chi = az.charpoly()  # det(sI − A), integer
    q = o.solve(flint.fmpz_mat(n, 1, [0] * (n - 1) + [1]))  # fmpq_mat
    d = flint.fmpz(1)
    for x in q.entries():
        d = d.lcm(x.q)
    x = flint.fmpz_mat(n, 1, [int(v * d) for v in q.entries()])
    acc = flint.fmpz_mat(n, 1, [0] * n)
    for k in range(n, -1, -1):  # Horner on integers, one denominator
        acc = az * acc + x * p[k]
    d = d * scale
    # the rank-one check: m_j = C A^j K = (O_n K)_j, and C adj(sI − A) K is the polynomial part
    # of det(sI − A) · Σ m_j s^(−j−1): one product of integer polynomials
    m = (o * acc).entries()
    nu = flint.fmpz_poly([m[n - 1 - i] for i in range(n)])  # Σ m_j s^(n−1−j)
    prod = chi * nu
    coeffs = [prod[k] for k in range(n, 2 * n)]
    achieved = chi * d + flint.fmpz_poly(coeffs)
    desired = flint.fmpz_poly(p) * (d // scale)
    assert achieved == desired, "the rank-one check failed"
    return [flint.fmpq(v, d) for v in acc.entries()]


def transpose(a):
    return [list(r) for r in zip(*a)]


def flint_feedback_same_work(a, n):
    """u = −Kx with B = e1: the observer gain of (Aᵀ, e1ᵀ), transposed (the dual problem)."""
    return flint_gain_same_work(transpose(a), n)


def flint_reduced_same_work(a, n):
    """Gopinath with C = e1ᵀ: the gain L of A22 − L A12 placing (s + 1)^(n−1), then the
    reduced observer's matrices F = A22 − L A12 and G = A21 − L A11 + F L."""
    m = n - 1
    a22 = [r[1:] for r in a[1:]]
    a12 = a[0][1:]
    l = flint_gain_same_work(a22, m, c=a12)
    lq = flint.fmpq_mat(m, 1, l)
    f = flint.fmpq_mat(a22) - lq * flint.fmpq_mat(1, m, a12)
    g = flint.fmpq_mat(m, 1, [r[0] for r in a[1:]]) - lq * a[0][0] + f * lq
    return l, f, g


def flint_deadbeat_same_work(a, n):
    """Dead-beat: P(z) = zⁿ, the same steps and check (the single-output error matrix is cyclic,
    so its minimal polynomial is zⁿ and the steps are n)."""
    return flint_gain_same_work(a, n, p=[0] * n + [1])


def flint_discrete_half_same_work(a, n):
    """Every pole at z = 1/2: 2ⁿ P(z) = (2z − 1)ⁿ on integers, one more denominator."""
    p = [comb(n, k) * 2 ** k * (-1) ** (n - k) for k in range(n + 1)]
    return flint_gain_same_work(a, n, p=p, scale=2 ** n)


def flint_detectable_same_work(a, n):
    """An observable plant: the rank of O_n decides detectability (every mode observable), then
    the gain for the whole (observable) plant and its check."""
    _, o = observability(a, n)
    assert o.rank() == n
    return flint_gain_same_work(a, n)


def flint_observe_same_work(a, n):
    _, o = observability(a, n)
    return o.det(), o.rank()


def flint_canonical_same_work(a, n):
    az, o = observability(a, n)
    chi = az.charpoly()
    coeff = [chi[n - k] for k in range(n)]  # 1, a_1, …, a_(n−1)
    m = flint.fmpz_mat(n, n, [coeff[j - i] if j >= i else 0 for i in range(n) for j in range(n)])
    t_inv = m.transpose() * o  # integer
    t = flint.fmpq_mat(t_inv).inv()
    aq = flint.fmpq_mat(az)
    a_o = flint.fmpq_mat(t_inv) * aq * t
    c_o = flint.fmpq_mat(1, n, [1] + [0] * (n - 1)) * t
    # Stoustrup's procedure: t_n = O_n⁻¹ e_n, t_(k−1) = A t_k
    cols = [o.solve(flint.fmpz_mat(n, 1, [0] * (n - 1) + [1]))]
    for _ in range(1, n):
        cols.append(aq * cols[-1])
    cols.reverse()
    t2 = flint.fmpq_mat(n, n, [cols[j][i, 0] for i in range(n) for j in range(n)])
    assert t2 == t, "the two procedures differ"
    return a_o, c_o


def same_work(orders, only=()):
    floor, _ = best_cpu(lambda: owb_cpu(["--version"]), runs=20)
    load = os.getloadavg()
    print(f"owb's process floor (owb --version): {floor * 1e3:.2f} ms CPU; "
          f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; "
          f"python-flint {flint.__version__}; {os.cpu_count()} cores")
    print()
    print("| command | n | owb CPU − floor | FLINT same work (CPU) | ratio |")
    print("|---|---|---|---|---|")
    for n in orders:
        a = dense_random(n)
        at, c = matrix_text(a), "[" + " ".join(["1"] + ["0"] * (n - 1)) + "]"
        b = "[" + "; ".join(["1"] + ["0"] * (n - 1)) + "]"
        half = ", ".join(["1/2"] * n)
        cases = [
            ("gain --summary", ["gain", "--a", at, "--c", c, "--repeated", "1", "--method",
                                "ackermann", "--summary", "--json"], flint_gain_same_work),
            ("observe", ["observe", "--a", at, "--c", c, "--json"], flint_observe_same_work),
            ("canonical", ["canonical", "--a", at, "--c", c, "--json"], flint_canonical_same_work),
            ("feedback", ["feedback", "--a", at, "--b", b, "--repeated", "1", "--method",
                          "ackermann", "--json"], flint_feedback_same_work),
            ("discrete --deadbeat", ["discrete", "--a", at, "--c", c, "--deadbeat", "--method",
                                     "ackermann", "--json"], flint_deadbeat_same_work),
            ("discrete --poles 1/2", ["discrete", "--a", at, "--c", c, "--poles", half,
                                      "--method", "ackermann", "--json"],
             flint_discrete_half_same_work),
            ("reduced", ["reduced", "--a", at, "--c", c, "--repeated", "1", "--method",
                         "ackermann", "--json"], flint_reduced_same_work),
            ("detectable", ["detectable", "--a", at, "--c", c, "--repeated", "1", "--method",
                            "ackermann", "--json"], flint_detectable_same_work),
        ]
        if only:
            cases = [k for k in cases if k[0].split()[0] in only]
        for name, args, peer in cases:
            t_owb, out = best_cpu(lambda: owb_cpu(args))
            t_fl, got = best_cpu(in_process(lambda: peer(a, n)))
            if name.startswith("gain") or name.startswith("discrete") or name.startswith("detectable"):
                assert [str(x) for x in got] == [r[0] for r in json.loads(out)["gain"]], "gains differ"
            if name == "feedback":
                assert [str(x) for x in got] == json.loads(out)["gain"][0], "gains differ"
            if name == "reduced":
                assert [str(x) for x in got[0]] == [r[0] for r in json.loads(out)["gain"]], "gains differ"
            own = max(t_owb - floor, 0.0)
            print(f"| `{name}` | {n} | {own * 1e3:.2f} ms | {t_fl * 1e3:.2f} ms | "
                  f"{own / t_fl:.1f}× |", flush=True)


def main():
    if sys.argv[1:2] == ["--same-work"]:
        # --same-work [--only gain,observe,…] [n …]
        rest = sys.argv[2:]
        only = ()
        if rest[:1] == ["--only"]:
            only, rest = tuple(rest[1].split(",")), rest[2:]
        same_work([int(x) for x in rest] or [10, 20, 30, 40, 60, 80], only)
        return
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
