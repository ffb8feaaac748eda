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
  * detectable: the rank of O_n (an observable plant), then the gain and its check;
  * control (B = e1, C = e1ᵀ, L placing (s + 1)ⁿ in A + LC, F placing (s + 2)ⁿ): L by the gain
    and its check, F by the dual gain and its check, the loop's determinants as rank-one and
    rank-two updates, the closed loop's blocks again on their own (compared), the plant's, the
    controller's and the closed loop's transfer functions in lowest terms (owb also factors
    four polynomials, which FLINT does not).
`--only feedback,reduced` restricts the commands (by their first word).
Each side the least CPU time of at least ten runs (more, up to sixty, until 0.4 s were spent):
owb's runs interleaved with runs of `owb --version`, whose least is the floor subtracted, so both
see the machine in the same state. The floor printed with the table is the one at its start.
The load average is printed with the table. The binary timed is a copy of
target/release/owb made at the start (`time_a_copy` says why).

    python3 tests/bench/flint_compare.py --float [--only zoh,kalman,dlqe] [n …]

The float commands against SciPy and python-control (slycot), same CPU-time accounting. The plant
is the same dense matrix divided by n (A/n, so its spectral radius stays near 3 for every n);
B = e1 for zoh; for the filters the noise enters every state (B = G = I) and the first n/2 states
are measured (C = [I 0]), with unit noise intensities — with one output the Riccati equation of a
dense plant of order 50 is singular to working precision for slycot too. NumPy's BLAS runs on one
thread (its spare threads would otherwise be counted as CPU time):
  * zoh (T = 1/10): `scipy.linalg.expm` of the augmented matrix [A B; 0 0]·T, Φ and Γ compared;
  * kalman: `control.lqe(A, I, C, I, I)` (slycot's Riccati solver), the poles of A − LC and the
    Lyapunov equation of the error covariance (`scipy.linalg.solve_continuous_lyapunov`) — what
    owb's report holds besides the filter; the gains compared;
  * dlqe: `control.dlqe(A, I, C, I, I)` (slycot), P compared.
Values agree to a relative 1e-8 or the script stops.
"""
import json, os, resource, subprocess, sys, time
from math import comb
from pathlib import Path

try:
    import flint
except ImportError:  # --float needs only SciPy and python-control
    flint = None

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
    run = subprocess.run([str(OWB), *args], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"owb {args[0]} exited with {run.returncode}: {run.stderr.strip()[-400:]}")
    out = run.stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out


def best_cpu(f, runs=10, spend=0.4, most=60):
    """The least CPU time of `runs` calls of `f` — more, up to `most`, until `spend` seconds
    were spent: a millisecond measurement takes the best of dozens, where five left the small
    orders' ratios moving by a factor of two with the machine."""
    times, out = [], None
    while len(times) < runs or (sum(times) < spend and len(times) < most):
        t, out = f()
        times.append(t)
    return min(times), out


def owb_own_cpu(args, runs=10, spend=0.4, most=60):
    """owb's CPU time for `args` less its process floor, the two interleaved — a floor run
    before every command run — and the least of each taken, so that both see the machine in the
    same state (a floor measured once at the start drifted by 0.2 ms within a table, as much as
    a whole 10-state command); and the command's output."""
    floors, times, out, k = [], [], None, 0
    while k < runs or (sum(times) + sum(floors) < spend and k < most):
        floors.append(owb_cpu(["--version"])[0])
        t, out = owb_cpu(args)
        times.append(t)
        k += 1
    return max(min(times) - min(floors), 0.0), out


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


def adjugate_form(chi, krylov_y, n):
    """x adj(sI − A) y from the numbers m_j = x A^j y (krylov_y, j < n) and chi = det(sI − A):
    the polynomial part of chi(s) · Σ m_j s^(−j−1) (rationals)."""
    nu = flint.fmpq_poly([krylov_y[n - 1 - i] for i in range(n)])
    prod = flint.fmpq_poly(chi) * nu
    return flint.fmpq_poly([prod[k] for k in range(n, 2 * n)])


def krylov_rows(a_q, x, n):
    """[x; xA; …; xA^(n−1)] for a row x (fmpq_mat)."""
    rows = [x]
    for _ in range(1, n):
        rows.append(rows[-1] * a_q)
    return flint.fmpq_mat(n, n, [v for r in rows for v in r.entries()])


def one_fractional_row_charpoly(m_q, n):
    """det(sI − M) for M whose fractions lie in row 0: the rank-one update of its integral rest
    (row 0 zeroed), as owb's characteristic polynomial takes such a matrix."""
    rest = flint.fmpz_mat(n, n, [0] * n + [int(v) for v in m_q.entries()[n:]])
    chi0 = flint.fmpq_poly(rest.charpoly())
    row = flint.fmpq_mat(1, n, m_q.entries()[:n])
    kry = krylov_rows(flint.fmpq_mat(rest), row, n)
    e0 = flint.fmpq_mat(n, 1, [1] + [0] * (n - 1))
    m = (kry * e0).entries()
    return chi0 - adjugate_form(rest.charpoly(), m, n)


def flint_control_same_work(a, n):
    """Observer-based control, B = e1, C = e1ᵀ, L placing (s + 1)ⁿ in A + LC and F placing
    (s + 2)ⁿ: L by the gain and its check (`control --observer-poly`), F by the dual gain and its
    check; det(sI − (A + BF)) and det(sI − (A + LC)) as rank-one updates and
    the controller's two determinants as rank-two updates (owb's LoopUpdates); the closed loop's
    blocks computed again on their own (one fractional row or column: the rank-one update of the
    integral rest) and compared; the plant's, the controller's and the closed loop's transfer
    functions in lowest terms (polynomial gcds). owb also factors four polynomials (rational
    roots), which this side does not."""
    l = [-v for v in flint_gain_same_work(a, n)]  # A − KC with K = −L, (s + 1)ⁿ
    p = [comb(n, k) * 2 ** (n - k) for k in range(n + 1)]  # (s + 2)ⁿ, lowest power first
    k = flint_gain_same_work(transpose(a), n, p=p)  # the dual: Aᵀ − K e1ᵀ
    f = flint.fmpq_mat(1, n, [-v for v in k])  # u = F x: A + BF = (Aᵀ − K Bᵀ)ᵀ
    az = flint.fmpz_mat(a)
    aq = flint.fmpq_mat(az)
    chi = az.charpoly()
    d = flint.fmpq_poly(chi)
    b = flint.fmpq_mat(n, 1, [1] + [0] * (n - 1))
    c = flint.fmpq_mat(1, n, [1] + [0] * (n - 1))
    lq = flint.fmpq_mat(n, 1, l)
    o_f, o_c = krylov_rows(aq, f, n), krylov_rows(aq, c, n)
    m = {name: adjugate_form(chi, (o * y).entries(), n)
         for name, o, y in (("fb", o_f, b), ("fl", o_f, lq), ("cb", o_c, b), ("cl", o_c, lq))}
    feedback, observer = d - m["fb"], d - m["cl"]
    open_k = ((d - m["fb"]) * (d - m["cl"]) - m["fl"] * m["cb"]) / d
    perturbed = ((d - m["fb"] - m["fl"]) * (d - m["cl"]) - m["fl"] * (m["cb"] + m["cl"])) / d
    # the closed loop's blocks on their own
    assert one_fractional_row_charpoly(aq + b * f, n) == feedback, "A + BF"
    assert one_fractional_row_charpoly((aq + lq * c).transpose(), n) == observer, "A + LC"
    # transfer functions in lowest terms
    plant_num = flint.fmpq_poly((az - flint.fmpz_mat(n, n, [1 if (i, j) == (0, 0) else 0
                                 for i in range(n) for j in range(n)])).charpoly()) - d
    g = plant_num.gcd(d)
    n_g, d_g = plant_num / g, d / g
    ctl_num = perturbed - open_k
    g = ctl_num.gcd(open_k)
    n_k, d_k = ctl_num / g, open_k / g
    num, den = n_g * d_k, d_g * d_k - n_k * n_g
    g = num.gcd(den)
    return f, l, feedback * observer, num / g, den / g


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


def table_header(peers, columns):
    """owb's process floor (CPU time of `owb --version`), printed with the load, the peers'
    versions and the table's header (each row subtracts its own floor: `owb_own_cpu`)."""
    floor, _ = best_cpu(lambda: owb_cpu(["--version"]), runs=20)
    load = os.getloadavg()
    print(f"owb's process floor (owb --version): {floor * 1e3:.2f} ms CPU; "
          f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; {peers}; "
          f"{os.cpu_count()} cores")
    print()
    print("| " + " | ".join(columns) + " |")
    print("|" + "---|" * len(columns))


def same_work(orders, only=()):
    table_header(f"python-flint {flint.__version__}",
                 ["command", "n", "owb CPU − floor", "FLINT same work (CPU)", "ratio"])
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
        cases.append(("control", ["control", "--a", at, "--b", b, "--c", c, "--observer-poly",
                                  f"(s + 1)^{n}", "--feedback-poly", f"(s + 2)^{n}", "--json"],
                      flint_control_same_work))
        if only:
            cases = [k for k in cases if k[0].split()[0] in only]
        for name, args, peer in cases:
            own, out = owb_own_cpu(args)
            t_fl, got = best_cpu(in_process(lambda: peer(a, n)))
            if name.startswith("gain") or name.startswith("discrete") or name.startswith("detectable"):
                assert [str(x) for x in got] == [r[0] for r in json.loads(out)["gain"]], "gains differ"
            if name == "feedback":
                assert [str(x) for x in got] == json.loads(out)["gain"][0], "gains differ"
            if name == "reduced":
                assert [str(x) for x in got[0]] == [r[0] for r in json.loads(out)["gain"]], "gains differ"
            if name == "control":
                shown = "[" + ", ".join(str(x) for x in got[0].entries()) + "]"
                assert shown == json.loads(out)["F"], "state feedbacks differ"
                shown = "[" + "; ".join(str(x) for x in got[1]) + "]"
                assert shown == json.loads(out)["L"], "observer gains differ"
            print(f"| `{name}` | {n} | {own * 1e3:.2f} ms | {t_fl * 1e3:.2f} ms | "
                  f"{own / t_fl:.1f}× |", flush=True)


def float_cases(n):
    """The float commands' plant and the peers' work, as (name, owb args, peer, compare)."""
    import numpy as np
    import scipy.linalg
    import control
    a_int = dense_random(n)
    a = np.array(a_int, dtype=float) / n
    at = matrix_text([[f"{x}/{n}" if x else "0" for x in r] for r in a_int])
    b_text = "[" + "; ".join(["1"] + ["0"] * (n - 1)) + "]"
    k = n // 2
    identity = lambda r, c: "[" + "; ".join(
        " ".join("1" if i == j else "0" for j in range(c)) for i in range(r)) + "]"
    eye, eye_k, c_text = identity(n, n), identity(k, k), identity(k, n)
    b = np.zeros((n, 1)); b[0, 0] = 1.0
    c = np.eye(n)[:k]

    def zoh_peer():
        aug = np.zeros((n + 1, n + 1))
        aug[:n, :n], aug[:n, n:] = a / 10, b / 10
        e = scipy.linalg.expm(aug)
        return e[:n, :n], e[:n, n:]

    def zoh_compare(out, got):
        d = json.loads(out)
        phi = np.array([[float(x) for x in r] for r in d["phi"]])
        gamma = np.array([[float(x) for x in r] for r in d["gamma"]])
        return max(np.abs(phi - got[0]).max(), np.abs(gamma - got[1]).max())

    def kalman_peer():
        l, p, e = control.lqe(a, np.eye(n), c, np.eye(n), np.eye(k))
        f = a - l @ c
        poles = np.linalg.eigvals(f)
        # the error covariance under the filter's own noise: F X + X Fᵀ + G Gᵀ + L Lᵀ = 0
        x = scipy.linalg.solve_continuous_lyapunov(f, -(np.eye(n) + l @ l.T))
        return l, poles, x

    def kalman_compare(out, got):
        l = np.array(json.loads(out)["kalman"]["gain"], dtype=float)
        return np.abs(l - got[0]).max() / max(1.0, np.abs(got[0]).max())

    def dlqe_peer():
        return control.dlqe(a, np.eye(n), c, np.eye(n), np.eye(k))

    def dlqe_compare(out, got):
        d = json.loads(out)["p"]
        p = np.array([[float(x) for x in r] for r in d])
        return np.abs(p - got[1]).max() / max(1.0, np.abs(got[1]).max())

    return [
        ("zoh", ["zoh", "--a", at, "--b", b_text, "--period", "1/10", "--json"], zoh_peer,
         zoh_compare),
        ("kalman", ["kalman", "--a", at, "--b", eye, "--c", c_text, "--input-noise", eye,
                    "--output-noise", eye_k, "--json"], kalman_peer, kalman_compare),
        ("dlqe", ["dlqe", "--a", at, "--c", c_text, "--qn", eye, "--rn", eye_k, "--json"],
         dlqe_peer, dlqe_compare),
    ]


def float_table(orders, only=()):
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = "1"
    import scipy, control
    try:
        import slycot
        slycot_version = slycot.__version__
    except ImportError:
        slycot_version = "not installed"
    table_header(f"SciPy {scipy.__version__}, python-control {control.__version__}, "
                 f"slycot {slycot_version}",
                 ["command", "n", "owb CPU − floor", "peer (CPU)", "ratio", "difference"])
    for n in orders:
        cases = float_cases(n)
        if only:
            cases = [k for k in cases if k[0] in only]
        for name, args, peer, compare in cases:
            own, out = owb_own_cpu(args)
            t_peer, got = best_cpu(in_process(peer))
            diff = compare(out, got)
            assert diff < 1e-8, f"{name} at n = {n}: owb and the peer differ by {diff:.2e}"
            print(f"| `{name}` | {n} | {own * 1e3:.2f} ms | {t_peer * 1e3:.2f} ms | "
                  f"{own / t_peer:.1f}× | {diff:.1e} |", flush=True)


def time_a_copy():
    """Times a copy of the release binary, not the file the linker has just written: that file's
    pages sit in the page cache in a form that faults in more slowly — on the 2-core machine
    about 0.1 ms more for `owb --version` and 0.1 ms more above it for a 10-state `zoh`, the same
    bytes — which neither its copy nor the file itself show once the page cache is dropped and
    its pages are read from disk again (measured: the two then within noise)."""
    import atexit, shutil, tempfile
    global OWB
    folder = tempfile.mkdtemp(prefix="owb-bench-")
    atexit.register(shutil.rmtree, folder, True)
    copy = Path(folder) / "owb"
    shutil.copy2(OWB, copy)
    OWB = copy


def orders_of(words):
    """The orders asked for, each a whole number from 1 to 200; otherwise the usage, status 1."""
    try:
        orders = [int(x) for x in words]
    except ValueError:
        orders = [0]
    if any(not 1 <= n <= 200 for n in orders):
        sys.exit("usage: flint_compare.py [--same-work | --float] [--only cmd,…] [n …] "
                 "(orders 1–200; see the header of this file)")
    return orders


def main():
    # --same-work | --float [--only gain,observe,…] [n …]
    if any(a in ("-h", "--help") for a in sys.argv[1:]):
        print(__doc__)
        return
    time_a_copy()
    tables = {"--same-work": (same_work, [10, 20, 30, 40, 60, 80]),
              "--float": (float_table, [10, 20, 50, 100])}
    if sys.argv[1:2] and sys.argv[1] in tables:
        table, default = tables[sys.argv[1]]
        rest, only = sys.argv[2:], ()
        if rest[:1] == ["--only"]:
            if len(rest) < 2:
                orders_of(["--only"])
            only, rest = tuple(rest[1].split(",")), rest[2:]
        table(orders_of(rest) or default, only)
        return
    orders = orders_of(sys.argv[1:]) or [20, 30, 60, 80]
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
