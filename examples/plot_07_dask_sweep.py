"""
# A parameter sweep on Dask

A design question needs many solves of one scene with a few numbers changed: here, how
does the fairlead tension of a catenary mooring line depend on the vessel's offset, for
three chain lengths? `sc.run_sweep` takes the scene, the analysis, the outputs to keep
and a table of cases, and runs the cases as independent tasks on a Dask cluster (a
local one of two worker processes here; any Dask scheduler by its address). It needs
Dask: `pip install "symcable[sweep]"`.
"""

# %%
# ## The cases
#
# The built-in `"oc3"` scene: one OC3-Hywind chain in 320 m of water, the fairlead 70 m
# below the surface at x = −5.2 m, the anchor at x = −853.87 m. A `grid` gives every
# combination of its lists: 3 chain lengths × 9 fairlead positions = 27 static solves.
# Keys are dotted paths into the scene's layout (`sections[0].length`,
# `end_b.position`). `codegen = False` runs every case in the CasADi virtual machine,
# with no C to compile first.
import os
import socket
from collections import Counter

import matplotlib.pyplot as plt
import numpy as np

import symcable as sc

lengths = [892.2, 902.2, 912.2]                        # m, the nominal ±10 m
offsets = np.linspace(-20.0, 20.0, 9)                  # m, fairlead moved along +x
fairlead_x, fairlead_z = -5.2, -70.0                   # m, the nominal fairlead
cases = {
    "name": "OC3 line: fairlead offset and chain length",
    "scene": sc.load_scene("oc3"),
    "analysis": "static",
    "outputs": ["fairlead_tension", "anchor_tension", "grounded_length"],
    "codegen": False,
    "grid": {"sections[0].length": lengths,
             "end_b.position": [[fairlead_x + float(dx), fairlead_z] for dx in offsets]},
}

# %%
# ## Running it
#
# `workers=2` starts a local cluster of two worker processes, one thread each, listening
# on 127.0.0.1 only, and closes it at the end. The first case runs here, in this
# process (it builds what the others reuse, and would compile the generated C), the
# rest on the workers. Dask starts its workers as new Python
# processes that import this script: the work runs under
# `if __name__ == "__main__":`, as with any Python multiprocessing.
# Each case's result is kept in memory here; give `out="folder"` to write one file per
# case as it finishes, so that an interrupted sweep run again does only what is missing.
if __name__ == "__main__":
    result = sc.run_sweep(cases, workers=2)
    print("\n".join(result.summary().splitlines()[:3]))
    solve_time = sum(c.wall_time for c in result.succeeded)    # s, each case's own run
    print(f"{len(result.succeeded)} of {len(result)} cases solved: wall time "
          f"{result.stats['wall_time']:.1f} s for {solve_time:.1f} s of solves")
    # each case records the process that ran it ("host:pid"); the first runs in this one
    here = f"{socket.gethostname()}:{os.getpid()}"
    per_process = Counter("this process" if c.worker == here
                          else "worker " + c.worker.split(":")[-1] for c in result.succeeded)
    print("cases per process:", ", ".join(f"{k} {v}" for k, v in sorted(per_process.items())))

# %%
# ## The table
#
# Each case carries its overrides and its output values (SI units).
if __name__ == "__main__":
    table = {}                                          # length -> (offset, outputs) rows
    for case in result.succeeded:
        length = case.overrides["sections[0].length"]
        dx = case.overrides["end_b.position"][0] - fairlead_x
        table.setdefault(length, []).append((dx, case.values["fairlead_tension"],
                                             case.values["grounded_length"]))
    for length in lengths:
        rows = np.array(sorted(table[length]))
        table[length] = rows
        print(f"chain {length:.1f} m: fairlead tension {rows[0, 1] / 1e3:.0f} kN at "
              f"{rows[0, 0]:+.0f} m, {rows[len(rows) // 2, 1] / 1e3:.0f} kN at 0 m, "
              f"{rows[-1, 1] / 1e3:.0f} kN at {rows[-1, 0]:+.0f} m")

# %%
# ## Tension against offset
#
# Moving the fairlead away from the anchor (+x) lifts chain off the seabed until none
# is left on it; from there the line can only stretch and the tension climbs steeply.
# 10 m more chain moves the whole curve about 10 m to the right.
if __name__ == "__main__":
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10.5, 4.2), constrained_layout=True)
    for length in lengths:
        rows = table[length]
        ax1.plot(rows[:, 0], rows[:, 1] / 1e3, "o-", ms=4, label=f"chain {length:.1f} m")
        ax2.plot(rows[:, 0], rows[:, 2], "o-", ms=4, label=f"chain {length:.1f} m")
    ax1.set_xlabel("fairlead offset away from the anchor (m)")
    ax1.set_ylabel("fairlead tension (kN)")
    ax1.set_title("Fairlead tension")
    ax1.legend()
    ax1.grid(alpha=0.3)
    ax2.set_xlabel("fairlead offset away from the anchor (m)")
    ax2.set_ylabel("chain on the seabed (m)")
    ax2.set_title("Grounded length")
    ax2.legend()
    ax2.grid(alpha=0.3)
    fig.suptitle("OC3 chain, 27 static cases on a local Dask cluster of 2 workers")
    fig.savefig("plot_07_dask_sweep.png", dpi=120)
