"""The peers of the chain study run live: MoorDyn (``moordyn``, the lumped-mass explicit code
whose validation tests the decks come from) and CableDyn (``cabledyn``, implicit
generalized-alpha finite elements in Fortran), each at its own default scheme, on a copy of the
deck and the same fairlead table as symcable. Both are optional (``pip install
"symcable[bench]"``); :func:`available` says which are installed, and a missing one is reported
as "not installed", never an error.

MoorDyn (2.7.2; Python API ``moordyn.Create / Init / Step / GetLineNodeTen / Close``):

* the deck as given, less ``fileIC`` (the quasi-static start it names,
  ``<deck>.ic``, is not in the reference folder; with ``ic_dir`` holding it, it is kept) and
  ``writeLog`` (a log file); ``cfl 0.1`` sets its step (RK2, its default scheme): 3.0 ms for
  WD0050;
* driven as its own validation test drives it (tests/quasi_static_chain.cpp in MoorDyn's
  repository): ``Init`` at rest at the table's first row, then one ``Step`` per table row
  from t = -10 s (MoorDyn's clock starts at 0), the fairlead at the row and its velocity the
  forward difference to the next row, which MoorDyn extrapolates linearly inside the 0.1 s
  call;
* tensions: the top and bottom segments' (``GetLineNodeTen`` of the end nodes: T + damping),
  the quantity of MoorDyn's ``FairTen``.

CableDyn (0.3.0; in-process class ``cabledyn.CableDyn(deck)``, whose constructor solves the
static state; ``step(dt, q, v, a)`` advances with the coupled points' kinematics at t + dt;
``channel("FairTen1")``, ``channel("AnchTen1")``):

* the deck less ``cfl``, ``fileIC`` and ``disableOutTime`` (options it refuses), plus ``dtM``
  (the step) and ``TMax``;
* its coupled points are both ends (6 DOFs); the anchor is passed where it is, the fairlead at
  the table's position, with the central-difference velocity and acceleration of the rows
  (interpolated linearly between rows).

MoorDyn is driven by ``studies/moordyn_driver.py`` (its session: a temporary folder as the
working directory, MoorDyn's output to a log). Wall time (``time.perf_counter``): from reading the deck to the last step, i.e. MoorDyn's
Create + Init (its dynamic-relaxation start) + stepping, CableDyn's constructor (its static
solve) + stepping; the tension reads inside the loop are counted (a few microseconds each).
"""
from __future__ import annotations

import sys
import tempfile
import time
from importlib import metadata
from pathlib import Path

import numpy as np

if str(Path(__file__).resolve().parents[1]) not in sys.path:
    sys.path.append(str(Path(__file__).resolve().parents[1]))
import moordyn_driver  # noqa: E402  (studies/moordyn_driver.py)

#: options each peer must not see (lower case): MoorDyn's log and missing start file;
#: CableDyn's refusals
_MOORDYN_DROP = ("fileic", "writelog")
_CABLEDYN_DROP = ("cfl", "fileic", "disableouttime")


def available() -> dict:
    """{"MoorDyn": version or None, "CableDyn": version or None}: installed peers."""
    out = {}
    for name, module, dist in (("MoorDyn", "moordyn", "moordyn"), ("CableDyn", "cabledyn", "cabledyn")):
        try:
            __import__(module)
            out[name] = metadata.version(dist)
        except Exception:  # noqa: BLE001  (absent, or a broken install: not usable either way)
            out[name] = None
    return out


def _edit_deck(text: str, drop, add=()) -> str:
    """The deck's lines less the OPTIONS whose key (second word) is in ``drop``, with the
    lines ``add`` inserted before the first dropped or the section's last option."""
    lines, out, placed = text.splitlines(), [], False
    for line in lines:
        words = line.split()
        if len(words) >= 2 and words[1].lower() in drop:
            if not placed:
                out.extend(add)
                placed = True
            continue
        out.append(line)
    if not placed and add:
        raise ValueError("deck has no option to replace; cannot place " + ", ".join(add))
    return "\n".join(out) + "\n"


