"""The observer workbench from Python and Jupyter.

Every function here builds one request of the workbench's library API (the request the ``owb``
command line, the course book and the browser make) and returns its report: the exact result,
the derivation typeset for Jupyter, and ``to_json()`` equal to ``owb … --json``. The computation
is the Rust library's; this module only converts values.

Values in:
  * matrices as strings in the workbench's syntax (``"[0 1; -2 -3]"``), nested lists, NumPy
    arrays, SymPy matrices, ``fractions.Fraction`` and integers;
  * floats are read as the decimals they print (``repr``): ``0.1`` is exactly 1/10, the number a
    reader sees, not the binary double nearest to it;
  * complex numbers as ``-1+2i``; SymPy's ``I`` is read as ``i``;
  * a python-control ``StateSpace`` (anything with ``A``, ``B``, ``C``, ``D`` attributes) in place
    of ``a``: ``gain(sys, poles=[-4, -5])``.

Values out: ``Result`` objects whose attributes are the fields of the command's ``--json`` answer,
with exact numbers as ``Fraction`` (irrational ones, such as ``sqrt(2) - 1``, stay strings in the
workbench's syntax; ``result.sympy(name)`` gives SymPy objects).
"""

from __future__ import annotations

import json as _json
import re as _re
from fractions import Fraction
from typing import Any, Mapping, Optional

from . import _native
from ._native import WorkbenchError

__all__ = [
    "WorkbenchError",
    "Result",
    "CheckResult",
    "run",
    "observe",
    "canonical",
    "gain",
    "feedback",
    "discrete",
    "zoh",
    "dlqe",
    "reduced",
    "detectable",
    "control",
    "optimal",
    "kalman",
    "perfect",
    "verify",
    "check",
    "exercises",
    "version",
]

version = _native.version()

# ---- values in -------------------------------------------------------------------------------

_RATIONAL = _re.compile(r"^-?\d+(/\d+)?$")
_FLOAT = _re.compile(r"^-?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-?(inf|NaN)$")


def _scalar(x: Any) -> str:
    """One number in the workbench's syntax."""
    if isinstance(x, bool):
        raise TypeError("a truth value is not a number")
    if isinstance(x, int):
        return str(x)
    if isinstance(x, Fraction):
        return f"{x.numerator}/{x.denominator}" if x.denominator != 1 else str(x.numerator)
    if isinstance(x, float):
        if x != x or x in (float("inf"), float("-inf")):
            raise ValueError(f"{x} is not a finite number")
        # the decimal the float prints, read exactly
        return repr(x)
    if isinstance(x, complex):
        re_, im = _scalar(x.real), _scalar(abs(x.imag))
        sign = "-" if x.imag < 0 else "+"
        return f"({re_} {sign} {im}i)"
    if isinstance(x, str):
        return x
    # NumPy scalars, SymPy numbers and expressions
    item = getattr(x, "item", None)
    if callable(item) and type(x).__module__.startswith("numpy"):
        return _scalar(item())
    if type(x).__module__.startswith("sympy"):
        return "(" + str(x).replace("**", "^").replace("I", "i") + ")"
    raise TypeError(f"cannot read {x!r} ({type(x).__name__}) as a number")


def _matrix(m: Any, flat_is_row: bool = False) -> str:
    """A matrix in the workbench's syntax, from a string, nested lists, NumPy or SymPy. A flat
    list is a column (a gain, B), or a row where ``flat_is_row`` (C, a feedback row F)."""
    if isinstance(m, str):
        return m
    tolist = getattr(m, "tolist", None)
    if callable(tolist) and not isinstance(m, (list, tuple)):
        m = tolist()
    if not isinstance(m, (list, tuple)):
        return f"[{_scalar(m)}]"
    rows = list(m)
    if rows and not isinstance(rows[0], (list, tuple)):
        rows = [rows] if flat_is_row else [[x] for x in rows]
    return "[" + "; ".join(" ".join(_scalar(x) for x in row) for row in rows) + "]"


def _list(xs: Any) -> str:
    """A list of numbers (poles) in the workbench's syntax."""
    if isinstance(xs, str):
        return xs
    tolist = getattr(xs, "tolist", None)
    if callable(tolist):
        xs = tolist()
    if not isinstance(xs, (list, tuple)):
        xs = [xs]
    return ", ".join(_scalar(x) for x in xs)


