"""Measure the reference-frame choices of studies/rod_notes/rod14.md: the Hessian of a bending-and-twist
energy on N edges with (d) each edge's frame from its own anchor (as symcable.models.rod.rod) and
(b) space-parallel transport along the rod from the clamp (every frame a function of all the
edges before it). Prints (nnz of the Hessian, n_q, SX instructions, seconds to build it).
Run: PYTHONPATH=. python studies/rod_notes/rod14_frames_measure.py"""
import casadi as ca, time
from symcable.models.rod.frames import transport
def build(N, chain):
    X = ca.SX.sym('x', 3, N + 1); th = ca.SX.sym('th', N)
    e = [X[:, j + 1] - X[:, j] for j in range(N)]; t = [ej / ca.norm_2(ej) for ej in e]
    t0 = ca.DM([1, 0, 0]); u0 = ca.DM([0, 0, 1])
    d1 = []
    for j in range(N):
        if chain:  # (b): space-parallel transport along the rod from the clamp's frame
            d1.append(transport(t0 if j == 0 else t[j - 1], t[j], u0 if j == 0 else d1[-1]))
        else:      # (d): each edge from its own anchor
            d1.append(transport(t0, t[j], u0))
    E = 0
    for i in range(1, N):
        kb = 2 * ca.cross(e[i-1], e[i]) / (ca.norm_2(e[i-1]) * ca.norm_2(e[i]) + ca.dot(e[i-1], e[i]))
        for j in (i - 1, i):
            m1 = ca.cos(th[j]) * d1[j] + ca.sin(th[j]) * ca.cross(t[j], d1[j])
            E += ca.dot(kb, m1) ** 2 + 2 * ca.dot(kb, ca.cross(t[j], m1)) ** 2
        if not chain:
            mv = transport(t[i-1], t[i], d1[i-1])
            E += (th[i] - th[i-1] + ca.atan2(ca.dot(ca.cross(mv, d1[i]), t[i]), ca.dot(mv, d1[i]))) ** 2
        else:
            E += (th[i] - th[i-1]) ** 2
    q = ca.vertcat(ca.vec(ca.vertcat(X[:, 1:], ca.DM.zeros(0, N))), th)
    q = ca.vertcat(*[ca.vertcat(X[:, j + 1], th[j]) for j in range(N)])
    g = ca.gradient(E, q); t1 = time.time(); H = ca.jacobian(g, q)
    f = ca.Function('h', [q, X[:, 0]], [H])
    return H.nnz(), q.numel(), f.n_instructions(), time.time() - t1
for N in (20, 40, 80):
    print(N, 'anchored', build(N, False), 'chain', build(N, True), flush=True)