def run_moordyn(deck: Path, rows: np.ndarray, t_end: float, ic_dir: Path | None = None,
                cfl: float | None = None) -> dict:
    """MoorDyn on ``deck`` driven by the table ``rows`` (t, x, y, z: the fairlead's
    displacement, its deck position being the origin) from rows[0, 0] to ``t_end`` s;
    ``cfl`` (-) replaces the deck's ``cfl`` option (its step dtM is cfl times its estimate of
    the segments' critical step) when given.

    Returns ``time`` (s), ``fairlead`` and ``anchor`` (kN: the end segments' tensions),
    ``wall`` (s), ``init`` (s: Create + Init), ``dtM`` (s, MoorDyn's step from its CFL)."""
    n = int(np.searchsorted(rows[:, 0], t_end + 1e-9))  # rows up to t_end
    keep_ic = ic_dir is not None and Path(ic_dir, deck.name + ".ic").is_file()
    text = deck.read_text()
    if cfl is not None:
        text = _edit_deck(text, ("cfl",), (f"{float(cfl)!r}   cfl",))
    files = {deck.name: _edit_deck(text, ("writelog",) if keep_ic else _MOORDYN_DROP)}
    if keep_ic:  # MoorDyn resolves fileIC against the working directory: the session's
        files[deck.name + ".ic"] = Path(ic_dir, deck.name + ".ic").read_bytes()

    def calls():  # one Step per row, the velocity the forward difference to the next row
        for i in range(n - 1):
            h = rows[i + 1, 0] - rows[i, 0]
            x = rows[i, 1:4]
            yield list(x), list((rows[i + 1, 1:4] - x) / h), rows[i, 0] - rows[0, 0], h

    # at rest where the table starts, as its test (and as symcable's statics)
    with moordyn_driver.session(files, deck.name, rows[0, 1:4], [0.0] * 3, prefix="chains_md_") as s:
        md = s.md
        line = md.GetLine(s.system, 1)
        top, ten = md.GetLineN(line), md.GetLineNodeTen
        run = moordyn_driver.drive(s, calls(), read=lambda: (np.linalg.norm(ten(line, top)),
                                                             np.linalg.norm(ten(line, 0))))
        wall = time.perf_counter() - s.started
        t_init, dtM = s.init_time, s.dt()
    T = np.asarray(run.reads)
    return {"time": rows[:n, 0].copy(), "fairlead": T[:, 0] / 1e3, "anchor": T[:, 1] / 1e3,
            "wall": wall, "init": t_init, "dtM": dtM, "ic": "the deck's fileIC" if keep_ic else "its IC solve"}


def run_cabledyn(deck: Path, rows: np.ndarray, dt: float, t_end: float) -> dict:
    """CableDyn on ``deck`` at the step ``dt`` s from rows[0, 0] to ``t_end`` s, the fairlead
    driven by the table ``rows`` (see the module docstring).

    Returns ``time`` (s), ``fairlead`` and ``anchor`` (kN, its FairTen1 / AnchTen1),
    ``wall`` (s), ``init`` (s: the constructor's static solve), ``newton`` (iterations)."""
    from cabledyn import CableDyn

    tk, X = rows[:, 0], rows[:, 1:4]
    V = np.gradient(X, tk, axis=0)
    A = np.gradient(V, tk, axis=0)
    n = int(round((t_end - tk[0]) / dt))
    times = tk[0] + dt * np.arange(n + 1)
    kin = [np.stack([np.interp(times, tk, Y[:, c]) for c in range(3)], axis=1) for Y in (X, V, A)]
    with tempfile.TemporaryDirectory(prefix="chains_cd_") as tmp:
        path = Path(tmp, deck.stem + ".dat")
        path.write_text(_edit_deck(deck.read_text(), _CABLEDYN_DROP,
                                   (f"{float(dt)!r}   dtM", f"{float(t_end - tk[0])!r}   TMax")))
        t0 = time.perf_counter()
        model = CableDyn(path)
        try:
            t_init = time.perf_counter() - t0
            q0, _, _ = model.get_coupled_motion()
            if q0.size != 6:
                raise RuntimeError(f"CableDyn: {q0.size} coupled DOFs on {deck.name}, expected 6 "
                                   "(anchor and fairlead)")
            q, v, a = q0.copy(), np.zeros(6), np.zeros(6)
            T = np.empty((n + 1, 2))
            T[0] = model.channel("FairTen1"), model.channel("AnchTen1")
            iters = 0
            for k in range(n):
                q[3:6] = q0[3:6] + kin[0][k + 1]
                v[3:6], a[3:6] = kin[1][k + 1], kin[2][k + 1]
                iters += model.step(dt, q, v, a)
                T[k + 1] = model.channel("FairTen1"), model.channel("AnchTen1")
            wall = time.perf_counter() - t0
        finally:
            model.close()
    return {"time": times, "fairlead": T[:, 0] / 1e3, "anchor": T[:, 1] / 1e3, "wall": wall,
            "init": t_init, "newton": iters}