def _polynomial(p: Any) -> str:
    if isinstance(p, str):
        return p
    if type(p).__module__.startswith("sympy"):
        expr = getattr(p, "as_expr", lambda: p)()
        free = sorted(str(s) for s in expr.free_symbols)
        text = str(expr).replace("**", "^")
        if len(free) == 1 and free[0] != "s":
            text = _re.sub(rf"\b{free[0]}\b", "s", text)
        return text
    # coefficients, highest power first (as numpy.poly and python-control give them)
    tolist = getattr(p, "tolist", None)
    if callable(tolist):
        p = tolist()
    coeffs = list(p)
    n = len(coeffs) - 1
    return " + ".join(f"({_scalar(c)})*s^{n - k}" for k, c in enumerate(coeffs))


_MATRIX_KEYS = {
    "a", "b", "c", "d", "l", "f", "g", "qn", "rn", "weight", "check-gain",
    "changed-a", "changed-b", "changed-c", "changed-d",
}
_ROW_KEYS = {"c", "f", "d", "changed-c", "changed-d"}
_LIST_KEYS = {"poles", "continuous-poles"}
_POLY_KEYS = {"poly", "feedback-poly", "observer-poly"}


def _value(key: str, v: Any) -> Any:
    if isinstance(v, bool):
        return v
    if key in _MATRIX_KEYS:
        return _matrix(v, flat_is_row=key in _ROW_KEYS)
    if key in _LIST_KEYS:
        return _list(v)
    if key in _POLY_KEYS:
        return _polynomial(v)
    if key in {"output", "starts", "seed", "grid", "derivative-output", "derivative-state"}:
        return int(v)
    if key in {"tolerance", "time-limit"}:
        return float(v)
    if isinstance(v, (int, float, Fraction)) or type(v).__module__.startswith(("numpy", "sympy")):
        return _scalar(v)
    return v


def _request(command: str, fields: Mapping[str, Any]) -> dict:
    request: dict = {"command": command}
    for name, v in fields.items():
        if v is None or v is False:
            continue
        key = name.rstrip("_").replace("_", "-")
        request[key] = _value(key, v)
    return request


def _plant(a: Any, fields: dict, take=("C",)) -> dict:
    """``a`` may be a python-control StateSpace (anything with ``A``, ``B``, ``C``, ``D``): its A,
    and the matrices named in ``take`` that the request does not give itself (D only when it
    is not zero)."""
    if all(hasattr(a, x) for x in ("A", "B", "C", "D")) and not isinstance(a, str):
        for name in take:
            m = getattr(a, name)
            nonzero = getattr(m, "any", lambda: bool(m))()
            if fields.get(name.lower()) is None and (name != "D" or nonzero):
                fields[name.lower()] = m
        fields["a"] = a.A
    elif a is not None:
        fields["a"] = a
    return fields


# ---- values out ------------------------------------------------------------------------------


def _exact(v: Any) -> Any:
    """Rational strings as Fractions, recursively; other values as they are."""
    if isinstance(v, str) and _RATIONAL.match(v.strip()):
        return Fraction(v.strip())
    if isinstance(v, str) and _FLOAT.match(v.strip()):
        # the float path's results are written as floats (1.24e0): read back as floats
        return float(v)
    if isinstance(v, list):
        return [_exact(x) for x in v]
    return v


class Result:
    """A command's report: the fields of its ``--json`` answer as attributes (exact numbers as
    ``Fraction``), the text the command line prints (``str(result)``), the derivation in LaTeX
    (shown by Jupyter), and ``to_json()``."""

    def __init__(self, request: dict, status: int, json_text: str, latex: Optional[str], warnings):
        self._request = request
        self.status = status
        self._json_text = json_text
        self.data = _json.loads(json_text)
        self.latex = latex
        self.warnings = list(warnings)
        self._text: Optional[str] = None

    @property
    def ok(self) -> bool:
        """Whether the command concluded without finding anything wrong (exit status 0)."""
        return self.status == 0

    def __getattr__(self, name: str) -> Any:
        data = self.__dict__.get("data", {})
        if name in data:
            return _exact(data[name])
        raise AttributeError(f"{type(self).__name__} has no field {name!r}; fields: {sorted(data)}")

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self.data))

    def to_json(self) -> str:
        """The JSON answer exactly as ``owb … --json`` prints it."""
        return self._json_text

    @property
    def text(self) -> str:
        """The report as the command line prints it (the command is run again, as text)."""
        if self._text is None:
            request = dict(self._request)
            request.pop("json", None)
            _, text, _, _ = _native.run(_json.dumps(request))
            self._text = text
        return self._text

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return f"<observer_workbench.Result of {self._request['command']}: {sorted(self.data)}>"

    def array(self, name: str):
        """A matrix field as a NumPy float array (exact entries rounded to f64)."""
        import numpy

        def num(x):
            x = _exact(x)
            if isinstance(x, list):
                return [num(y) for y in x]
            if isinstance(x, str):
                return complex(self_sympy(x)).real
            return float(x)

        def self_sympy(x):
            import sympy

            return sympy.N(sympy.sympify(x.replace("^", "**"), rational=True))

        return numpy.array(num(self.data[name]), dtype=float)

    def sympy(self, name: str) -> Any:
        """A field as SymPy objects (matrices as ``sympy.Matrix``), radicals exact."""
        import sympy

        def conv(x):
            if isinstance(x, list):
                return [conv(y) for y in x]
            if isinstance(x, str):
                return sympy.sympify(x.replace("^", "**").replace("sqrt", "sqrt"), rational=True)
            return x

        v = conv(self.data[name])
        if isinstance(v, list) and v and isinstance(v[0], list):
            return sympy.Matrix(v)
        return v

    def _repr_latex_(self) -> Optional[str]:
        if self.latex:
            return "$$" + self.latex + "$$"
        return None

    def _repr_html_(self) -> str:
        import html

        if self._request["command"] == "verify" and "examples" in self.data:
            return _verification_table(self.data)
        return "<pre>" + html.escape(self.text) + "</pre>"


