"""The Mechanism: the one interface every formulation produces and every generic solver reads.

A Mechanism is a second-order system with constraints, written in CasADi symbols::

    q' = G(q) v                          (kinematics; identity for node positions; in general
                                          an expression of (q, v, z, t, p))
    M(q; p) v' = f(q, v, z, t; p)        (n_v equations, N)
    g(q, v, z, t; p) = 0                 (n_z constraints; z are their multipliers)

``q`` (n_q,) are coordinates (m, rad), ``v`` (n_v,) generalised velocities, ``z`` (n_z,)
algebraic unknowns (constraint forces, N), ``t`` time (s) and ``p`` parameters in named
blocks (``load``, ``current``, ``motion``, ...), which continuation and sweeps move. The
force ``f`` contains every load a formulation knows about: internal, damping, drag, weight,
contact, constraint forces (typically ``-B(q)^T z`` with ``B = dg/dq``), and the inertia of
prescribed motion. A formulation never calls a solver; :mod:`symcable.mechanism.functions` turns a
Mechanism into the static residual, the DAE residual and the tangent matrices, once.

The kinematics is ``q' = v`` unless ``kinematics`` is given, an expression of
``(q, v, z, t, p)``: ``G(q) v`` for rotations, and for coordinates that are increments relative
to a prescribed motion (the planar linearised dynamics, whose segment strain and angle rates
carry the prescribed end velocity, a function of ``t`` and ``p``) an affine ``G(q) v + w(q, t;
p)``. The derived ``qdot`` Function takes ``(q, v, z, t, p)``.

Prescribed coordinates are not unknowns: they enter ``f`` and the outputs as functions of
``t`` and ``p`` (see :mod:`symcable.mechanism.assembly` for fixed and moving nodes).

First-order states (coordinates without a velocity of their own, such as the seabed
friction's bristle deflections of :mod:`symcable.models.common.friction`) are the last
``n_q - n_v`` entries of ``q``; ``kinematics`` gives their rates, and ``rest`` the rows that
fix them at rest, which the static residual appends to the force balance; ``layout.states``
names them (:class:`StateNames`), for labels (:meth:`Mechanism.coordinate_names`) and for the
message of the periodic solvers, which refuse them.
"""
from __future__ import annotations

import hashlib
import math
import re
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, Iterable, Mapping

import numpy as np

from ..errors import SymcableError

_CASADI_NAME = re.compile(r"[A-Za-z](?:[A-Za-z0-9]|_(?=[A-Za-z0-9]))*")


def casadi_name(name: str) -> str:
    """A valid CasADi Function name (and C identifier) for ``name``: ``name`` itself when it
    is one (a letter, then letters, digits and single underscores, not ending in one),
    else its letters and digits joined by single underscores, led by a letter and followed
    by 8 hex digits of its SHA-256, so that two names never map to one (``"my-line"`` ->
    ``"my_line_e20e07b7"``, ``"1"`` -> ``"n1_6b86b273"``)."""
    if _CASADI_NAME.fullmatch(name) and name not in ("null", "jac", "hess"):
        return name
    words = re.findall(r"[A-Za-z0-9]+", name)
    stem = "_".join(words)[:48].strip("_") or "n"
    if not stem[0].isalpha():
        stem = "n" + stem
    return f"{stem}_{hashlib.sha256(name.encode('utf-8', 'surrogatepass')).hexdigest()[:8]}"



@dataclass(frozen=True)
class Output:
    """A named quantity computed from the state.

    Attributes
    ----------
    expr : casadi.SX or casadi.MX
        Expression of ``(q, v, z, t, p)``; any shape (a column vector is usual).
    unit : str
        SI unit of every entry, e.g. ``"N"``, ``"m"``, ``"1"``.
    owner : str
        The part it belongs to (``"line1"``) or ``""`` for the whole mechanism.
    description : str
        One line for tables and plot labels.
    """

    expr: object
    unit: str
    owner: str = ""
    description: str = ""


