"""
# A towed body in a turn

A ship tows a 9500 kg body on 480 m of cable (355 m bare cable above 125 m of faired
cable) at 12 knots, then turns 270° to port. The built-in scene `"towed_body"` is the
towed system of Sun, Zhu & LaRosa (*Dynamic modeling of cable towed body using nodal
position finite element method*, Ocean Engineering 38, 2011). This example finds the
steady tow, then follows the body through the turn: where does it go, how deep does it
run, and how hard does the cable pull on the ship?
"""

# %%
# ## The scene
#
# The towpoint (`points.ship`) moves with `kind = "tow"`: straight at 6.17 m/s along
# +x, then a turn of 300 m radius. The built-in scene runs straight for 120 s before
# turning; to keep this example short the turn here starts after 10 s. A scene is
# frozen once loaded: change it through its dict and load it again.
import matplotlib.pyplot as plt
import numpy as np

import symcable as sc

layout = sc.load_scene("towed_body").to_dict()
tow = layout["points"]["ship"]["motion"]
tow["turns"] = [{"after": 10.0, "radius": 300.0, "angle": 270.0}]  # s, m, deg to port
scene = sc.load_scene(layout)
print(f"tow speed {tow['speed']:.2f} m/s ({tow['speed'] * 3600 / 1852:.1f} kn), "
      f"turn radius {tow['turns'][0]['radius']:.0f} m")

# %%
# ## The run
#
# A scene whose towpoints all move at one velocity starts from its **steady tow**: the
# static solution in the frame moving with the ship, every node moving at the tow
# speed, so the first seconds are already the towed state. 280 s cover the straight
# run, the whole 270° turn (229 s at this speed and radius) and 40 s on the new
# heading.
run = sc.simulate(scene, duration=280.0)
print(run.summary())

t = run.time
ship = run.points["ship"]["position"]          # (n_t, 3) m
body = run.bodies["fish"]["position"]          # (n_t, 3) m, the body's reference point
# the line "tow" runs from the ship (end A) to the body (end B): the cable's pull on
# the ship is its end-A tension
pull = run.lines["tow"].anchor_tension         # N
depth = -body[:, 2]                            # m
layback = np.linalg.norm(ship[:, :2] - body[:, :2], axis=1)

turn = tow["turns"][0]
t_in = turn["after"]                                                   # s
t_out = t_in + np.radians(turn["angle"]) * turn["radius"] / tow["speed"]
centre = np.array([tow["speed"] * t_in, turn["radius"]])              # m: 300 m to port
from_centre = np.linalg.norm(body[:, :2] - centre, axis=1)
turning = (t > t_in) & (t <= t_out)
after = t > t_out

print(f"start of the run: {run.stats['start']}")
print(f"steady tow: towpoint tension {pull[0] / 1e3:.1f} kN, body depth {depth[0]:.1f} m, "
      f"layback {layback[0]:.1f} m")
print(f"turn from {t_in:.0f} s to {t_out:.0f} s: the body comes within "
      f"{from_centre[turning].min():.0f} m of the centre (ship {turn['radius']:.0f} m), "
      f"sinks to {depth[turning].max():.1f} m; "
      f"towpoint tension down to {pull[turning].min() / 1e3:.1f} kN")
print(f"after the turn: towpoint tension up to {pull[after].max() / 1e3:.1f} kN "
      f"as the body is pulled back to speed")

# %%
# ## Tracks, depth and tension
#
# In the turn the body runs on a smaller circle than the ship, so it moves slower
# through the water: the cable's drag holds it up less, it sinks about 40 m and the
# towpoint tension drops by a fifth. When the ship straightens out the body is pulled
# back to speed: the tension overshoots its steady value while the body climbs.
fig = plt.figure(figsize=(11, 4.8), constrained_layout=True)
grid = fig.add_gridspec(2, 2, width_ratios=[1.1, 1])
ax_plan = fig.add_subplot(grid[:, 0])
ax_depth = fig.add_subplot(grid[0, 1])
ax_tension = fig.add_subplot(grid[1, 1], sharex=ax_depth)

ax_plan.plot(ship[:, 0], ship[:, 1], label="ship (towpoint)")
ax_plan.plot(body[:, 0], body[:, 1], label="towed body")
for tk in np.arange(0.0, t[-1] + 1.0, 60.0):
    k = int(np.argmin(np.abs(t - tk)))
    ax_plan.plot([ship[k, 0], body[k, 0]], [ship[k, 1], body[k, 1]], ":", color="0.6", lw=1)
ax_plan.plot(*centre, "+", color="k", label="centre of the turn")
ax_plan.plot([ship[0, 0], body[0, 0]], [ship[0, 1], body[0, 1]], "o", color="k", ms=4,
             label="start (t = 0)")
ax_plan.set_aspect("equal")
ax_plan.set_xlabel("x (m)")
ax_plan.set_ylabel("y (m)")
ax_plan.set_title("Tracks in plan (dotted: ship to body every 60 s)")
ax_plan.legend(loc="upper left")
ax_plan.grid(alpha=0.3)

ax_depth.plot(t, depth, color="tab:orange")
ax_depth.invert_yaxis()
ax_depth.set_ylabel("body depth (m)")
ax_depth.set_title("Towed body (shaded: ship turning)")
ax_depth.grid(alpha=0.3)
ax_tension.plot(t, pull / 1e3, color="tab:blue")
ax_tension.set_ylabel("towpoint tension (kN)")
ax_tension.set_xlabel("time (s)")
ax_tension.grid(alpha=0.3)
for ax in (ax_depth, ax_tension):
    ax.axvspan(t_in, t_out, color="0.92", zorder=0)
fig.savefig("plot_03_towed_body.png", dpi=120)
