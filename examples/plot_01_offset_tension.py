"""
# Offset–tension curve of a catenary mooring

A floating platform held by three catenary chains: how hard do the lines pull it back
when it drifts, and how much tension does the most loaded line carry? This example
builds the three-line mooring of the OC3-Hywind spar (Jonkman, *Definition of the
Floating System for Phase IV of OC3*, NREL/TP-500-47535, 2010) around a rigid body and
sweeps the body in surge with `sc.offset_sweep`: at every offset the lines are solved in
static equilibrium, and the restoring force on the body and the tension of each line are
returned.
"""

# %%
# ## The mooring
#
# 320 m of water, three chains of 902.2 m at 120° from each other, anchors on the
# seabed at 853.87 m from the spar's axis, fairleads 70 m below the water line at
# 5.2 m from it. The spar is a `kind = "fixed"` body: the sweep moves it to each offset
# and holds it there. Each line has 20 segments.
import math

import matplotlib.pyplot as plt
import numpy as np

import symcable as sc

DEPTH = 320.0                          # m
R_ANCHOR, R_FAIRLEAD = 853.87, 5.2     # m, from the spar's axis
Z_FAIRLEAD = -70.0                     # m
LENGTH = 902.2                         # m, unstretched chain length

points, lines = {}, []
for k in range(3):
    heading = math.radians(180.0 + 120.0 * k)   # line 1 points upwind, along -x
    c, s = math.cos(heading), math.sin(heading)
    points[f"anchor{k + 1}"] = {"kind": "fixed",
                                "position": [R_ANCHOR * c, R_ANCHOR * s, -DEPTH]}
    lines.append({"name": f"line{k + 1}", "end_a": f"anchor{k + 1}",
                  # the fairlead: a point fixed on the body, in body axes (m)
                  "end_b": f"spar@[{R_FAIRLEAD * c}, {R_FAIRLEAD * s}, {Z_FAIRLEAD}]",
                  "sections": [{"type": "chain", "length": LENGTH, "segments": 20}]})

scene = sc.load_scene({
    "name": "OC3-Hywind spar, three catenary chains",
    "model": "cable3d",
    "environment": {"depth": DEPTH, "water_density": 1025.0},
    "line_types": {"chain": {"EA": 384.243e6, "mass": 77.7066, "diameter": 0.09}},
    "points": points,
    "bodies": {"spar": {"kind": "fixed", "position": [0.0, 0.0, 0.0]}},
    "lines": lines,
})

# %%
# ## The sweep
#
# `sc.offsets_along("surge", -20, 20, 41)` gives 41 offset rows (dx, dy, dz, droll,
# dpitch, dyaw) from −20 m to +20 m in surge. The whole sweep is one call.
sweep = sc.offset_sweep(scene, "spar", sc.offsets_along("surge", -20.0, 20.0, 41))
print(sweep.summary())

surge = sweep.offsets[:, 0]                 # m
fx = sweep.force[:, 0]                      # N, restoring force along x
tension = sweep.tension_b                   # N, (offsets, lines): tension at each fairlead
k_surge = sweep.stiffness[0, 0]             # N/m, exact tangent at zero offset

i0 = int(np.argmin(np.abs(surge)))
print(f"\nall {int(sweep.converged.sum())} of {len(surge)} offsets converged")
print(f"surge stiffness at zero offset: {k_surge / 1e3:.1f} kN/m")
print(f"vertical pull of the lines on the spar at zero offset: {-sweep.force[i0, 2] / 1e6:.3f} MN")
print(f"fairlead pretension: {tension[i0, 0] / 1e3:.1f} kN per line")
for x in (-20.0, 20.0):
    i = int(np.argmin(np.abs(surge - x)))
    print(f"at surge {x:+.0f} m: restoring force {fx[i] / 1e3:+.1f} kN, "
          f"largest line tension {tension[i].max() / 1e3:.1f} kN "
          f"({sweep.line_names[int(np.argmax(tension[i]))]})")

# %%
# ## The curves
#
# Left: the restoring force against surge, with the linear spring of the exact
# stiffness at zero offset dashed. The curve is not symmetric: in positive surge line 1
# (anchored along −x) lifts off the seabed and stiffens fast; in negative surge lines 2
# and 3 take the load, each at 60° to the motion, and the mooring is softer than its
# tangent. Right: each line's fairlead tension (lines 2 and 3 are equal by symmetry).
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.2), constrained_layout=True)
ax1.plot(surge, fx / 1e3, "o-", ms=3, label="symcable, lines in equilibrium")
ax1.plot(surge, -k_surge * surge / 1e3, "--", color="0.4",
         label=f"linear, K = {k_surge / 1e3:.1f} kN/m")
ax1.axhline(0.0, color="0.8", lw=0.8)
ax1.set_xlabel("surge offset (m)")
ax1.set_ylabel("restoring force $F_x$ (kN)")
ax1.set_title("Restoring force of the mooring")
ax1.legend()
ax1.grid(alpha=0.3)
for j, (name, style) in enumerate(zip(sweep.line_names, ["-", "-", "--"])):
    ax2.plot(surge, tension[:, j] / 1e3, style, lw=2, label=name)
ax2.set_xlabel("surge offset (m)")
ax2.set_ylabel("fairlead tension (kN)")
ax2.set_title("Line tensions")
ax2.legend()
ax2.grid(alpha=0.3)
fig.savefig("plot_01_offset_tension.png", dpi=120)