@dataclass(frozen=True)
class Bound:
    """A condition every admissible solution meets, ``lower <= expr <= upper`` entry by
    entry: what the equations alone do not exclude but the physics does (a segment of
    positive length, a cable that does not push, a seabed that carries no more than what
    presses on it). The solvers check it on every solution they return.

    Attributes
    ----------
    expr : casadi.SX or casadi.MX (k, 1)
        Expression of ``(q, v, z, t, p)``.
    lower, upper : float or array (k,)
        Bounds in the unit of ``expr`` (-inf / inf: none).
    unit : str
        SI unit of ``expr``.
    scale : float
        A magnitude of ``expr`` (its unit): a violation is reported relative to it.
    what : str
        What the condition means, for messages (``"segments of positive length"``).
    """

    expr: object
    lower: object = -np.inf
    upper: object = np.inf
    unit: str = ""
    scale: float = 1.0
    what: str = ""


@dataclass(frozen=True)
class ParamBlocks:
    """Parameters ``p`` as named, contiguous blocks with default values.

    Attributes
    ----------
    names : tuple of str
        Block names in the order they sit in ``p``.
    sizes : tuple of int
        Entries of each block.
    values : ndarray (n_p,)
        The scene's own values (the target of every solve).
    """

    names: tuple[str, ...] = ()
    sizes: tuple[int, ...] = ()
    values: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self):
        if len(self.names) != len(self.sizes) or len(set(self.names)) != len(self.names):
            raise SymcableError(f"parameter blocks {self.names!r}: names must be unique, "
                                f"one size each (got sizes {self.sizes!r})")
        values = np.asarray(self.values, dtype=float).ravel()
        if values.size != sum(self.sizes):
            raise SymcableError(f"parameter blocks {self.names!r}: {values.size} values given "
                                f"for {sum(self.sizes)} entries")
        object.__setattr__(self, "values", values)

    @cached_property
    def n(self) -> int:
        return int(sum(self.sizes))

    def slice(self, name: str) -> slice:
        """Where block ``name`` sits in ``p``."""
        if name not in self.names:
            raise SymcableError(f"parameter block {name!r}: unknown (blocks: "
                                f"{', '.join(self.names) or 'none'})")
        i = self.names.index(name)
        start = int(sum(self.sizes[:i]))
        return slice(start, start + self.sizes[i])

    def with_values(self, base: np.ndarray | None = None, **blocks) -> np.ndarray:
        """A copy of ``base`` (default: the scene's values) with whole blocks replaced."""
        p = np.array(self.values if base is None else base, dtype=float)
        for name, value in blocks.items():
            sl = self.slice(name)
            value = np.broadcast_to(np.asarray(value, dtype=float).ravel(), (sl.stop - sl.start,))
            p[sl] = value
        return p

    def get(self, p: np.ndarray, name: str) -> np.ndarray:
        return np.asarray(p, dtype=float)[self.slice(name)]


