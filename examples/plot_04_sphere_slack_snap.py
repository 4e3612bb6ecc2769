"""
# A payload sphere through slack and snap

A 12.2 kg sphere hangs on 18.9 m of 1.6 mm steel cable, and the top of the cable is
heaved by 85 mm at 1.27 Hz, near the system's vertical resonance. Over part of each
cycle the sphere falls faster than the top: the cable goes slack (zero tension), then
snaps taut and the tension jumps to about twice the static value. This is the
built-in scene `"sphere127"`, the payload-sphere case of Sun, Zhu & LaRosa (Ocean
Engineering 38, 2011). The 3D cable model is fully nonlinear, so it runs through the
slack phases and the snaps.
"""

# %%
# ## Statics
#
# The static tension at the top, T0, is the submerged weight of cable and sphere.
import matplotlib.pyplot as plt

import symcable as sc

scene = sc.load_scene("sphere127")
static = sc.solve_static(scene)
T0 = static.lines["cable"].fairlead_tension           # N, end B of the cable: the top
motion = scene.points["top"].motion
print(f"static top tension T0 = {T0:.2f} N")
print(f"top motion: {motion.amplitude[2] * 1e3:.0f} mm at {1.0 / motion.period:.2f} Hz")

# %%
# ## The run
#
# Ten periods from rest (the motion ramps in over the first one). `simulate` picks the
# time step for 1 % of the tension range by comparing runs at halved steps, and
# reports the slack phases and snaps it saw; its warning says that snap peaks converge
# slowly in the time step.
period = motion.period
run = sc.simulate(scene, duration=10 * period)
print(run.summary())
cable = run.lines["cable"]
dt = run.stats["dt"]

# %%
# The warning advises checking the peaks at half the step: run again at a fixed `dt / 2`
# and compare the largest tension over the last three periods.
check = sc.simulate(scene, duration=10 * period, dt=dt / 2)

t = run.time
top = cable.fairlead_tension                          # N
last = t >= t[-1] - 3 * period
t2 = check.time
top2 = check.lines["cable"].fairlead_tension
last2 = t2 >= t2[-1] - 3 * period
slack = top < 0.02 * T0                 # slack: the top carries less than 2 % of T0
print(f"time step {dt * 1e3:.3f} ms; over the last three periods:")
print(f"  top tension {top[last].min():.3f} to {top[last].max():.1f} N "
      f"= {top[last].max() / T0:.2f} T0 at the snap")
print(f"  at dt/2 the snap peak is {top2[last2].max():.1f} N = {top2[last2].max() / T0:.2f} T0 "
      f"({100 * (top2[last2].max() / top[last].max() - 1):+.1f} %)")
print(f"  top tension below 2 % of T0 for {100 * slack[last].mean():.1f} % of the time")
print(f"whole run: some segment slack {100 * cable.stats['slack_fraction']:.1f} % of the time, "
      f"{cable.stats['snaps']} slack-to-taut events (summed over the segments)")

# %%
# ## Tension at the top
#
# Each cycle: the tension falls to zero as the top moves down faster than the sphere
# can follow, stays near zero while the cable is slack (shaded), then the cable comes
# taut again and stops the falling sphere: the tension climbs to about twice T0. The
# run at half the step lies on top of the first one.
fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 5.5), sharex=True, constrained_layout=True,
                               gridspec_kw={"height_ratios": [1, 2]})
z_top = run.points["top"]["position"][:, 2] - scene.points["top"].position[2]
ax1.plot(t[last], 1e3 * z_top[last], color="tab:gray")
ax1.set_ylabel("top heave (mm)")
ax1.set_title("Payload sphere heaved at 1.27 Hz: top tension over the last three periods")
ax1.grid(alpha=0.3)
ax2.plot(t[last], top[last] / T0, label=f"dt = {dt * 1e3:.2f} ms (simulate's choice)")
ax2.plot(t2[last2], top2[last2] / T0, "--", label=f"dt = {dt / 2 * 1e3:.2f} ms (check)")
ax2.fill_between(t[last], 0, 1, where=slack[last], transform=ax2.get_xaxis_transform(),
                 color="tab:red", alpha=0.25, lw=0, label="slack (< 2 % of T0)")
ax2.axhline(1.0, color="0.5", lw=0.8, ls=":")
ax2.set_xlabel("time (s)")
ax2.set_ylabel("top tension / T0 (-)")
ax2.legend(loc="upper left", ncol=3, fontsize="small")
ax2.set_ylim(-0.1, 2.5)
ax2.grid(alpha=0.3)
fig.savefig("plot_04_sphere_slack_snap.png", dpi=120)
