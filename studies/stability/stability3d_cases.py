"""The rows of the cable3d stability study (run3d.py): the study line of
``studies/cable3d_case.py`` ("smooth": fairlead [1, 2, 0.5] m, T = 8 s, 10 segments,
friction 0.5 on a damped bed) pushed to its extremes, one change per row."""
from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from typing import Callable

import cable3d_case as case3d

T = case3d.PERIOD
PERIODS = 8               # time-run length (the base line's transient: 2e-4 of the range after 8)
REF_STEPS = 3200          # the reference: GA1 at T/3200 over the same periods


@dataclass
class Row:
    """One row. ``make()`` returns the scene dict; ``dt`` (s) the step of the time columns
    (None: GA1/GA2 at T/100, RK4 at its default); ``methods`` the columns run;
    ``codegen`` for the time runs (None: the default); ``ref_steps`` the reference's GA1
    steps per period (None: no reference)."""

    name: str
    group: str
    make: Callable[[], dict]
    param: str = ""
    dt: float | None = None
    periods: int = PERIODS
    methods: tuple = ("ga1", "ga2", "rk4", "shooting", "collocation", "hb")
    codegen: bool | None = None
    ref_steps: int | None = REF_STEPS
    #: (row, row) whose cells' wall times give each method's growth with the segments: a
    #: method not in ``methods`` is then reported with its extrapolated time, not run
    estimate_from: tuple | None = None
    info: dict = field(default_factory=dict)


def base(**kw) -> dict:
    return case3d.scene_dict("smooth", **kw)


def scaled_amplitude(f: float) -> dict:
    d = base(name=f"amplitude x{f:g}")
    mo = d["end_b"]["motion"]
    mo["amplitude"] = [a * f for a in mo["amplitude"]]
    return d


def stiff(k: float) -> dict:
    d = base(name=f"EA x{k:g}")
    d["line_types"]["rope"]["EA"] *= k
    return d


def oblique_current(speed: float = 2.0, angle_deg: float = 60.0) -> dict:
    """A uniform current of ``speed`` m/s at ``angle_deg`` in plan from the line's heading
    (anchor to fairlead, atan2(30, 80) = 20.6 deg from x): 2 m/s at 60 deg pushes the line
    across its plane with 197 N/m of drag against 538 N/m of submerged weight."""
    d = base(name=f"current {speed:g} m/s at {angle_deg:g} deg")
    th = math.atan2(30.0, 80.0) + math.radians(angle_deg)
    d["environment"]["current"] = [speed * math.cos(th), speed * math.sin(th), 0.0]
    return d


def mostly_grounded() -> dict:
    """250 m of the rope (23 segments, ds = 10.9 m) from an anchor moved back along the
    line's heading to (-130, -49, -60) m: about 175 m (70 %) lie straight on the bed, in
    tension at rest (symcable's statics has no static friction), held by friction in motion."""
    d = base(name="mostly on the seabed")
    d["end_a"]["position"] = [-130.0, -49.0, -case3d.DEPTH]
    d["sections"] = [{"type": "rope", "length": 250.0, "segments": 23}]
    return d


def buoyant_section() -> dict:
    """50 m of rope, 20 m of buoyancy modules (30 kg/m, 0.35 m: 68.6 kg/m of net buoyancy),
    60 m of rope: a lazy wave whose arch stands 16 m above the bed."""
    d = base(name="buoyant section")
    d["line_types"]["buoy"] = dict(d["line_types"]["rope"], mass=30.0, diameter=0.35)
    d["sections"] = [{"type": "rope", "length": 50.0, "segments": 5},
                     {"type": "buoy", "length": 20.0, "segments": 4},
                     {"type": "rope", "length": 60.0, "segments": 6}]
    return d


def rows(quick: bool, slack: dict | None, cfl_dt: float) -> list:
    """The rows; ``slack`` the amplitude search's result ({"taut": f, "slack": f}),
    ``cfl_dt`` MoorDyn's CFL-0.1 step of the base line (s)."""
    time_cols = ("ga1", "ga2", "rk4")
    dt_rows = [Row(f"dt = {k} x MoorDyn CFL", "time step", lambda: base(name="dt rows"),
                   f"dt = {k * cfl_dt:.4g} s = T/{T / (k * cfl_dt):.0f}", dt=k * cfl_dt,
                   methods=time_cols) for k in (10, 30)]
    if quick:  # 4 periods against GA1 at T/1600: the test's budget, in the VM
        q = dict(periods=4, ref_steps=1600)
        return [Row("base", "base", lambda: base(name="base"), "study line, 10 segments",
                    methods=("ga1", "rk4", "collocation"), **q),
                Row(dt_rows[1].name, dt_rows[1].group, dt_rows[1].make, dt_rows[1].param,
                    dt=dt_rows[1].dt, methods=time_cols, **q)]
    out = [Row("base", "base", lambda: base(name="base"), "study line, 10 segments"),
           Row("EA x100", "stiffness", lambda: stiff(100.0), "EA = 5e9 N (c = 9129 m/s)"),
           Row("40 segments", "segments", lambda: base(segments=40, name="40 segments"),
               "ds = 2.75 m, n_y = 234"),
           # generated C at 400 segments: simulate had not finished compiling after 25 min
           # (measured, stopped), so the time columns run in the virtual machine there; 2
           # periods, against GA1 at T/200 (a check of the step only)
           Row("400 segments", "segments", lambda: base(segments=400, name="400 segments"),
               "ds = 0.275 m, n_y = 2394", periods=2, methods=("ga1", "ga2"),
               codegen=False, ref_steps=200, estimate_from=("base", "40 segments")),
           *dt_rows]
    if slack and slack.get("taut") and slack.get("slack"):
        ft, fs = slack["taut"], slack["slack"]
        out += [Row("near-slack amplitude", "slack", lambda: scaled_amplitude(ft),
                    f"amplitude x{ft:g} (last taut of the search)"),
                Row("snap amplitude", "slack", lambda: scaled_amplitude(2 * fs),
                    f"amplitude x{2 * fs:g} (twice the first slack)")]
    out += [Row("oblique current 2 m/s", "current", oblique_current, "60 deg off the line's plane"),
            Row("mostly on the seabed", "seabed", mostly_grounded, "250 m, 70 % grounded, friction 0.5"),
            Row("buoyant section", "buoyancy", buoyant_section, "20 m of 68.6 kg/m net buoyancy"),
            Row("touchdown landing", "seabed", lambda: case3d.scene_dict("landing"),
                "heave 1.5 m: a node lands at ~1 m/s")]
    return out


def with_motion_removed(d: dict) -> dict:
    dd = copy.deepcopy(d)
    dd["end_b"].pop("motion", None)
    return dd
