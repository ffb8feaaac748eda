"""The Python package against the command line it mirrors and against python-control: the same
request gives the same JSON as ``owb … --json``; exact gains agree with ``control.acker`` on
well-conditioned cases; refusals are exceptions with the command line's message."""

import json
import os
import subprocess
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

import observer_workbench as owb

REPO = Path(__file__).resolve().parents[2]
OWB = os.environ.get("OWB_BINARY", str(REPO / "target" / "release" / "owb"))


def owb_cli(*args):
    if not Path(OWB).exists():
        pytest.fail(f"the owb binary is needed for this comparison: build it (cargo build --release) or set OWB_BINARY; not found: {OWB}")
    out = subprocess.run([OWB, *args], capture_output=True, text=True, cwd=REPO)
    return out.returncode, out.stdout, out.stderr


def test_to_json_is_the_command_lines_json():
    cases = [
        (owb.gain("[2 -3; 4 -5]", "[-3 2]", poles="-4, -5", convention="a+lc"),
         ["gain", "--a", "[2 -3; 4 -5]", "--c", "[-3 2]", "--poles", "-4, -5", "--convention", "a+lc"]),
        (owb.observe("[1 0; 0 2]", "[1 0]"), ["observe", "--a", "[1 0; 0 2]", "--c", "[1 0]"]),
        (owb.discrete("[1 1; 0 1]", "[1 0]", deadbeat=True),
         ["discrete", "--a", "[1 1; 0 1]", "--c", "[1 0]", "--deadbeat"]),
        (owb.gain(tf="(s + 1)/(s^2 + 3s + 5)", itae=1),
         ["gain", "--tf", "(s + 1)/(s^2 + 3s + 5)", "--itae", "1"]),
        (owb.control("[2 -3; 4 -5]", "[2; 3]", "[-3 2]", observer_poly=[1, 12, 36], feedback_poly="s^2 + 3s + 2"),
         ["control", "--a", "[2 -3; 4 -5]", "--b", "[2; 3]", "--c", "[-3 2]",
          "--observer-poly", "s^2 + 12s + 36", "--feedback-poly", "s^2 + 3s + 2"]),
    ]
    for result, args in cases:
        status, out, err = owb_cli(*args, "--json")
        assert status == 0, err
        assert result.to_json() == out
        # and the text is the command line's text
        status, out, err = owb_cli(*args)
        assert str(result) == out


def test_exact_gain_agrees_with_python_control_acker():
    control = pytest.importorskip("control")
    rng = np.random.default_rng(7)
    for n in (2, 3, 4):
        for _ in range(5):
            a = rng.integers(-5, 6, size=(n, n))
            c = rng.integers(-3, 4, size=(1, n))
            o = np.vstack([c @ np.linalg.matrix_power(a, k) for k in range(n)])
            if abs(np.linalg.det(o)) < 0.5:
                continue  # unobservable or nearly so: acker is not the reference there
            poles = [-(k + 1) for k in range(n)]
            exact = owb.gain(a, c, poles=poles).gain
            reference = control.acker(a.T.astype(float), c.T.astype(float), poles).T
            got = np.array([[float(x) for x in row] for row in exact])
            assert np.allclose(got, reference, rtol=1e-9, atol=1e-9), (a, c, got, reference)
            assert all(isinstance(x, Fraction) for row in exact for x in row)


def test_a_state_space_object_is_a_plant():
    control = pytest.importorskip("control")
    sys = control.ss([[0, 1], [-2, -3]], [[0], [1]], [[1, 0]], 0)
    # the same requests written out: the plant's matrices are taken from the object
    assert owb.gain(sys, poles=[-4, -5]).to_json() == owb.gain(
        "[0 1; -2 -3]", "[1 0]", poles="-4, -5"
    ).to_json()
    assert owb.feedback(sys, poles=[-4, -5]).to_json() == owb.feedback(
        "[0 1; -2 -3]", "[0; 1]", poles="-4, -5"
    ).to_json()
    assert owb.zoh(sys, period="1/2").to_json() == owb.zoh("[0 1; -2 -3]", "[0; 1]", period="1/2").to_json()
    assert owb.canonical(sys).to_json() == owb.canonical("[0 1; -2 -3]", "[1 0]", b="[0; 1]").to_json()
    k = owb.kalman(sys, input_noise=1, output_noise=Fraction(1, 10))
    assert k.data["kalman"]["residual"] < 1e-8