@dataclass(frozen=True)
class Scales:
    """Typical magnitudes, for step limits, scaled residuals and default tolerances.

    Attributes
    ----------
    q : ndarray (n_q,)   typical coordinate change, m or rad
    v : ndarray (n_v,)   typical velocity, m/s or rad/s
    z : ndarray (n_z,)   typical constraint force, N
    force : float        N, a characteristic force (weight, tension)
    mass : float         kg, a characteristic mass (converts constraint rows to forces)
    residual_floor : float
        N, the smallest force residual float64 round-off lets the equations reach.
    resolution : float
        N, the smallest load the static equations must resolve (the lightest node's weight;
        inf when no node weighs anything): :meth:`static_tolerance` stays below a thousandth
        of it, where round-off allows.
    g : ndarray (n_z,) or None
        Typical magnitude of each constraint row, in its own unit: a time step is converged
        when |g_i| <= tol g_i (default: the median coordinate scale).
    merit : ndarray (n_q + n_z,) or None
        Row weights D of the static line search's merit 0.5 |D R|^2 (default ones): for
        residual rows whose units differ in meaning (the planar statics' geometric rows
        against its force balances). Any weighting keeps the Newton step a descent direction.
    """

    q: np.ndarray
    v: np.ndarray
    z: np.ndarray
    force: float
    mass: float = 1.0
    residual_floor: float = 0.0
    g: np.ndarray | None = None
    merit: np.ndarray | None = None
    resolution: float = math.inf

    def static_tolerance(self, force: float | None = None, rtol: float = 1e-9) -> float:
        """The default static tolerance on the residual's max-norm, N: ``rtol`` times the force
        scale (``force``, default :attr:`force`), or ten times the round-off floor where that
        is larger, but not above a thousandth of :attr:`resolution` (a node's residual adds
        up along the line: a tension error of up to N x the tolerance over N nodes) while a
        fiftieth of the floor is below it (the floor has a hundredfold margin over float64's
        resolution of the coordinates). A short stiff line far from the origin has a round-off floor larger than
        a node's weight: a start with every segment at zero tension would pass ten times the
        floor, and the line's tension would be lost (a 5 m wire 550 m from the origin: 0.5 N
        at the ends for 40 and 60 N)."""
        F = self.force if force is None else force
        loose = 10.0 * self.residual_floor
        tight = max(0.02 * self.residual_floor, 1e-3 * self.resolution)
        return max(rtol * F, min(loose, tight))

    def g_scale(self) -> np.ndarray:
        """``g``, or the median of ``q`` for every constraint row."""
        if self.g is not None:
            return np.asarray(self.g, dtype=float)
        ref = float(np.median(self.q)) if np.size(self.q) else 1.0
        return np.full(np.size(self.z), ref)


@dataclass(frozen=True)
class Start:
    """A static starting point.

    ``q``, ``z`` are (close to) an equilibrium at the parameters ``p``; when ``p`` differs
    from the target the solver continues from it to the target in the block ``homotopy``.

    Attributes
    ----------
    q : ndarray (n_q,)
        Coordinates, m or rad.
    z : ndarray (n_z,)
        Constraint forces, N (empty for a mechanism without constraints).
    p : ndarray (n_p,)
        The parameters at which (q, z) is close to an equilibrium.
    source : str
        What the start is (``"static solution"``, ``"given position"``), as
        :func:`~symcable.solvers.equilibrium.solve_equilibrium` names it in its attempts
        and ``stats["start"]``.
    homotopy : str
        What ``p`` differs from the target in (parameter blocks, e.g. ``"bending"``), for
        messages: the continuation is named ``"continuation in <homotopy>"``
        (``"continuation in parameters"`` when ""); it moves every parameter along the
        straight path from ``p`` to the target. Default "".
    exact : bool
        ``(q, z)`` solves the equations at ``p`` (a nearby design's solution): when plain
        Newton from it at the target fails, the continuation from ``p`` is tried at once,
        before the starts after it (a path of small steps from an equilibrium, where a
        relaxed start would cost a minimisation). Default False.
    """

    q: np.ndarray
    z: np.ndarray
    p: np.ndarray
    source: str
    homotopy: str = ""
    exact: bool = False


@dataclass(frozen=True)
class PartLayout:
    """Where one part's nodes sit in the mechanism's coordinates.

    Attributes
    ----------
    kind : str
        ``"line"``, ``"point"``, ``"body"`` or ``"element"`` (a spring or joint element
        with no nodes of its own).
    s : ndarray (n_nodes,)
        Unstretched arc length of each node, m (zeros for a point).
    node_q : ndarray of int (n_nodes, dim)
        Index in ``q`` of each node's coordinates; -1 where the node is prescribed.
    node_v : ndarray of int (n_nodes, dim)
        The same in ``v``.
    prescribed : mapping node index -> str
        For a prescribed node, the name of what moves it: the mechanism's output
        ``NAME.position`` (m) is that node's position (``assemble`` fills it from its
        :class:`~symcable.mechanism.assembly.Prescribed` joints).
    """

    kind: str
    s: np.ndarray
    node_q: np.ndarray
    node_v: np.ndarray
    prescribed: Mapping[int, str] = field(default_factory=dict)

    @property
    def n_nodes(self) -> int:
        return int(self.node_q.shape[0])


