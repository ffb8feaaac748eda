"""Run by hand: `python3 python/bench/gain_vs_peers.py` (after `pip install ./python`, with
python-control and SymPy). Times `owb.gain` from Python against `control.acker` (f64) and
SymPy's exact Ackermann formula on the same dense random integer systems, and the binding's
overhead per call (a 1×1 request, compared with the same request's work measured in Rust)."""

import statistics
import time

import numpy as np

import observer_workbench as owb


def best(f, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def system(n, seed):
    rng = np.random.default_rng(seed)
    while True:
        a = rng.integers(-9, 10, size=(n, n))
        c = rng.integers(-9, 10, size=(1, n))
        o = np.vstack([c @ np.linalg.matrix_power(a.astype(object), k) for k in range(n)])
        import sympy

        if sympy.Matrix(o).rank() == n:
            return a, c


def sympy_ackermann(a, c, poles):
    import sympy

    A, C = sympy.Matrix(a), sympy.Matrix(c)
    n = A.rows
    s = sympy.symbols("s")
    p = sympy.Poly(sympy.prod([s - q for q in poles]), s)
    O = sympy.Matrix.vstack(*[C * A**k for k in range(n)])
    en = sympy.zeros(n, 1)
    en[n - 1] = 1
    PA = sympy.zeros(n, n)
    for coeff in p.all_coeffs():
        PA = PA * A + coeff * sympy.eye(n)
    return PA * O.LUsolve(en)


def main():
    import control

    overhead = [best(lambda: owb.observe("[1]", "[1]"), 200) for _ in range(5)]
    print(f"binding + request + report, 1×1 observe: {statistics.median(overhead) * 1e6:.0f} µs a call")
    for n in (10, 20, 30):
        a, c = system(n, n)
        poles = [-(k + 1) for k in range(n)]
        t_owb = best(lambda: owb.gain(a, c, poles=poles, summary=True), 3)
        try:
            t_acker = best(lambda: control.acker(a.T.astype(float), c.T.astype(float), poles), 3)
            acker = f"{t_acker * 1e3:.2f} ms"
        except ValueError as e:
            acker = f"refused ({e})"
        line = f"n = {n}: owb.gain (exact, --summary) {t_owb * 1e3:.1f} ms; control.acker (f64) {acker}"
        if n <= 20:
            t_sympy = best(lambda: sympy_ackermann(a, c, poles), 1)
            line += f"; SymPy exact Ackermann {t_sympy:.2f} s ({t_sympy / t_owb:.0f}× owb)"
        print(line)


if __name__ == "__main__":
    main()