def test_floats_are_read_as_the_decimals_they_print():
    r = owb.gain(np.array([[0.1, 1.0], [-2.0, -3.0]]), [1, 0], poles=[-4, -5])
    (k1,), (k2,) = r.gain

    def places_exactly(a11):
        # A − KC for C = [1 0]: its trace and determinant give det(sI − (A − KC)) = s² + 9s + 20
        m = [[a11 - k1, Fraction(1)], [-2 - k2, Fraction(-3)]]
        return (-(m[0][0] + m[1][1]), m[0][0] * m[1][1] - m[0][1] * m[1][0]) == (9, 20)

    # exact for the decimal 0.1 the float prints, not for the binary double nearest to it
    assert places_exactly(Fraction("0.1"))
    assert not places_exactly(Fraction(0.1))


def test_refusals_raise_with_the_command_lines_message():
    with pytest.raises(owb.WorkbenchError, match="in --a") as e:
        owb.gain("[1 2; 3]", "[1 0]", poles="-1, -2")
    status, _, err = owb_cli("gain", "--a", "[1 2; 3]", "--c", "[1 0]", "--poles", "-1, -2")
    assert status == 2
    assert str(e.value).splitlines()[0] == err.splitlines()[0].removeprefix("error: ")
    with pytest.raises(owb.WorkbenchError, match="unknown key"):
        owb.run("gain", a="[1]", c="[1]", poles="-1", polls="-2")


def test_check_names_the_mistake_from_python_values():
    wrong = owb.check("stoustrup-pole-assignment", {"L": np.array([[6], [12]])})
    part = wrong.part("L")
    assert part["verdict"] == "wrong"
    assert part["mistake"] == "sign_convention"
    right = owb.check("stoustrup-pole-assignment", {"L": [[-6], [-12]]})
    assert right.part("L")["verdict"] == "correct"


def test_radicals_stay_exact_and_sympy_reads_them():
    sympy = pytest.importorskip("sympy")
    r = owb.gain("[0 1; -2 -3]", "[1 0]", butterworth=1)
    k = r.sympy("gain")
    s_ = sympy.symbols("s")
    a, c = sympy.Matrix([[0, 1], [-2, -3]]), sympy.Matrix([[1, 0]])
    # the order-2 Butterworth polynomial with T = 1, placed exactly (radicals and all)
    placed = (s_ * sympy.eye(2) - (a - k * c)).det()
    assert sympy.expand(placed - (s_**2 + sympy.sqrt(2) * s_ + 1)) == 0
    s = sympy.symbols("s")
    assert owb.gain("[0 1; -2 -3]", "[1 0]", poly=(s + 4) * (s + 5)).gain == [[6], [0]]
    assert r._repr_latex_().startswith("$$\\begin{aligned}")


def test_json_requests_and_results_round_trip():
    r = owb.run("observe", a=[[1, 0], [0, 2]], c=[1, 0])
    assert json.loads(r.to_json()) == r.data
    assert r.observable is False
    # each unobservable eigenvalue λ is one of A's and fails the PBH test: rank [λI − A; C] < n
    a, c = np.array([[1.0, 0.0], [0.0, 2.0]]), np.array([[1.0, 0.0]])
    for mode in r.unobservable_eigenvalues:
        lam = float(Fraction(mode["value"]))
        assert np.linalg.matrix_rank(np.vstack([lam * np.eye(2) - a, c])) < 2


def test_the_autograding_notebook_runs_and_names_the_mistake():
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    path = REPO / "python" / "examples" / "autograde.ipynb"
    nb = nbformat.read(path, as_version=4)
    nbclient.NotebookClient(nb, timeout=120, kernel_name="python3").execute()
    printed = "".join(
        o.get("text", "") for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
    )
    assert "sign" in printed and "✘" in printed, printed


