"""Symbolic observer gains: the whole `owb gain --json` process against SymPy and python-flint
doing the same work in-process (run by hand; the README reports one run).

Cases (every pole at -w):
  msd       mass-spring-damper A = [0 1; -k/m -c/m], C = [1 0]
  chain2-4  chains of 2, 3, 4 equal masses m joined by equal springs k (n = 4, 6, 8), the first
            position measured
  nonmono   A = [0 1; -a -b] measured through C = [1 c]: det O_n = c^2 - b c + a... is not a
            monomial, so the final gcds have real work

Work per case, for every tool: Ackermann's K = P(A) O_n^-1 e_n with every entry a rational
function in lowest terms, then the check det(sI - A + K C) == P(s) as an identity.
  owb     the whole process (parse, design, check, JSON), CPU time of the child
  SymPy   Matrix arithmetic, LUsolve, cancel() on each entry, the determinant check by berkowitz
          and cancel (in-process CPU time)
  flint   fmpz_mpoly numerators and denominators reduced by gcd after each operation (the same
          arithmetic owb does), Gauss–Jordan for O_n^-1 e_n, Horner for P(A) q, the check by
          the rank-one update det(sI - A) + sum_j (O_n K)_j adj terms (in-process CPU time)
CPU times are the minimum of the repeats; owb's process floor (`owb --version`) is shown.

Usage: python tests/bench/symbolic_vs_peers.py [path/to/owb]
"""

import resource
import subprocess
import sys
import time

import flint
import sympy

OWB = sys.argv[1] if len(sys.argv) > 1 else "target/release/owb"
REPEATS = 7


def chain(n):
    size = 2 * n
    a = [["0"] * size for _ in range(size)]
    for i in range(n):
        a[2 * i][2 * i + 1] = "1"
        coef = {i: -1 if i + 1 == n else -2}
        if i > 0:
            coef[i - 1] = 1
        if i + 1 < n:
            coef[i + 1] = 1
        if n == 1:
            coef[i] = -1
        for j, c in coef.items():
            a[2 * i + 1][2 * j] = f"{c}*k/m"
    c = ["1"] + ["0"] * (size - 1)
    return a, [c], size


CASES = {
    "msd": ([["0", "1"], ["-k/m", "-c/m"]], [["1", "0"]], 2),
    "chain2": chain(2),
    "chain3": chain(3),
    "chain4": chain(4),
    "nonmono": ([["0", "1"], ["-a", "-b"]], [["1", "c"]], 2),
}


def text(m):
    return "[" + "; ".join(" ".join(r) for r in m) + "]"


