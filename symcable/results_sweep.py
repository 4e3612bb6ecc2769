"""What a sweep gives: a table of cases by outputs (:class:`SweepResult`), one row per case
(:class:`CaseResult`), savable as CSV or JSON and loadable back.

A case that failed has status ``"failed"``, its one-line message and no values: its cells are
empty in the CSV and absent in the JSON, never NaN. A case the sweep did not reach (stopped
by ``limit`` or an interruption) has status ``"not run"``.
"""
from __future__ import annotations

import csv
import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import SymcableError

__all__ = ["CaseResult", "SweepResult"]

#: the statuses of a case without values; any other is its analysis' own ("converged";
#: "slack" and "invalid" results were computed and say why they may not be an answer)
NOT_RUN = "not run"
FAILED = "failed"
#: cases listed by :meth:`SweepResult.summary` (of those with values, and of the others)
SUMMARY_ROWS = 20
#: the CSV heads the column of a key a case sets (scene key or analysis option) so
_KEY = "set."


@dataclass(frozen=True)
class CaseResult:
    """One case of a sweep.

    Attributes
    ----------
    name : str
    hash : str
        12 hex digits of the case's content (its result file is ``<name>-<hash>.json``).
    overrides : dict
        Scene key (dotted path) -> value.
    status : str
        The analysis result's own status ("converged", "slack", "invalid", ...), "failed" or
        "not run".
    values : dict
        Output name -> float (SI units, see :mod:`symcable.sweep.case`); every output the
        analysis gives; empty unless the case ran and did not fail.
    message : str
        One line: why it failed (the error's type and message), else "".
    wall_time : float
        s, the case's own run (its worker's clock).
    worker : str
        host:pid that ran it ("" when not run).
    builds : dict
        Its generated-C loads by kind: "memory", "cache" (loaded from the build cache),
        "compiled" (compiled for this case), "vm" (not in the cache, run in the virtual
        machine instead: see :mod:`symcable.sweep.run`).
    skipped : bool
        Found in the results folder from an earlier run (not run again).
    """

    name: str
    hash: str
    overrides: dict
    status: str
    values: dict = field(default_factory=dict)
    message: str = ""
    wall_time: float = 0.0
    worker: str = ""
    builds: dict = field(default_factory=dict)
    skipped: bool = False

    @property
    def ok(self) -> bool:
        """It ran and did not fail (it has values)."""
        return self.status not in (FAILED, NOT_RUN)

    @classmethod
    def from_dict(cls, d: dict, **changes) -> "CaseResult":
        keys = cls.__dataclass_fields__
        return cls(**{**{k: v for k, v in d.items() if k in keys}, **changes})


