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

# The values the course's examples print beside those above, computed here too (none is typed):
A = np.array([[2, -3], [4, -5]], float)
C = np.array([[-3, 2]], float)
K = observer_gain(A, C, [0, 0])
E = A - K @ C
steps = next(k for k in range(1, 5) if np.allclose(np.linalg.matrix_power(E, k), 0))
print("dead-beat steps (first k with (A - KC)^k = 0):", steps)
K = observer_gain(A, C, [0.5, 0.25])
Lc = np.linalg.solve(A, K)
print("current estimator polynomial det(zI - (A - Lc C A)):", np.poly(A - Lc @ C @ A))
# reduced order, ladder at x1: error polynomial and the direct noise gain of D_y = [1; L]
A = np.array([[-2, 1, 0], [1, -2, 1], [0, 1, -2]], float)
L = observer_gain(A[1:, 1:], A[0:1, 1:], [-4, -4])
print("ladder reduced-order error polynomial:", np.poly(A[1:, 1:] - L @ A[0:1, 1:]))
print("ladder sum of D_y^2:", float(np.sum(np.vstack([[[1.0]], L]) ** 2)))
# reduced order, Stoustrup's plant: Q = [C; e1] (C completed with the first unit row)
A = np.array([[2, -3], [4, -5]], float)
Q = np.array([[-3, 2], [1, 0]], float)
Ab = Q @ A @ np.linalg.inv(Q)
print("Stoustrup reduced-order L (pole -4):", observer_gain(Ab[1:, 1:], Ab[0:1, 1:], [-4]).ravel())
# detectability: the unobservable modes (eigenvalues of A on ker O) and the observer polynomial
for A, C in (([[-1, 0], [1, -1]], [[1, 0]]), ([[1, 0], [0, -1]], [[0, 1]])):
    A, C = np.array(A, float), np.array(C, float)
    O = np.vstack([C, C @ A])
    _, s, vt = np.linalg.svd(O)
    V = vt[np.sum(s > 1e-9):].T           # ker O
    modes = np.linalg.eigvals(V.T @ A @ V)
    print("unobservable modes", modes, "detectable:", "yes" if np.all(modes.real < 0) else "no")
K = np.array([[2.0], [0.0]])
print("detectable observer polynomial:", np.poly(np.array([[-1, 0], [1, -1]]) - K @ np.array([[1, 0]])))
