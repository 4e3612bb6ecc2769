"""
# Buckling of a compressed rod

A straight steel rod, pinned at both ends, is shortened step by step: its ends are
pushed together. It carries the compression straight up to the Euler load
P_E = π²EI/L², then buckles sideways, and past that point the load hardly grows while
the rod bows out. This example follows that path with `sc.trace_branch` (static
continuation with a stability check at every point) on the Kirchhoff rod model
(`model = "rod"`) and compares it with Euler's load and the exact elastica.
"""

# %%
# ## The rod
#
# 10 m of solid steel bar, 50 mm in diameter, weightless (`weight = 0`) and in air, so
# that nothing but the end load bends it: the pure Euler strut. 20 segments.
import math

import matplotlib.pyplot as plt
import numpy as np
from scipy.special import ellipe, ellipk

import symcable as sc

L, d, E, G = 10.0, 0.05, 210e9, 80e9          # m, m, Pa, Pa
area, inertia = math.pi * d**2 / 4, math.pi * d**4 / 64
EI, EA, GJ = E * inertia, E * area, G * 2 * inertia
P_euler = math.pi**2 * EI / L**2               # N, pinned-pinned
print(f"EI = {EI / 1e3:.2f} kN m^2, EA = {EA / 1e6:.1f} MN, "
      f"Euler load P_E = {P_euler / 1e3:.3f} kN")

scene = sc.load_scene({
    "name": "pinned steel strut",
    "model": "rod",
    "environment": {"water_density": 0.0},                   # in air
    "line_types": {"bar": {"EA": EA, "EI": EI, "GJ": GJ, "mass": 7850 * area,
                           "diameter": d, "weight": 0.0}},
    "sections": [{"type": "bar", "length": L, "segments": 20}],
    "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
    "end_b": {"condition": "pinned", "position": [L, 0.0, 0.0]},
})

# %%
# ## Following the branch
#
# `sc.build_mechanism` gives the scene's static problem; `sc.trace_branch` moves one
# parameter along a path and solves the equilibrium at every value, here the x
# coordinate (`component=0`) of end B's position. Before buckling the rod only
# shortens elastically (by P/EA·L, a fraction of a millimetre); past the Euler load the
# straight rod is unstable, and the trace leaves it along its buckling mode.
mech = sc.build_mechanism(scene)
delta_cr = P_euler / EA * L                              # m, shortening at the Euler load
shortening = np.r_[np.array([0.0, 0.5, 0.9, 1.5]) * delta_cr, np.geomspace(2 * delta_cr, 0.4, 16)]
branch = sc.trace_branch(mech, "end_b.position", L - shortening, component=0)

force = branch.output("end_force_b")[:, 0]              # N, the rod's push on end B (+x)
positions = branch.output("positions")                   # (points, nodes, 3) m
lateral = np.linalg.norm(positions[:, :, 1:], axis=2)    # m, sideways deflection
bow = lateral.max(axis=1)
first = int(np.argmax([pt.left for pt in branch.points]))
print(f"{len(branch.points)} equilibria in {branch.stats['wall_time']:.1f} s, "
      f"all stable: {all(pt.stable for pt in branch.points)}")
print(f"straight at {force[first - 1] / 1e3:.3f} kN = {force[first - 1] / P_euler:.2f} P_E "
      f"(shortened {shortening[first - 1] * 1e3:.2f} mm)")
print(f"buckled at the next point, {shortening[first] * 1e3:.2f} mm: "
      f"load {force[first] / 1e3:.3f} kN = {force[first] / P_euler:.4f} P_E "
      "(the 20-segment rod's critical load)")

# %%
# ## The elastica
#
# The inextensible pinned elastica, with k = sin(θ₀/2) for the end slope θ₀:
# P/P_E = (2K(k)/π)², shortening Δ/L = 2(1 − E(k)/K(k)), bow at midspan δ/L = k/K(k)
# (K, E the complete elliptic integrals, SciPy's with parameter m = k²).
k = np.linspace(0.0, 0.21, 200)                          # up to 0.44 m of shortening
K, Ek = ellipk(k**2), ellipe(k**2)
elastica_load = (2 * K / math.pi) ** 2                   # P / P_E
elastica_shortening = 2 * (1 - Ek / K) * L               # m
elastica_bow = k / K * L                                 # m
for target in (0.1, 0.4):
    i = int(np.argmin(np.abs(shortening - target)))
    P_el = np.interp(shortening[i], elastica_shortening, elastica_load) * P_euler
    bow_el = np.interp(shortening[i], elastica_shortening, elastica_bow)
    print(f"shortened {shortening[i] * 1e3:.0f} mm: load {force[i] / 1e3:.3f} kN "
          f"(elastica {P_el / 1e3:.3f} kN), midspan bow {bow[i]:.3f} m (elastica {bow_el:.3f} m)")

# %%
# ## Load against shortening, and the buckled shapes
#
# Left: the load rises steeply while the rod is straight (the inset zooms on the first
# half millimetre), levels off at the Euler load and grows only slowly after: a strut
# has almost no reserve past buckling. Right: the rod's shape at a few points of the
# branch.
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10.5, 4.2), constrained_layout=True)
ax1.plot(shortening * 1e3, force / P_euler, "o", ms=4, label="symcable rod, 20 segments")
ax1.plot(elastica_shortening * 1e3, elastica_load, "-", color="0.3", lw=1,
         label="inextensible elastica")
ax1.plot([0.0, delta_cr * 1e3], [0.0, 1.0], "-", color="0.3", lw=1)
ax1.axhline(1.0, color="tab:red", ls="--", lw=1, label="Euler load $P_E$")
ax1.set_xlabel("end shortening (mm)")
ax1.set_ylabel("axial load / $P_E$ (-)")
ax1.set_title(f"Pinned strut, $P_E$ = {P_euler / 1e3:.2f} kN")
ax1.set_ylim(0.0, 1.25)
ax1.legend(loc="lower right")
ax1.grid(alpha=0.3)
zoom = ax1.inset_axes([0.3, 0.42, 0.4, 0.3])
zoom.plot([0.0, delta_cr * 1e3, 0.5], [0.0, 1.0, 1.0], "-", color="0.3", lw=1)
zoom.plot(shortening[:first + 2] * 1e3, force[:first + 2] / P_euler, "o", ms=4)
zoom.axhline(1.0, color="tab:red", ls="--", lw=1)
zoom.set_xlim(-0.02, 0.5)
zoom.set_ylim(0.0, 1.2)
zoom.set_xlabel("shortening (mm)", fontsize="small")
zoom.tick_params(labelsize="small")
zoom.grid(alpha=0.3)

sign = np.sign(positions[-1, len(positions[-1]) // 2, 1:])    # the plane it buckled in
for target in (0.025, 0.1, 0.2, 0.4):                          # m of shortening
    i = int(np.argmin(np.abs(shortening - target)))
    x = positions[i, :, 0]
    w = positions[i, :, 1:] @ sign / np.linalg.norm(sign)
    ax2.plot(x, w, "o-", ms=2.5, label=f"shortened {shortening[i] * 1e3:.0f} mm")
ax2.plot([0.0, L], [0.0, 0.0], "-", color="0.6", lw=1, label="straight")
ax2.set_xlabel("x (m)")
ax2.set_ylabel("lateral deflection (m)")
ax2.set_title("Buckled shapes")
ax2.legend(fontsize="small")
ax2.grid(alpha=0.3)
fig.savefig("plot_05_rod_buckling.png", dpi=120)
