"""What a sweep gives: a table of cases by outputs (:class:`SweepResult`), one row per case
(:class:`CaseResult`), savable as CSV or JSON and loadable back.

A case that failed has status ``"failed"``, its one-line message and no values: its cells are
empty in the CSV and absent in the JSON, never NaN. A case the sweep did not reach (stopped
by ``limit`` or an interruption) has status ``"not run"``.
"""
from __future__ import annotations

import csv
import io
import json
import math
import reprlib
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ..errors import LimitError, SymcableError
from ..limits import check_nesting, read_bounded

__all__ = ["CaseResult", "SweepResult"]

#: the statuses of a case without values; any other is its analysis' own ("converged";
#: "slack" and "invalid" results were computed and say why they may not be an answer)
NOT_RUN = "not run"
FAILED = "failed"
#: every status a case may have: its analysis' ("converged"; "slack" and "invalid" results
#: were computed and say why they may not be an answer; "partial" a result of several parts
#: not all of which converged), FAILED or NOT_RUN
STATUSES = ("converged", "slack", "invalid", "partial", FAILED, NOT_RUN)
#: cases listed by :meth:`SweepResult.summary` (of those with values, and of the others)
SUMMARY_ROWS = 20
#: the CSV heads the column of a key a case sets (scene key or analysis option) so
_KEY = "set."
_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxlist, _REPR.maxtuple, _REPR.maxdict = 4, 8, 8, 8
_REPR.maxstring = _REPR.maxother = 100


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
    def from_dict(cls, d: Mapping, **changes) -> "CaseResult":
        """The case of the dict ``d`` (a saved case file's JSON object, an entry of
        :meth:`SweepResult.to_dict`; other keys are ignored), with ``changes`` (fields) set.

        Every field is checked, of ``d`` and of ``changes``: the name, hash, status, message
        and worker strings (the status one of :data:`STATUSES`), the overrides and values
        tables (values: output name -> finite number; none unless the status is one of a
        case that ran), wall_time a number >= 0, builds a table of integers >= 0, skipped a
        bool.

        Raises
        ------
        SymcableError
            One line naming the case, the field, its value and what is allowed.
        """
        if not isinstance(d, Mapping):
            raise SymcableError(f"case record = {_show(d)}: must be a table (JSON object) of "
                                "the case's fields")
        keys = cls.__dataclass_fields__
        fields = {k: v for k, v in d.items() if k in keys}
        where = f"case {_show(fields['name'])}: " if isinstance(fields.get("name"), str) else \
            "case record: "
        fields.update(_checked(fields, where))
        fields.update(changes)
        fields.update(_checked(changes, where))
        for key in ("name", "hash", "overrides", "status"):
            if key not in fields:
                raise SymcableError(f"{where}{key}: required field missing")
        if fields["status"] in (FAILED, NOT_RUN) and fields.get("values"):
            raise SymcableError(f"{where}values = {_show(fields['values'])}: must be empty "
                                f"for status {fields['status']!r} (a case without a result "
                                "has no values)")
        return cls(**fields)


def _show(value: Any) -> str:
    """``repr(value)`` shortened (long lists, deep nesting, long strings) to one line of at
    most 100 characters."""
    if isinstance(value, int) and value.bit_length() > 300:  # repr of a huge int may raise
        return f"<an integer of {value.bit_length()} bits>"
    text = _REPR.repr(value).replace("\n", " ")
    return text if len(text) <= 100 else text[:97] + "..."


