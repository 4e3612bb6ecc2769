"""
# A MoorDyn chain deck under heave

symcable reads MoorDyn v2 input files. This example writes a small deck, a chain
mooring line from an anchor on the seabed to a fairlead at the surface in 50 m of
water, loads it with `sc.load_scene`, solves its static shape, then moves the fairlead
up and down harmonically and follows the fairlead tension in time.
"""

# %%
# ## The deck
#
# A MoorDyn deck has sections headed by `---` lines: line types, points, lines and
# options. Point 1 is the anchor (`Fixed`), point 2 the fairlead (`Vessel`). The chain
# is 410 m long, 390 kg/m, EA = 1.674 GN, with a 0.252 m volume-equivalent diameter
# (MoorDyn's `Diam`), cut into 20 segments. `BA/-zeta = -1` asks for axial damping at
# 100 % of critical on the segments' own axial mode, as MoorDyn reads it. The options
# give the water depth and density and the seabed: its stiffness `kBot`, damping `cBot`
# and friction coefficient.
import matplotlib.pyplot as plt

import symcable as sc

DECK = """\
--------------------- MoorDyn Input File ------------------------------------
A single chain mooring line in 50 m of water
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI    Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2) (-)  (-)    (-)     (-)
chain      0.252   390        1.674e9    -1.0        0     1.37   1.0    0.64    0.0
---------------------- POINT PROPERTIES --------------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     400.0   0.0     -50.0   0      0       0      0
2     Vessel    0.0     0.0     0.0     0      0       0      0
---------------------- LINES -------------------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)     (#)      (#)      (m)       (-)      (-)
1    chain      1        2        410.0     20       -
---------------------- OPTIONS -----------------------------------------------
1025.0     WtrDnsty             water density (kg/m^3)
50.0       WtrDpth              water depth (m)
1.0e5      kBot                 seabed stiffness (Pa/m)
1.0e4      cBot                 seabed damping (Pa-s/m)
0.5        FrictionCoefficient  seabed friction coefficient (-)
------------------------- need this line -------------------------------------
"""

with open("chain_deck.txt", "w") as f:
    f.write(DECK)

scene = sc.load_scene("chain_deck.txt")
print(f"read: model {scene.model.value}, {scene.n_segments} segments, "
      f"{scene.length:.1f} m of chain, water depth {scene.environment.depth:.0f} m")

# %%
# ## Statics
#
# End A is the anchor, end B the fairlead.
static = sc.solve_static(scene)
print(f"static fairlead tension {static.fairlead_tension / 1e3:.1f} kN, "
      f"anchor tension {static.anchor_tension / 1e3:.1f} kN, "
      f"{static.grounded_length:.1f} m of chain on the seabed")

# %%
# ## Heave
#
# The deck does not carry the vessel's motion. Add it to the scene: a harmonic heave of
# the fairlead, 2 m amplitude, 10 s period, `z = 2 sin(2πt/10)` about its position. The
# run starts from the static state at rest and ramps the motion in over its first
# period; the time step is chosen by `simulate` so that the end tensions are within 1 %
# of their range (its default tolerance).
layout = scene.to_dict()
layout["end_b"]["motion"] = {"kind": "harmonic", "period": 10.0,
                             "amplitude": [0.0, 0.0, 2.0],   # m, [x, y, z]
                             "phase_deg": [0.0, 0.0, -90.0]}  # z = A sin(wt)
heaving = sc.load_scene(layout)

run = sc.simulate(heaving, duration=40.0)
print(run.summary())

t = run.time
heave = run.positions[:, -1, 2]          # m, the fairlead's z
late = t >= 20.0                          # the last two periods
tf = run.fairlead_tension
error = run.stats["error_measured"]       # relative to the tension range
print(f"time step {run.stats['dt']:.3f} s, estimated error {100 * error:.2f} % "
      "of the tension range")
print(f"fairlead tension over the last two periods: {tf[late].min() / 1e3:.1f} to "
      f"{tf[late].max() / 1e3:.1f} kN (static {static.fairlead_tension / 1e3:.1f} kN)")
print(f"anchor tension over the last two periods: {run.anchor_tension[late].min() / 1e3:.1f} to "
      f"{run.anchor_tension[late].max() / 1e3:.1f} kN")

# %%
# ## Fairlead tension in time
#
# The tension follows the heave with a phase lead: the chain's drag and inertia add to
# the quasi-static stretch while the fairlead moves up fastest. The upward half of
# the cycle lifts chain off the seabed and costs more tension than the downward half
# gives back, so the tension swings further above its static value than below.
fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 5.5), sharex=True, constrained_layout=True,
                               gridspec_kw={"height_ratios": [1, 2]})
ax1.plot(t, heave, color="tab:gray")
ax1.set_ylabel("fairlead heave (m)")
ax1.set_title("Chain mooring line (MoorDyn deck) under a 2 m, 10 s fairlead heave")
ax1.grid(alpha=0.3)
ax2.plot(t, tf / 1e3, label="fairlead (end B)")
ax2.plot(t, run.anchor_tension / 1e3, label="anchor (end A)")
ax2.axhline(static.fairlead_tension / 1e3, ls="--", color="tab:blue", lw=1,
            label="fairlead, static")
ax2.set_xlabel("time (s)")
ax2.set_ylabel("tension (kN)")
ax2.set_ylim(run.anchor_tension.min() / 1e3 - 120.0, tf.max() / 1e3 + 30.0)
ax2.legend(loc="lower center", ncol=3)
ax2.grid(alpha=0.3)
fig.savefig("plot_02_moordyn_chain_heave.png", dpi=120)