_VERDICT_MARK = {
    "holds": "✔",
    "holds_approximately": "≈",
    "erratum": "erratum",
    "unreproducible": "unreproducible",
    "mismatch": "✘ mismatch",
}


def _verification_table(data: dict) -> str:
    """``owb verify --json`` as HTML: one table per example (claim, source, printed, recomputed,
    verdict), the explanation of every verdict that is not a plain hold under its row."""
    import html

    e = html.escape
    out = []
    for ex in data["examples"]:
        out.append(f"<h4>{e(ex['id'])} <small>({e(ex.get('document', ''))})</small></h4>")
        out.append("<table><thead><tr><th>claim</th><th>source</th><th>printed</th>"
                   "<th>recomputed</th><th>verdict</th></tr></thead><tbody>")
        for c in ex["claims"]:
            verdict = c["verdict"]
            out.append(
                f"<tr><td><code>{e(c['id'])}</code></td><td>{e(c['source'])}</td>"
                f"<td><code>{e(c['printed'])}</code></td><td><code>{e(c['recomputed'])}</code></td>"
                f"<td>{e(_VERDICT_MARK.get(verdict, verdict))}</td></tr>"
            )
            if verdict != "holds" and c.get("explanation"):
                out.append(f"<tr><td></td><td colspan=\"4\"><small>{e(c['explanation'])}</small></td></tr>")
        out.append("</tbody></table>")
    summary = data.get("summary", {})
    out.append("<p>" + e(", ".join(f"{k.replace('_', ' ')}: {v}" for k, v in summary.items())) + "</p>")
    return "\n".join(out)


def run(command: str, **fields: Any) -> Result:
    """Runs any workbench command: ``run("gain", a=…, c=…, poles=…)``; field names are the
    command line's flags with ``_`` for ``-`` (``input_noise`` for ``--input-noise``)."""
    request = _request(command, fields)
    request["json"] = True
    status, text, latex, warnings = _native.run(_json.dumps(request))
    return Result(request, status, text, latex, warnings)


def observe(a: Any, c: Any = None, **kw: Any) -> Result:
    """Observability: O_n, its rank, the unobservable subspace and modes (``owb observe``)."""
    return run("observe", **_plant(a, {"c": c, **kw}))


def canonical(a: Any, c: Any = None, b: Any = None, **kw: Any) -> Result:
    """The observer canonical form, Di Ruscio's and Stoustrup's procedures (``owb canonical``)."""
    return run("canonical", **_plant(a, {"c": c, "b": b, **kw}, ("B", "C")))


def gain(a: Any = None, c: Any = None, *, float_check: bool = False, **kw: Any) -> Result:
    """The exact observer gain for a desired polynomial (``owb gain``): ``poles=``, ``poly=``,
    ``repeated=``, ``butterworth=``, ``bessel=`` or ``itae=``; ``method=`` (ackermann, bass-gura,
    canonical, lemma-3.1), ``convention=`` (a-kc, a+lc), ``float_check=True`` for the checked
    f64 path, ``tf=`` for a transfer function instead of ``a``/``c``."""
    return run("gain", **_plant(a, {"c": c, "float": float_check, **kw}))


def feedback(a: Any, b: Any = None, **kw: Any) -> Result:
    """State feedback by duality (``owb feedback``)."""
    return run("feedback", **_plant(a, {"b": b, **kw}, ("B",)))


def discrete(a: Any, c: Any = None, **kw: Any) -> Result:
    """A discrete-time observer: prediction or current estimator, dead-beat (``owb discrete``)."""
    return run("discrete", **_plant(a, {"c": c, **kw}))