@dataclass(frozen=True)
class SweepResult:
    """A sweep's table: ``cases`` (in the sweep's order) by ``outputs``.

    ``stats``: ``wall_time`` s (the whole call), ``ran``, ``skipped`` (found in the folder),
    ``failed``, ``not_run``, ``workers`` (how many), ``scheduler`` (address, "local" or
    "in-process"), ``out`` (the results folder or None), ``compiled_in_workers`` (cases that
    compiled generated C on a worker, with ``codegen = true``), ``vm_fallback`` (cases that
    ran functions in the virtual machine because the build cache did not have them compiled).
    """

    name: str
    analysis: str
    outputs: tuple
    keys: tuple
    cases: tuple
    stats: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.cases)

    def __repr__(self) -> str:
        return (f"SweepResult({self.name!r}: {len(self)} cases, {len(self.succeeded)} with "
                f"values, {len(self.failed)} failed; outputs {', '.join(self.outputs)})")

    def __getitem__(self, name: str) -> CaseResult:
        for c in self.cases:
            if c.name == name:
                return c
        raise KeyError(name)

    @property
    def names(self) -> tuple:
        return tuple(c.name for c in self.cases)

    @property
    def succeeded(self) -> tuple:
        """The cases that ran and did not fail, in order (the rows of :meth:`column`)."""
        return tuple(c for c in self.cases if c.ok)

    @property
    def failed(self) -> dict:
        """Case name -> its one-line message, of every failed case."""
        return {c.name: c.message for c in self.cases if c.status == FAILED}

    def column(self, output: str) -> np.ndarray:
        """The output's values over :attr:`succeeded` (SI units), as floats."""
        if output not in self.outputs and not any(output in c.values for c in self.cases):
            raise SymcableError(f"output = {output!r}: not in this sweep (its outputs: "
                                f"{', '.join(self.outputs)})")
        return np.array([c.values[output] for c in self.succeeded], float)

    # ----------------------------------------------------------------- text and files

    def summary(self) -> str:
        s = self.stats
        lines = [f"sweep      {self.name}: {len(self)} cases, analysis {self.analysis}",
                 f"cases      {s.get('ran', 0)} run, {s.get('skipped', 0)} already done, "
                 f"{s.get('failed', 0)} failed, {s.get('not_run', 0)} not run",
                 f"workers    {s.get('workers', '?')} ({s.get('scheduler', '?')}), "
                 f"wall time {s.get('wall_time', float('nan')):.3g} s"]
        if s.get("out"):
            lines.append(f"results    {s['out']}")
        if s.get("compiled_in_workers"):
            lines.append(f"note       {s['compiled_in_workers']} cases compiled generated C on a "
                         "worker (codegen = true; their model structure differs from the first "
                         "case's: e.g. another dt or number of segments)")
        if s.get("vm_fallback"):
            lines.append(f"note       {s['vm_fallback']} cases ran (in part) in the virtual "
                         "machine: their compiled functions differ from the first case's (e.g. "
                         "another dt, number of segments, cable3d motion period or amplitude) "
                         "and workers do not compile (codegen = true in the sweep file: they do)")
        ok, bad = self.succeeded, [c for c in self.cases if not c.ok]
        for c in ok[:SUMMARY_ROWS]:
            cells = ", ".join(f"{k} {c.values[k]:.6g}" for k in self.outputs if k in c.values)
            lines.append(f"  {c.name}: {c.status}: {cells}")
        if len(ok) > SUMMARY_ROWS:
            lines.append(f"  ... {len(ok) - SUMMARY_ROWS} more (the table: save it, or "
                         f"results.csv in the results folder)")
        for c in bad[:SUMMARY_ROWS]:
            lines.append(f"  {c.name}: {c.status}" + (f": {c.message}" if c.message else ""))
        if len(bad) > SUMMARY_ROWS:
            lines.append(f"  ... {len(bad) - SUMMARY_ROWS} more failed or not run")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"name": self.name, "analysis": self.analysis, "outputs": list(self.outputs),
                "keys": list(self.keys), "stats": dict(self.stats),
                "cases": [asdict(c) for c in self.cases]}

    @classmethod
    def from_dict(cls, d: dict) -> "SweepResult":
        return cls(d["name"], d["analysis"], tuple(d["outputs"]), tuple(d.get("keys", ())),
                   tuple(CaseResult.from_dict(c) for c in d["cases"]), dict(d.get("stats", {})))

    def save(self, path) -> Path:
        """Write the table as ``.csv``: one row per case (case, status, hash, the scene keys
        and options the cases set, headed ``set.<key>``, JSON for lists; the outputs;
        wall_time, message; a failed case's outputs empty), or as ``.json``: everything,
        every value of every case."""
        path = Path(path)
        if path.suffix == ".json":
            path.write_text(json.dumps(self.to_dict(), indent=1, default=str))
            return path
        if path.suffix != ".csv":
            raise SymcableError(f"path = {str(path)!r}: a sweep saves as .csv or .json")
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["case", "status", "hash", *(_KEY + k for k in self.keys),
                        *self.outputs, "wall_time", "message"])
            for c in self.cases:
                keys = [_cell(c.overrides[k]) if k in c.overrides else "" for k in self.keys]
                vals = [repr(c.values[k]) if k in c.values else "" for k in self.outputs]
                w.writerow([c.name, c.status, c.hash, *keys, *vals, repr(c.wall_time), c.message])
        return path

    @classmethod
    def load(cls, path) -> "SweepResult":
        """Read a table written by :meth:`save` (a CSV has no name, analysis or stats: the
        file's stem, "" and {})."""
        path = Path(path)
        if path.suffix == ".json":
            return cls.from_dict(json.loads(path.read_text()))
        with open(path, newline="") as fh:
            rows = list(csv.reader(fh))
        head = rows[0]
        i0, i_wall = head.index("hash") + 1, head.index("wall_time")
        keys = [h[len(_KEY):] for h in head[i0:i_wall] if h.startswith(_KEY)]
        outputs = head[i0 + len(keys):i_wall]
        cases = []
        for r in rows[1:]:
            ks, vs = r[i0:i0 + len(keys)], r[i0 + len(keys):i_wall]
            cases.append(CaseResult(
                r[0], r[2], {k: _uncell(v) for k, v in zip(keys, ks) if v != ""}, r[1],
                {k: float(v) for k, v in zip(outputs, vs) if v != ""},
                message=r[i_wall + 1], wall_time=float(r[i_wall])))
        return cls(path.stem, "", tuple(outputs), tuple(keys), tuple(cases), {})


def _cell(value: Any) -> str:
    return value if isinstance(value, str) else json.dumps(value)


def _uncell(text: str) -> Any:
    try:
        return json.loads(text)
    except ValueError:
        return text