@dataclass(frozen=True)
class StateNames:
    """What a mechanism's first-order states are (the last ``n_q - n_v`` entries of q, which
    no part's nodes hold): names for labels, and for messages where they come from and
    what does without them.

    Attributes
    ----------
    names : tuple of str
        One per state, in the order of q (``"node3.bristle.x"``).
    unit : str
        SI unit of every state (``"m"``).
    source : str
        The setting that adds them, as a message names it
        (``'seabed.friction_law = "bristle"'``).
    without : str
        The setting that models the same without them (``'seabed.friction_law =
        "coulomb"'``); "" when there is none.
    rate_blocks : tuple of str
        Per state (empty: none for any), the parameter block (1/s) whose positive value
        makes the state relax to its rest value in time, at that rate, where otherwise any
        value of it would persist (a quaternion's norm); "" for a state without one. The
        periodic solvers set it (their periodic states would form a family otherwise:
        :func:`~symcable.solvers.periodic_mech.check_periodic`).
    """

    names: tuple[str, ...]
    unit: str
    source: str = ""
    without: str = ""
    rate_blocks: tuple[str, ...] = ()

    def rate_block(self, i: int) -> str:
        """State ``i``'s rate block, or ""."""
        return self.rate_blocks[i] if i < len(self.rate_blocks) else ""


@dataclass(frozen=True)
class Layout:
    """Dimension and parts of a mechanism, and the names of its first-order states
    (``states``, None when it has none or leaves them unnamed).

    Attributes
    ----------
    dim : int
        Coordinates per node: 3 (x, y, z) or 2 (a planar line, x and z); 1 for a
        one-dimensional toy, and :class:`Mechanism`'s default.
    parts : mapping str -> PartLayout
        Part name -> where that part's nodes sit in q and v (:class:`PartLayout`); empty
        for a mechanism without nodes.
    states : StateNames or None
        Names of the first-order states (the last ``n_q - n_v`` entries of q), or None.
    """

    dim: int
    parts: Mapping[str, PartLayout] = field(default_factory=dict)
    states: StateNames | None = None


@dataclass(frozen=True)
class Reanchor:
    """An optional hook of a Mechanism whose coordinates are measured from frames stored as
    parameters (the rod's anchored reference frames, :mod:`symcable.models.rod.rod`): a time
    march calls it between steps so that no coordinate nears the chart's singularity.

    ``margin``: expression (1, 1) of ``(q, t, p)``, how far the state is from the chart's
    singularity (the rod: min over edges of 1 + t0 . t, 2 at the anchors, 0 at the half
    turn); ``update``: expression (n_p, 1) of ``(q, t, p)``, the parameters re-anchored at
    the state (the same physical state, q unchanged); ``threshold``: the march re-anchors
    after a step whose margin fell below it; ``floor``: a margin below which a step is not
    trusted (the march retakes it from a re-anchored start, step by step); ``velocity``:
    expression (n_v, 1) of ``(q, v, t, p)``, the velocities in the new chart (None: v
    unchanged; the rod's twist rates gain their reference frame's spin, which the new anchor
    no longer has)."""

    margin: object
    update: object
    threshold: float = 0.5
    floor: float = 0.05
    velocity: object = None


