"""
# Generated C: compiled solves and standalone code

Every symcable analysis is built from CasADi expressions, and CasADi can write them out
as C. With `codegen=True` an analysis compiles its functions (the static Newton solve,
the time step) into a shared library and runs that instead of CasADi's virtual machine:
the same numbers, faster. The library is kept in a build cache, so only the first call
on a new model structure pays for the compiler. `symcable codegen` writes the same C as
standalone source files, with a `main.c`, to build into your own program.

The scene is the built-in `"sphere"`: a 12.2 kg sphere on 18.9 m of steel cable, the
top heaved by 85 mm at 0.807 Hz.
"""

# %%
# ## Compiled against the virtual machine
#
# The same run three times: 20 periods at a fixed step of T/100 (2000 steps).
# The first call with `codegen=True` writes the C and compiles it, which takes tens of
# seconds (unless an earlier run left this model in the build cache, `~/.cache/symcable`
# or `$SYMCABLE_CACHE_DIR`); the second finds it in the cache. `codegen=False` runs the
# virtual machine.
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import symcable as sc

scene = sc.load_scene("sphere")
period = scene.points["top"].motion.period
dt, duration = period / 100, 20 * period


def timed_run(codegen):
    start = time.perf_counter()
    run = sc.simulate(scene, duration=duration, dt=dt, codegen=codegen)
    return run, time.perf_counter() - start


first, t_first = timed_run(True)
second, t_second = timed_run(True)
vm, t_vm = timed_run(False)
for name, run, wall in [("C, first call", first, t_first), ("C, second call", second, t_second),
                        ("virtual machine", vm, t_vm)]:
    print(f"{name:16s} {wall:7.2f} s in all, {run.stats['us_per_step']:6.1f} us per step "
          f"({run.stats['steps']} steps, compiled: {run.stats['compiled']})")
us_c = min(first.stats["us_per_step"], second.stats["us_per_step"])
speedup = vm.stats["us_per_step"] / us_c
top_c = second.lines["cable"].fairlead_tension       # N, tension at the top
top_vm = vm.lines["cable"].fairlead_tension
print(f"per step the compiled code is {speedup:.0f} times faster than the virtual machine")
print(f"largest difference of the top tension, C against the virtual machine: "
      f"{np.max(np.abs(top_c - top_vm)):.2e} N (tension {top_c.min():.1f} to {top_c.max():.1f} N)")

# %%
# ## Standalone C
#
# `symcable codegen SCENE --out DIR` writes the scene's static solve and time step as C
# source, a header with the scene's numbers, a `README.md` that documents every function,
# and a `main.c` that solves the statics and takes time steps from the same start as
# `simulate`. Here the command runs from Python; in a shell it is
# `symcable codegen sphere --out sphere_c`.
exe = shutil.which("symcable") or str(Path(sys.executable).with_name("symcable"))
subprocess.run([exe, "codegen", "sphere", "--out", "sphere_c"], check=True, capture_output=True)
for path in sorted(Path("sphere_c").glob("*.[chm]*")):
    print(f"  {path.name:24s} {path.stat().st_size / 1e3:8.1f} kB")

# %%
# Build it with the system's C compiler (`-O0` compiles fastest; `-O2` runs faster) and
# take the same 2000 steps. `main.c` prints every output, one a line: pick the force on
# the top point at the end and compare with the Python run.
cc = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
standalone = None
if cc is None:
    print("no C compiler found: skipping the build")
else:
    start = time.perf_counter()
    subprocess.run([cc, "-O0", "main.c", "symcable_scene.c", "-lm", "-o", "example"],
                   cwd="sphere_c", check=True)
    t_build = time.perf_counter() - start
    start = time.perf_counter()
    out = subprocess.run(["./example", str(second.stats["steps"])], cwd="sphere_c", check=True,
                         capture_output=True, text=True).stdout
    t_exe = time.perf_counter() - start
    print("\n".join(out.splitlines()[:2]))
    force = [float(re.search(rf"^dyn\.top\.force\[{i}\] = (\S+)$", out, re.M).group(1))
             for i in range(3)]
    standalone = float(np.linalg.norm(force))
    print(f"built in {t_build:.1f} s; {second.stats['steps']} steps and the printout "
          f"in {t_exe:.2f} s")
    print(f"top tension after {second.stats['steps']} steps: standalone C {standalone:.6f} N, "
          f"Python {top_c[-1]:.6f} N")

# %%
# ## The figure
#
# Left: wall time of each call (log scale; the first compiled call is mostly the
# compiler). Right: the top tension of the compiled run and of the virtual machine over
# the last three periods: the same curve.
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True,
                               gridspec_kw={"width_ratios": [1, 1.4]})
labels = ["C, 1st call\n(compiles, unless\nalready cached)", "C, 2nd call\n(cached)",
          "virtual\nmachine"]
walls = [t_first, t_second, t_vm]
bars = ax1.bar(labels, walls, color=["tab:gray", "tab:blue", "tab:orange"])
for bar, run in zip(bars, [first, second, vm]):
    ax1.text(bar.get_x() + bar.get_width() / 2, bar.get_height() * 1.15,
             f"{run.stats['us_per_step']:.0f} µs/step", ha="center", fontsize="small")
ax1.set_yscale("log")
ax1.set_ylim(min(walls) / 3, max(walls) * 4)
ax1.set_ylabel("wall time of the call (s)")
ax1.set_title(f"simulate, {second.stats['steps']} steps")
ax1.grid(alpha=0.3, axis="y")
t = second.time
last = t >= t[-1] - 3 * period
ax2.plot(t[last], top_c[last], label="generated C")
ax2.plot(vm.time[last], top_vm[last], "--", label="virtual machine")
if standalone is not None:
    ax2.plot(t[-1], standalone, "k*", ms=10, label="standalone main.c, last step")
ax2.set_xlabel("time (s)")
ax2.set_ylabel("top tension (N)")
ax2.set_title("Payload sphere at 0.807 Hz: the same answer")
ax2.set_ylim(top_c[last].min() - 5.0, top_c[last].max() + 15.0)
ax2.legend(loc="upper center", ncol=3, fontsize="small")
ax2.grid(alpha=0.3)
fig.savefig("plot_08_generated_c.png", dpi=120)