def _number(value: Any) -> float | None:
    """``value`` as a finite float, or None when it is not a finite number (a bool is not)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    try:
        x = float(value)
    except OverflowError:
        return None
    return x if math.isfinite(x) else None


def _checked(fields: Mapping, where: str) -> dict:
    """The fields of a case record that :meth:`CaseResult.from_dict` converts (values to
    float), each checked; raises SymcableError for the first that is wrong."""
    def bad(key, value, allowed):
        return SymcableError(f"{where}{key} = {_show(value)}: {allowed}")

    out = {}
    for key in ("name", "hash", "status", "message", "worker"):
        if key in fields and not isinstance(fields[key], str):
            raise bad(key, fields[key], "must be a string")
    if "status" in fields and fields["status"] not in STATUSES:
        raise bad("status", fields["status"], f"must be one of {', '.join(map(repr, STATUSES))}")
    for key in ("overrides", "values", "builds"):
        if key in fields:
            table = fields[key]
            if not isinstance(table, Mapping) or not all(isinstance(k, str) for k in table):
                raise bad(key, table, "must be a table (JSON object) with string keys")
    if "values" in fields:
        values = {}
        for k, v in fields["values"].items():
            x = _number(v)
            if x is None:
                raise bad(f"values.{k}", v, "must be a finite number (an output's value, SI "
                          "units)")
            values[k] = x
        out["values"] = values
    if "builds" in fields:
        for k, v in fields["builds"].items():
            if isinstance(v, bool) or not isinstance(v, int) or v < 0:
                raise bad(f"builds.{k}", v, "must be an integer >= 0 (a count of loads)")
    if "wall_time" in fields:
        x = _number(fields["wall_time"])
        if x is None or x < 0:
            raise bad("wall_time", fields["wall_time"], "must be a number >= 0 (s)")
        out["wall_time"] = x
    if "skipped" in fields and not isinstance(fields["skipped"], bool):
        raise bad("skipped", fields["skipped"], "must be true or false")
    return out


@dataclass(frozen=True)
class SweepResult:
    """A sweep's table: ``cases`` (in the sweep's order) by ``outputs``.

    ``stats``: ``wall_time`` s (the whole call), ``ran``, ``skipped`` (found in the folder),
    ``failed``, ``not_run``, ``workers`` (how many), ``scheduler`` (address, "local" or
    "in-process"), ``out`` (the results folder or None), ``compiled_in_workers`` (cases that
    compiled generated C on a worker, with ``codegen = true``), ``vm_fallback`` (cases that
    ran functions in the virtual machine because the build cache did not have them compiled).

    Attributes
    ----------
    name : str
        The sweep's name (a table loaded from CSV: the file's stem).
    analysis : str
        The analysis every case ran: ``"static"``, ``"simulate"`` or ``"periodic"`` (a
        table loaded from CSV: "").
    outputs : tuple of str
        The outputs kept, the table's columns (SI units, see :mod:`symcable.sweep.case`).
    keys : tuple of str
        Every scene key (dotted path) or analysis option some case sets, in the order first
        set: the ``set.<key>`` columns of the CSV.
    cases : tuple of CaseResult
        One per case, in the sweep's order, those that failed or were not run included.
    stats : dict
        The keys above (a table loaded from CSV: empty).
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
        lines = [f"sweep      {_line(self.name)}: {len(self)} cases, analysis "
                 f"{_line(self.analysis)}",
                 _line(f"cases      {s.get('ran', 0)} run, {s.get('skipped', 0)} already "
                       f"done, {s.get('failed', 0)} failed, {s.get('not_run', 0)} not run"),
                 _line(f"workers    {s.get('workers', '?')} ({s.get('scheduler', '?')}), "
                       f"wall time {_number(s.get('wall_time')) or float('nan'):.3g} s")]
        if s.get("out"):
            lines.append(f"results    {_line(str(s['out']))}")
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
            lines.append(f"  {_line(c.name)}: {_line(c.status)}: {cells}")
        if len(ok) > SUMMARY_ROWS:
            lines.append(f"  ... {len(ok) - SUMMARY_ROWS} more (the table: save it, or "
                         f"results.csv in the results folder)")
        for c in bad[:SUMMARY_ROWS]:
            lines.append(f"  {_line(c.name)}: {_line(c.status)}"
                         + (f": {_line(c.message)}" if c.message else ""))
        if len(bad) > SUMMARY_ROWS:
            lines.append(f"  ... {len(bad) - SUMMARY_ROWS} more failed or not run")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"name": self.name, "analysis": self.analysis, "outputs": list(self.outputs),
                "keys": list(self.keys), "stats": dict(self.stats),
                "cases": [asdict(c) for c in self.cases]}

    @classmethod
    def from_dict(cls, d: Mapping) -> "SweepResult":
        """The table of the dict ``d`` (:meth:`to_dict`'s layout), every case checked
        (:meth:`CaseResult.from_dict`).

        Raises
        ------
        SymcableError
            One line naming what is missing or wrong (a case by its index).
        """
        if not isinstance(d, Mapping):
            raise SymcableError(f"sweep table = {_show(d)}: must be a table (JSON object) of "
                                "name, analysis, outputs, keys, stats and cases")
        for key, kind in (("name", str), ("analysis", str), ("outputs", list),
                          ("cases", list), ("keys", list), ("stats", Mapping)):
            if key not in d and key not in ("keys", "stats"):
                raise SymcableError(f"sweep table: {key}: required key missing")
            if key in d and not isinstance(d[key], kind):
                raise SymcableError(f"sweep table: {key} = {_show(d[key])}: must be a "
                                    f"{'table' if kind is Mapping else kind.__name__}")
        for key in ("outputs", "keys"):
            if not all(isinstance(x, str) for x in d.get(key, ())):
                raise SymcableError(f"sweep table: {key} = {_show(d[key])}: must be a list "
                                    "of strings")
        cases = []
        for i, c in enumerate(d["cases"]):
            try:
                cases.append(CaseResult.from_dict(c))
            except SymcableError as exc:
                raise SymcableError(f"sweep table: cases[{i}]: {exc}") from None
        return cls(d["name"], d["analysis"], tuple(d["outputs"]), tuple(d.get("keys", ())),
                   tuple(cases), dict(d.get("stats", {})))

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
        file's stem, "" and {}).

        The file is read as a regular file within the ``file_bytes`` limit
        (:func:`symcable.limits.read_bounded`) and every case is checked.

        Raises
        ------
        SymcableError
            One line: the file is not a sweep's table, or a case in it is wrong
            (:class:`~symcable.errors.LimitError`: too large or nested too deeply).
        OSError
            The file cannot be read, or is not a regular file (a folder, a device).
        """
        path = Path(path)
        what = "a sweep's table"
        try:
            text = read_bounded(path, "file_bytes", what).decode("utf-8")
            if path.suffix == ".json":
                data = json.loads(text)
                check_nesting(data, f"{what} {str(path)!r}")
                return cls.from_dict(data)
            rows = list(csv.reader(io.StringIO(text, newline="")))
            head = rows[0]
            i0, i_wall = head.index("hash") + 1, head.index("wall_time")
            keys = [h[len(_KEY):] for h in head[i0:i_wall] if h.startswith(_KEY)]
            outputs = head[i0 + len(keys):i_wall]
            cases = []
            for r in rows[1:]:
                ks, vs = r[i0:i0 + len(keys)], r[i0 + len(keys):i_wall]
                cases.append(CaseResult.from_dict({
                    "name": r[0], "hash": r[2], "status": r[1],
                    "overrides": {k: _uncell(v) for k, v in zip(keys, ks) if v != ""},
                    "values": {k: float(v) for k, v in zip(outputs, vs) if v != ""},
                    "message": r[i_wall + 1], "wall_time": float(r[i_wall])}))
        except LimitError:
            raise
        except SymcableError as exc:
            raise SymcableError(f"{path}: {exc}") from None
        except (ValueError, IndexError, RecursionError) as exc:
            raise SymcableError(f"{path}: not a sweep's table as SweepResult.save writes it "
                                f"({_line(' '.join(str(exc).split()))[:200]})") from None
        return cls(path.stem, "", tuple(outputs), tuple(keys), tuple(cases), {})


def _line(text: str) -> str:
    """``text`` on one line: its characters that are not printable (newlines, NUL, control
    characters) escaped as Python writes them (``\\n``)."""
    if text.isprintable():
        return text
    return "".join(ch if ch.isprintable() else repr(ch)[1:-1] for ch in text)


def _cell(value: Any) -> str:
    return value if isinstance(value, str) else json.dumps(value)


def _uncell(text: str) -> Any:
    try:
        return json.loads(text)
    except ValueError:
        return text