def _otter_cases(student_globals):
    """Runs the Otter-Grader test file's doctest cases as Otter does: in the notebook's
    namespace, each case passing or failing with doctest's report."""
    import doctest

    path = REPO / "python" / "examples" / "otter" / "tests" / "q_gain.py"
    spec = {}
    exec(path.read_text(encoding="utf-8"), spec)
    results = []
    for case in spec["test"]["suites"][0]["cases"]:
        parser = doctest.DocTestParser()
        test = parser.get_doctest(case["code"], dict(student_globals), "q_gain", str(path), 0)
        runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
        out = []
        runner.run(test, out=out.append)
        results.append((runner.failures == 0, "".join(out)))
    return results


def test_the_otter_grader_test_passes_a_right_gain_and_names_a_wrong_one():
    right = _otter_cases({"L": np.array([[-6], [-12]])})
    assert all(ok for ok, _ in right), right
    wrong = _otter_cases({"L": np.array([[6], [12]])})
    assert not any(ok for ok, _ in wrong)
    # what Otter shows the student for the hidden case: the mistake named
    assert "sign" in wrong[1][1], wrong[1][1]


def test_an_answer_with_control_characters_is_refused_at_its_part():
    r = owb.check("stoustrup-pole-assignment", {"L": "[-6;\x07 -12]"})
    part = r.part("L")
    assert part["verdict"] == "unreadable" and "control character" in part["feedback"], part


# ---- the float commands against python-control (the cross-checks, run every time) ------------


def _random_system(rng, n, stable):
    a = rng.normal(size=(n, n))
    if stable:
        a -= (max(np.linalg.eigvals(a).real) + 0.5) * np.eye(n)
    b = rng.normal(size=(n, 1))
    c = rng.normal(size=(1, n))
    # two decimals, so that what owb reads is exactly what python-control gets
    return np.round(a, 2), np.round(b, 2), np.round(c, 2)


def test_dlqe_agrees_with_python_control():
    control = pytest.importorskip("control")
    rng = np.random.default_rng(11)
    compared = 0
    for n in (2, 3, 4):
        for _ in range(4):
            a, _, c = _random_system(rng, n, False)
            a = np.round(a / (max(abs(np.linalg.eigvals(a))) + 0.1), 2)
            g, qn, rn = np.eye(n), np.eye(n), np.array([[1.0]])
            expected, p_expected, _ = control.dlqe(a, g, c, qn, rn)
            r = owb.dlqe(a, c, qn=qn, rn=rn, g=g)
            assert np.allclose(r.array("gain"), expected, rtol=1e-8, atol=1e-10), (a, c)
            assert np.allclose(r.array("p"), p_expected, rtol=1e-8, atol=1e-10)
            compared += 1
    assert compared == 12


def test_zoh_agrees_with_python_control_c2d():
    control = pytest.importorskip("control")
    rng = np.random.default_rng(12)
    for n in (2, 3, 5):
        for period in ("1/10", "1/2", "2"):
            a, b, c = _random_system(rng, n, False)
            t = float(Fraction(period))
            expected = control.c2d(control.ss(a, b, c, 0), t, "zoh")
            r = owb.zoh(a, b, period=period)
            assert np.allclose(r.array("phi"), expected.A, rtol=1e-9, atol=1e-12), (a, period)
            assert np.allclose(r.array("gamma"), expected.B, rtol=1e-9, atol=1e-12)


def test_kalman_agrees_with_python_control_lqe():
    control = pytest.importorskip("control")
    rng = np.random.default_rng(13)
    for n in (2, 3, 4):
        for _ in range(3):
            a, b, c = _random_system(rng, n, True)
            expected, _, _ = control.lqe(a, b, c, 1.0, 0.1)
            r = owb.kalman(a, b, c, input_noise=1, output_noise=Fraction(1, 10))
            kalman = next(m for m in r.comparison if m["method"] == "kalman")
            assert np.allclose(np.array(kalman["gain"]), expected, rtol=1e-8, atol=1e-10), (a, b, c)


def test_a_verification_shows_as_a_table_in_jupyter():
    r = owb.verify("stoustrup-pole-assignment", folder=str(REPO / "worked_examples"))
    assert r.summary["mismatch"] == 0
    table = r._repr_html_()
    assert table.count("<tr>") == 1 + len(r.examples[0]["claims"])
    assert "✔" in table and "<code>L</code>" in table
