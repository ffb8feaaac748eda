"""Numbers for the course's worked examples beyond the five documents, computed once by an
independent implementation (python-control 0.10.1, with numpy and scipy) and recorded in
worked_examples/course-*.toml as *printed* values, with this script as their source. The
workbench recomputes each exactly and compares; these numbers are never its expected values.

Run by hand (not in CI):  pip install control==0.10.1 && python3 tests/crosscheck/python_control.py
"""
import control
import numpy as np

np.set_printoptions(precision=12, suppress=False)


def observer_gain(a, c, poles):
    # the observer gain of (A, C) is the transpose of the state-feedback gain of (A', C')
    return control.acker(np.array(a).T, np.array(c).T, poles).T


print("python-control", control.__version__)

# Discrete time: Stoustrup's matrices taken as x(k+1) = A x(k), y(k) = C x(k)
A = [[2, -3], [4, -5]]
C = [[-3, 2]]
print("dead-beat K (poles 0, 0):", observer_gain(A, C, [0, 0]).ravel())
print("prediction K (poles 1/2, 1/4):", observer_gain(A, C, [0.5, 0.25]).ravel())
K = observer_gain(A, C, [0.5, 0.25])
print("current L_c = A^-1 K:", np.linalg.solve(np.array(A, float), K).ravel())

# Zero-order hold of the double integrator, T = 0.1
sysd = control.c2d(control.ss([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]]), 0.1, "zoh")
print("ZOH Phi:", sysd.A.ravel(), "Gamma:", sysd.B.ravel())

# Reduced order (Gopinath): Baranowski's RC ladder measured at x1; z = x, A22 and A12 blocks
A = np.array([[-2, 1, 0], [1, -2, 1], [0, 1, -2]], float)
A12, A22 = A[0:1, 1:], A[1:, 1:]
print("reduced-order L, ladder, poles -4, -4:", observer_gain(A22, A12, [-4, -4]).ravel())

# Detectable: Stoustrup's series connection measured at x1 (x2 unobservable, mode -1)
# observable part in the coordinates T = [e1 e2]: A_oo = -1, C_o = 1
print("detectable K_o (pole -3):", observer_gain([[-1]], [[1]], [-3]).ravel())

# Discrete Kalman filter of the sampled double integrator (T = 0.1, process noise through Gamma)
Ad = np.array([[1, 0.1], [0, 1]])
Gd = np.array([[0.005], [0.1]])
Cd = np.array([[1, 0]])
for rn in (0.01, 1 / 7):
    L, P, E = control.dlqe(Ad, Gd, Cd, 1.0, rn)
    print(f"dlqe R_n = {rn:.6g}: L", np.round(L.ravel(), 8), "P", np.round(P.ravel(), 8))