def zoh(a: Any, b: Any = None, *, period: Any, **kw: Any) -> Result:
    """A continuous plant sampled with a zero-order hold (``owb zoh``)."""
    return run("zoh", **_plant(a, {"b": b, "period": period, **kw}, ("B",)))


def dlqe(a: Any, c: Any, *, qn: Any, rn: Any, g: Any = None, **kw: Any) -> Result:
    """The discrete-time steady-state Kalman filter (``owb dlqe``)."""
    return run("dlqe", a=a, c=c, qn=qn, rn=rn, g=g, **kw)


def reduced(a: Any, c: Any = None, **kw: Any) -> Result:
    """The reduced-order (Gopinath) observer (``owb reduced``)."""
    return run("reduced", **_plant(a, {"c": c, **kw}))


def detectable(a: Any, c: Any = None, **kw: Any) -> Result:
    """An observer for an unobservable, detectable pair (``owb detectable``)."""
    return run("detectable", **_plant(a, {"c": c, **kw}))


def control(a: Any, b: Any = None, c: Any = None, **kw: Any) -> Result:
    """Observer-based control, the separation principle checked (``owb control``)."""
    return run("control", **_plant(a, {"b": b, "c": c, **kw}, ("B", "C")))


def optimal(a: Any, c: Any = None, **kw: Any) -> Result:
    """Multi-output gains by optimality (``owb optimal``)."""
    return run("optimal", **_plant(a, {"c": c, **kw}))


def kalman(a: Any, b: Any = None, c: Any = None, **kw: Any) -> Result:
    """The Kalman filter against chosen poles (``owb kalman``)."""
    return run("kalman", **_plant(a, {"b": b, "c": c, **kw}, ("B", "C", "D")))


def perfect(a: Any, b: Any = None, c: Any = None, **kw: Any) -> Result:
    """The perfect (descriptor) observer (``owb perfect``)."""
    return run("perfect", **_plant(a, {"b": b, "c": c, **kw}, ("B", "C", "D")))


def verify(*examples: str, folder: Optional[str] = None) -> Result:
    """The worked examples recomputed and compared with the documents (``owb verify``)."""
    fields: dict = {"examples": list(examples)}
    if folder is not None:
        fields["dir"] = folder
    return run("verify", **fields)


def exercises() -> list:
    """The ids of the exercises built into the workbench."""
    return list(_native.builtin_exercises())


class CheckResult:
    """A check of a student's answers: per part ✔/✘, the mistake named, the score — what
    ``owb check --json`` says — and the feedback text (``str(result)``)."""

    def __init__(self, data: dict):
        self.data = data
        self.parts = data["parts"]
        self.score = data["score"]
        self.text = data["text"]

    @property
    def all_correct(self) -> bool:
        return all(p["verdict"] == "correct" for p in self.parts)

    def part(self, name: str) -> dict:
        for p in self.parts:
            if p["id"] == name:
                return p
        raise KeyError(f"no part {name!r}; parts: {[p['id'] for p in self.parts]}")

    def __str__(self) -> str:
        return self.text

    def _repr_html_(self) -> str:
        import html

        return "<pre>" + html.escape(self.text) + "</pre>"


def _toml_string(s: str) -> str:
    """A TOML basic string holding exactly ``s``: control characters escaped, so that the
    checker sees them and says so at the part (a TOML error would hide which part)."""
    out = []
    for ch in s:
        if ch == "\\":
            out.append("\\\\")
        elif ch == '"':
            out.append('\\"')
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04X}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def check(exercise: str, answers: Mapping[str, Any]) -> CheckResult:
    """Checks answers to an exercise: ``exercise`` is a built-in exercise id or a path to an
    exercise file; ``answers`` maps each part to the student's answer — text in the workbench's
    syntax or a Python value (a NumPy array, nested lists, a Fraction, a SymPy matrix)."""
    text = _native.builtin_exercise(exercise)
    name = f"{exercise} (built in)"
    if text is None:
        with open(exercise, encoding="utf-8") as f:
            text = f.read()
        name = exercise
    lines = ["[answers]"]
    for part, value in answers.items():
        if isinstance(value, str):
            answer = value
        elif isinstance(value, (list, tuple)) or hasattr(value, "tolist") or hasattr(value, "shape"):
            answer = _matrix(value)
        else:
            answer = _scalar(value)
        lines.append(f"{_toml_string(str(part))} = {_toml_string(answer)}")
    data = _json.loads(_native.check_text(name, text, "\n".join(lines) + "\n"))
    return CheckResult(data)