def child_cpu(args):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(args, capture_output=True, check=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out.stdout


def best(f):
    times = []
    result = None
    for _ in range(REPEATS):
        t0 = time.process_time()
        result = f()
        times.append(time.process_time() - t0)
    return min(times), result


# ---------------------------------------------------------------- SymPy
def sympy_gain(a_text, c_text, n):
    a = sympy.Matrix([[sympy.sympify(x) for x in r] for r in a_text])
    c = sympy.Matrix([[sympy.sympify(x) for x in r] for r in c_text])
    s, w = sympy.symbols("s w")
    p = sympy.Poly((s + w) ** n, s)
    rows = [c]
    for _ in range(n - 1):
        rows.append(rows[-1] * a)
    o = sympy.Matrix.vstack(*rows)
    e = sympy.zeros(n, 1)
    e[n - 1] = 1
    q = o.LUsolve(e).applyfunc(sympy.cancel)
    pa = sympy.zeros(n, n)
    for coeff in p.all_coeffs():
        pa = pa * a + coeff * sympy.eye(n)
    k = (pa * q).applyfunc(sympy.cancel)
    char = (s * sympy.eye(n) - a + k * c).berkowitz_det()
    assert sympy.cancel(char - p.as_expr()) == 0
    return k


# ---------------------------------------------------------------- python-flint
class RF:
    """num/den of fmpz_mpoly, reduced by gcd after every operation."""

    __slots__ = ("n", "d")

    def __init__(self, n, d):
        g = n.gcd(d)
        if not g.is_one():
            n, d = n // g, d // g
        if d.leading_coefficient() < 0:
            n, d = -n, -d
        self.n, self.d = n, d

    def __add__(self, o):
        return RF(self.n * o.d + o.n * self.d, self.d * o.d)

    def __sub__(self, o):
        return RF(self.n * o.d - o.n * self.d, self.d * o.d)

    def __mul__(self, o):
        return RF(self.n * o.n, self.d * o.d)

    def __truediv__(self, o):
        return RF(self.n * o.d, self.d * o.n)

    def is_zero(self):
        return self.n.is_zero()


def flint_gain(a_text, c_text, n):
    names = sorted({ch for r in a_text + c_text for x in r for ch in x if ch.isalpha()} | {"w"})
    ctx = flint.fmpz_mpoly_ctx.get(tuple(names), "lex")
    gens = dict(zip(names, ctx.gens()))
    one, zero = ctx.from_dict({(0,) * len(names): 1}), ctx.from_dict({})

    def parse(x):
        # the entries are products and quotients of small integers and symbols
        num, _, den = x.partition("/")
        value = eval(num, {}, gens) if num else one  # noqa: S307 - our own fixed strings
        value = value if not isinstance(value, int) else one * value
        d = eval(den, {}, gens) if den else one  # noqa: S307
        d = d if not isinstance(d, int) else one * d
        return RF(value, d)

    rf_zero, rf_one = RF(zero, one), RF(one, one)
    a = [[parse(x) for x in r] for r in a_text]
    c = [parse(x) for x in c_text[0]]
    w = RF(gens["w"], one)
    # O_n rows C A^k
    rows = [c]
    for _ in range(n - 1):
        prev = rows[-1]
        rows.append([sum_rf([prev[i] * a[i][j] for i in range(n)], rf_zero) for j in range(n)])
    # solve O q = e_n by Gauss–Jordan
    m = [rows[i][:] + [rf_one if i == n - 1 else rf_zero] for i in range(n)]
    for col in range(n):
        piv = next(r for r in range(col, n) if not m[r][col].is_zero())
        m[col], m[piv] = m[piv], m[col]
        inv = rf_one / m[col][col]
        m[col] = [x * inv for x in m[col]]
        for r in range(n):
            if r != col and not m[r][col].is_zero():
                f = m[r][col]
                m[r] = [x - f * y for x, y in zip(m[r], m[col])]
    q = [m[i][n] for i in range(n)]
    # P(A) q by Horner, P(s) = (s + w)^n
    coeffs = [binom(n, j) for j in range(n + 1)]  # coefficient of s^(n-j) is C(n,j) w^j
    wp = [rf_one]
    for _ in range(n):
        wp.append(wp[-1] * w)
    v = q[:]
    for j in range(1, n + 1):
        av = [sum_rf([a[i][t] * v[t] for t in range(n)], rf_zero) for i in range(n)]
        cj = RF(one * coeffs[j], one) * wp[j]
        v = [av[i] + cj * q[i] for i in range(n)]
    k = v
    # check by the rank-one update: det(sI - A + K C) = a(s) + sum_j (O K)_j adj terms
    ok = [sum_rf([rows[r][t] * k[t] for t in range(n)], rf_zero) for r in range(n)]
    open_loop = charpoly_coeffs(a, n, rf_zero, rf_one)
    got = open_loop[:]
    for j in range(n):
        for i in range(j + 1, n + 1):
            e = i - j - 1
            got[e] = got[e] + ok[j] * open_loop[i]
    want = [RF(one * coeffs[n - e], one) * wp[n - e] for e in range(n + 1)]
    assert all((g - x).is_zero() for g, x in zip(got, want)), "flint check failed"
    return k


def sum_rf(xs, zero):
    out = zero
    for x in xs:
        if not x.is_zero():
            out = out + x
    return out


def binom(n, j):
    from math import comb

    return comb(n, j)


def charpoly_coeffs(a, n, zero, one):
    """Faddeev–LeVerrier over the rational functions: coefficients lowest first."""
    ident = [[one if i == j else zero for j in range(n)] for i in range(n)]
    m = [row[:] for row in ident]
    coeffs = [zero] * (n + 1)
    coeffs[n] = one
    for k in range(1, n + 1):
        am = [[sum_rf([a[i][t] * m[t][j] for t in range(n)], zero) for j in range(n)] for i in range(n)]
        tr = sum_rf([am[i][i] for i in range(n)], zero)
        ck = RF(-tr.n, tr.d * k)
        coeffs[n - k] = ck
        m = [[am[i][j] + (ck if i == j else zero) for j in range(n)] for i in range(n)]
    return coeffs


def main():
    floor, _ = min((child_cpu([OWB, "--version"]) for _ in range(REPEATS)), key=lambda x: x[0])
    print(f"owb process floor (owb --version): {floor * 1e3:.2f} ms CPU")
    print(f"{'case':8} {'n':>2} {'owb (process)':>14} {'python-flint':>13} {'SymPy':>10} {'owb/flint':>10} {'SymPy/owb':>10}")
    for name, (a, c, n) in CASES.items():
        args = [OWB, "gain", "--a", text(a), "--c", text(c), "--poles", ", ".join(["-w"] * n), "--json"]
        t_owb = min(child_cpu(args)[0] for _ in range(REPEATS))
        t_flint, _ = best(lambda: flint_gain(a, c, n))
        t_sympy, _ = best(lambda: sympy_gain(a, c, n)) if n <= 8 else (float("nan"), None)
        print(
            f"{name:8} {n:>2} {t_owb * 1e3:>11.2f} ms {t_flint * 1e3:>10.2f} ms {t_sympy * 1e3:>7.1f} ms"
            f" {t_owb / t_flint:>10.1f} {t_sympy / t_owb:>10.1f}"
        )


if __name__ == "__main__":
    main()