@dataclass(frozen=True, eq=False)
class Mechanism:
    """A discretised system of parts, as CasADi expressions (see the module docstring).

    Attributes
    ----------
    name : str
    q, v, z : casadi symbols (n_q, 1), (n_v, 1), (n_z, 1)
    t : casadi symbol (1, 1), s
    p : casadi symbol (n_p, 1)
    params : ParamBlocks
    mass : expression (n_v, n_v) of ``(q, t, p)``, kg (kg m^2 for rotations; t enters
        through a prescribed node's position, e.g. the direction of an element's added mass)
    force : expression (n_v, 1) of ``(q, v, z, t, p)``, N (N m)
    constraint : expression (n_z, 1) of ``(q, v, z, t, p)``
    kinematics : expression (n_q, 1) of ``(q, v, z, t, p)``: q' = G(q) v (+ prescribed
        terms in t and p); None means q' = v
    scales : Scales
    starts : callable () -> iterable of Start, in order of preference (built lazily)
    outputs : mapping name -> Output
    layout : Layout
    terms : tuple of str, the physics terms built
    static_params : mapping block -> values used for statics (e.g. ``ramp = 0``)
    bounds : mapping name -> Bound, the admissibility conditions every solution is
        checked against
    stability_coordinates : int array or None
        For a massless (static) mechanism whose residual is the gradient of an energy only in
        some coordinates (the planar line: node positions, whose rows are force balances;
        its segment angles and strains, with their compatibility rows, are internal): those
        entries of q (and the same rows of f). The solver judges stability on the Schur
        complement of the tangent onto them. None: no stability is read from a massless
        mechanism.
    stability_when : expression (1, 1) of (q, v, z, t, p) or None
        Stability is judged only where this is negative (the planar line: its least axial
        force in sections with bending, since a tension-only cable under conservative loads
        cannot lose stability); None: always.
    reanchor : Reanchor or None
        The optional re-anchoring hook a time march calls between steps (:class:`Reanchor`);
        None for every mechanism whose coordinates need none.
    elements : ElementForm or None
        Optionally, the momentum rows once more as element kernels plus a rest
        (:class:`~symcable.mechanism.element_form.ElementForm`), for solvers that evaluate the
        iteration matrix as a loop over elements; the expressions above stay the definition.
        A Mechanism rebuilt from another with a changed mass or force must drop it.
    functions_of : Mechanism or None
        The Mechanism whose expressions these are, with other numbers (the same structure:
        :mod:`symcable.models.structure`); its derived Functions serve this one too. None:
        its own.
    rest : expression (n_q - n_v, 1) of (q, z, t, p) or None
        For a mechanism with first-order states (the last n_q - n_v entries of q, their
        rates in ``kinematics``): the rows that fix them at rest, in N like the force rows;
        the static residual is (f, g, rest) at v = 0, and stability is judged as for a
        massless mechanism, on ``stability_coordinates`` (the first-order states follow
        through their rows). None: no first-order states (statics need n_q = n_v).
    """

    name: str
    q: object
    v: object
    z: object
    t: object
    p: object
    params: ParamBlocks
    mass: object
    force: object
    constraint: object
    scales: Scales
    starts: Callable[[], Iterable[Start]]
    outputs: Mapping[str, Output] = field(default_factory=dict)
    layout: Layout = field(default_factory=lambda: Layout(dim=1))
    kinematics: object = None
    terms: tuple[str, ...] = ()
    static_params: Mapping[str, object] = field(default_factory=dict)
    bounds: Mapping[str, Bound] = field(default_factory=dict)
    stability_coordinates: object = None
    stability_when: object = None
    rest: object = None
    reanchor: Reanchor | None = None
    elements: object = None
    functions_of: object = None

    def __post_init__(self):
        n_q, n_v, n_z = self.n_q, self.n_v, self.n_z
        checks = [("mass", self.mass, (n_v, n_v)), ("force", self.force, (n_v, 1)),
                  ("constraint", self.constraint, (n_z, 1))]
        if self.rest is not None:
            if self.kinematics is None or n_q <= n_v:
                raise SymcableError(f"mechanism {self.name!r}: rest rows are for first-order "
                                    "states (n_q > n_v, their rates in kinematics)")
            checks.append(("rest", self.rest, (n_q - n_v, 1)))
        names = self.layout.states
        if names is not None and len(names.names) != n_q - n_v:
            raise SymcableError(f"mechanism {self.name!r}: layout.states names "
                                f"{len(names.names)} states, it has n_q - n_v = {n_q - n_v}")
        if self.kinematics is not None:
            checks.append(("kinematics", self.kinematics, (n_q, 1)))
        elif n_q != n_v:
            raise SymcableError(f"mechanism {self.name!r}: n_q = {n_q} != n_v = {n_v} needs "
                                "kinematics q' = G(q) v")
        for name, b in self.bounds.items():
            k = int(b.expr.numel())
            if b.expr.shape[1] != 1 or any(np.size(x) not in (1, k) for x in (b.lower, b.upper)) \
                    or not b.scale > 0:
                raise SymcableError(f"mechanism {self.name!r}: bound {name!r} needs a column "
                                    "expression, lower/upper scalars or of its length, scale > 0")
        for what, expr, shape in checks:
            if tuple(expr.shape) != shape:
                raise SymcableError(f"mechanism {self.name!r}: {what} has shape "
                                    f"{tuple(expr.shape)}, expected {shape}")
        if int(self.p.numel()) != self.params.n:
            raise SymcableError(f"mechanism {self.name!r}: p has {int(self.p.numel())} entries "
                                f"but the blocks {self.params.names} have {self.params.n}")
        for what, arr, n in (("q", self.scales.q, n_q), ("v", self.scales.v, n_v),
                             ("z", self.scales.z, n_z)):
            if np.asarray(arr).shape != (n,):
                raise SymcableError(f"mechanism {self.name!r}: scales.{what} has shape "
                                    f"{np.asarray(arr).shape}, expected ({n},)")
        if self.scales.merit is not None and np.shape(self.scales.merit) != (n_q + n_z,):
            raise SymcableError(f"mechanism {self.name!r}: scales.merit has shape "
                                f"{np.shape(self.scales.merit)}, expected ({n_q + n_z},)")

    @cached_property
    def fname(self) -> str:
        """The prefix of the names of the CasADi Functions derived from it: ``name`` made a
        valid Function name (:func:`casadi_name`)."""
        return casadi_name(self.name)

    @cached_property
    def n_q(self) -> int:
        return int(self.q.numel())

    @cached_property
    def n_v(self) -> int:
        return int(self.v.numel())

    @cached_property
    def n_z(self) -> int:
        return int(self.z.numel())

    @property
    def symbols(self) -> tuple:
        """``(q, v, z, t, p)``, the arguments of every expression."""
        return (self.q, self.v, self.z, self.t, self.p)

    @property
    def static_p(self) -> np.ndarray:
        """The parameters of the static problem: the scene's, with ``static_params`` applied."""
        return self.params.with_values(**dict(self.static_params))

    def coordinate_names(self, tagged: bool = False) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """``(q names, v names)``, one string per entry: a line's node i in direction x
        ``"node{i}.x"`` (``tagged``: ``"{part}.node{i}.x"``, for mechanisms of several
        parts), any other part's ``"{part}.x"`` (a node shared by a line and a point goes
        by the point's name; a body's rotation: ``"{part}.e1"`` ... in q, the quaternion's
        vector part, ``"{part}.rx"`` ... in v, its angular velocity in body axes), the
        first-order states by ``layout.states`` (a body's ``"{part}.e0"``); "" for an entry
        nothing names."""
        out = []
        for n, key in ((self.n_q, "node_q"), (self.n_v, "node_v")):
            names = [""] * n
            parts = sorted(self.layout.parts.items(), key=lambda kv: kv[1].kind == "line")
            for part_name, part in parts:
                tag = f"{part_name}." if tagged else ""
                for i, row in enumerate(np.asarray(getattr(part, key))):
                    for c, j in enumerate(row):
                        axis = "xyz"[c] if len(row) <= 3 else str(c)
                        if part.kind == "body" and i == 1:  # its rotation's row
                            axis = f"e{c + 1}" if key == "node_q" else f"r{axis}"
                        if 0 <= j < n and not names[j]:
                            names[j] = (f"{tag}node{i}.{axis}" if part.kind == "line"
                                        else f"{part_name}.{axis}")
            if key == "node_q" and self.layout.states is not None:
                names[self.n_v:] = self.layout.states.names
            out.append(tuple(names))
        return out[0], out[1]

    def output_names(self, owner: str | None = None) -> tuple[str, ...]:
        return tuple(k for k, o in self.outputs.items() if owner is None or o.owner == owner)
