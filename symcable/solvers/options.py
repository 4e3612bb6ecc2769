"""Solver options: one frozen dataclass per method, validated once when built, and closed
choices as enums read by one shared parser (:func:`parse_choice`)."""
from __future__ import annotations

import enum
from dataclasses import dataclass

from ..errors import SymcableError

__all__ = ["CollocationScheme", "Collocation", "GeneralizedAlpha", "GeneralizedAlphaFirstOrder",
           "HarmonicBalance", "NewtonScheme", "RK4", "Shooting", "parse_choice"]


def parse_choice(enum_cls, value, key: str):
    """``value`` (an enum member or its string value, case-insensitive, ``_`` = ``-``) as a
    member of ``enum_cls``; a SymcableError naming ``key``, the value and the choices otherwise."""
    if isinstance(value, enum_cls):
        return value
    text = str(value).strip().lower().replace("_", "-")
    for member in enum_cls:
        if member.value == text:
            return member
    choices = ", ".join(repr(m.value) for m in enum_cls)
    raise SymcableError(f"{key} = {value!r}: must be one of {choices}")


def _number(key, value, lo=None, hi=None, integer=False, lo_open=False):
    try:
        x = int(value) if integer else float(value)
        if integer and x != value:
            raise ValueError
    except (TypeError, ValueError):
        raise SymcableError(f"{key} = {value!r}: must be {'an integer' if integer else 'a number'}") from None
    if x != x or (lo is not None and (x < lo or (lo_open and x == lo))) or (hi is not None and x > hi):
        if integer and hi is None and lo is not None and not lo_open:
            raise SymcableError(f"{key} = {value!r}: must be an integer >= {lo}")
        rng = f"{'(' if lo_open else '['}{lo}, {hi if hi is not None else 'inf'}]"
        raise SymcableError(f"{key} = {value!r}: must be in {rng}")
    return x


class _ImplicitScheme:
    """Validation shared by the implicit schemes' options (rho_inf, tol, max_iter)."""

    def __post_init__(self):
        object.__setattr__(self, "rho_inf", _number("rho_inf", self.rho_inf, 0.0, 1.0))
        object.__setattr__(self, "tol", _number("tol", self.tol, 0.0, lo_open=True))
        object.__setattr__(self, "max_iter", _number("max_iter", self.max_iter, 1, integer=True))


@dataclass(frozen=True)
class GeneralizedAlpha(_ImplicitScheme):
    """Implicit generalized-alpha (Chung & Hulbert 1993, in the form of Arnold & Bruels 2007
    for constrained systems): second order, unconditionally stable; ``rho_inf`` in [0, 1] is
    the spectral radius at infinite step (1: no numerical damping, 0: the most);
    ``tol`` the scaled Newton tolerance of each step; ``max_iter`` Newton iterations.

    Parameters
    ----------
    rho_inf : float, default 0.8
        Spectral radius at infinite step, in [0, 1] (dimensionless): 1 no numerical
        damping, 0 the most.
    tol : float, default 1e-10
        Newton tolerance of each step, > 0 (dimensionless): the max-norm of the step's
        residual, force rows divided by the mechanism's force scale and constraint rows by
        their scales. A step whose residual stays above it has failed.
    max_iter : int, default 50
        Newton iterations per step, >= 1 (CasADi's Newton with its line search, then plain
        Newton where that failed).

    Raises
    ------
    SymcableError
        A value that is not a number or out of its range.
    """

    rho_inf: float = 0.8
    tol: float = 1e-10
    #: CasADi's Newton with its line search; a step that converges stops at ``tol``, so the
    #: cap only costs where a step fails. Measured: a line dragged along a frictional bed
    #: with its trailing half slack needs 21-30 iterations at the reversal (20 failed)
    max_iter: int = 50


    @property
    def coefficients(self) -> tuple[float, float, float, float]:
        """(alpha_m, alpha_f, gamma, beta)."""
        r = self.rho_inf
        am = (2 * r - 1) / (r + 1)
        af = r / (r + 1)
        gamma = 0.5 + af - am
        beta = 0.25 * (gamma + 0.5) ** 2
        return am, af, gamma, beta


class NewtonScheme(str, enum.Enum):
    """How a first-order generalized-alpha step runs its Newton iterations:
    ``"unrolled"``, a fixed number of iterations written out in one Function (chord
    iterations on a matrix factorised by a block LU written out in SX; fast, compiles to C;
    its derivative is that of the iterations taken), or ``"rootfinder"``, CasADi's Newton
    rootfinder (the exact Jacobian at every iteration; its derivative is the exact
    implicit-function one, for Newton on a period map; virtual machine only)."""

    UNROLLED = "unrolled"
    ROOTFINDER = "rootfinder"


@dataclass(frozen=True)
class GeneralizedAlphaFirstOrder(_ImplicitScheme):
    """Implicit first-order generalized-alpha (Jansen, Whiting & Hulbert 2000) on the DAE
    residual F(y', y, t; p) = 0, y = (q, v): second order, unconditionally stable on linear
    problems; ``rho_inf`` in [0, 1] the spectral radius at infinite step; ``tol`` the Newton
    tolerance on the residual scaled to a change of y over one step relative to its scales;
    ``max_iter`` Newton iterations; ``newton`` how they run (:class:`NewtonScheme`).
    Unlike :class:`GeneralizedAlpha` (second order in time,
    q' = v), it takes any kinematics q' = G(q) v + w(q, t; p); it is the scheme that
    ``simulate(..., method="generalized-alpha")`` runs on a DynamicModel. A class of its
    own, not a field of GeneralizedAlpha: its coefficients (alpha_m, alpha_f in [1/2, 3/2]),
    its carried state (y, y') and what it accepts all differ, and no option of one means
    anything to the other (an ``isinstance`` tells the solvers which scheme they hold).

    Parameters
    ----------
    rho_inf : float, default 0.5
        Spectral radius at infinite step, in [0, 1] (dimensionless): 1 no numerical
        damping, 0 the most.
    tol : float, default 1e-10
        Newton tolerance, > 0 (dimensionless): the max-norm of the step residual scaled to
        a change of y over the step relative to the mechanism's scales (kinematic rows
        h |F| / scales.q, momentum rows h |F| / (m_i scales.v)).
    max_iter : int, default 20
        Newton iterations per step, >= 1.
    newton : NewtonScheme or str, default "unrolled"
        How the iterations run: ``"unrolled"`` or ``"rootfinder"`` (:class:`NewtonScheme`;
        a string is matched case-insensitively, ``_`` for ``-``).

    Raises
    ------
    SymcableError
        A value that is not a number, out of its range, or not one of the choices.
    """

    rho_inf: float = 0.5
    tol: float = 1e-10
    max_iter: int = 20
    newton: NewtonScheme = NewtonScheme.UNROLLED

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "newton", parse_choice(NewtonScheme, self.newton, "newton"))

    @property
    def coefficients(self) -> tuple[float, float, float]:
        """(alpha_m, alpha_f, gamma) (Jansen et al. 2000, eqs. 17 and 20)."""
        r = self.rho_inf
        am = 0.5 * (3.0 - r) / (1.0 + r)
        af = 1.0 / (1.0 + r)
        return am, af, 0.5 + am - af

    @property
    def error_constant(self) -> float:
        """C in y_1 - y(t_1) = C h^3 y^(3) + O(h^4), the local error of the principal root
        on y' = lambda y (from the scheme's characteristic polynomial):
        (r^2 - r + 1) / (3 (1 + r)^2), 1/12 at r = 1, 1/9 at r = 1/2, 1/3 at r = 0."""
        r = self.rho_inf
        return (r * r - r + 1.0) / (3.0 * (1.0 + r) ** 2)


@dataclass(frozen=True)
class RK4:
    """Classical explicit Runge-Kutta of order 4 (mechanisms without constraints only).

    It takes no parameters: ``RK4()``. Its step is the run's fixed ``dt`` (s; adaptive
    steps with ``tol`` need generalized-alpha), by default at most 0.8 times its stability
    limit.
    """


class CollocationScheme(str, enum.Enum):
    RADAU = "radau"
    LEGENDRE = "legendre"


@dataclass(frozen=True)
class Collocation:
    """Direct collocation of one period: ``intervals`` intervals of polynomial ``degree``
    on ``scheme`` points; the NLP is solved by ``solver`` ("ipopt" or "newton").

    Parameters
    ----------
    intervals : int, default 40
        Equal time intervals of the period, >= 2.
    degree : int, default 3
        Degree of the state's polynomial on each interval (the number of collocation
        points), 1 to 9.
    scheme : CollocationScheme or str, default "radau"
        Collocation points: ``"radau"`` (Radau IIA; the end point is a collocation point,
        so constraints hold at every mesh point: use it for constrained mechanisms) or
        ``"legendre"`` (Gauss-Legendre).
    solver : str, default "ipopt"
        How the square system is solved: ``"ipopt"`` (IPOPT with a zero objective) or
        ``"newton"`` (CasADi's Newton rootfinder).

    Raises
    ------
    SymcableError
        A value that is not an integer, out of its range, or not one of the choices.
    """

    intervals: int = 40
    degree: int = 3
    scheme: CollocationScheme = CollocationScheme.RADAU
    solver: str = "ipopt"

    def __post_init__(self):
        object.__setattr__(self, "intervals", _number("intervals", self.intervals, 2, integer=True))
        object.__setattr__(self, "degree", _number("degree", self.degree, 1, 9, integer=True))
        object.__setattr__(self, "scheme", parse_choice(CollocationScheme, self.scheme, "scheme"))
        if self.solver not in ("ipopt", "newton"):
            raise SymcableError(f"solver = {self.solver!r}: must be 'ipopt' or 'newton'")


@dataclass(frozen=True)
class HarmonicBalance:
    """Harmonic balance with ``harmonics`` harmonics, ``samples`` time samples per period
    (default 4 harmonics + 4, enough to resolve cubic nonlinearities without aliasing).
    Default 10 harmonics: the response to quadratic drag |v| v decays like 1/h^3, and 10
    put a drag-dominated line's fairlead tension within 0.1 % of its range of collocation's.

    Parameters
    ----------
    harmonics : int, default 10
        Harmonics of the period kept in the response, >= 1 (the mean is kept as well).
    samples : int or None, default None
        Time samples per period at which the equations are balanced, at least
        2 harmonics + 1; None: 4 harmonics + 4.

    Raises
    ------
    SymcableError
        A value that is not an integer or below its minimum.
    """

    harmonics: int = 10
    samples: int | None = None

    def __post_init__(self):
        object.__setattr__(self, "harmonics", _number("harmonics", self.harmonics, 1, integer=True))
        if self.samples is not None:
            object.__setattr__(self, "samples", _number("samples", self.samples,
                                                        2 * self.harmonics + 1, integer=True))


@dataclass(frozen=True)
class Shooting:
    """Shooting on the period map of generalized-alpha with ``steps`` steps per period (at
    least 8) and spectral radius ``rho_inf`` in [0, 1] at infinite step; None: the
    integrator's own default (0.8 for :class:`GeneralizedAlpha`, 0.5 for
    :class:`GeneralizedAlphaFirstOrder`; a cable3d, rod or hybrid scene: ``simulate``'s, 0);
    ``newton_tol`` (> 0) each step's
    scaled Newton tolerance, None: the integrator's default (a cable3d scene: ``simulate``'s,
    :data:`symcable.api.cable3d.NEWTON_TOL`).

    Parameters
    ----------
    steps : int, default 100
        Generalized-alpha steps per period, >= 8 (the step is the period over ``steps``,
        s).
    rho_inf : float or None, default None
        Spectral radius at infinite step, in [0, 1] (dimensionless); None: the
        integrator's default (0.8 or 0.5, above), or, for a scene of ``model`` cable3d, rod
        or hybrid, ``simulate``'s (0, :data:`symcable.api.cable3d.RHO_INF`).
    newton_tol : float or None, default None
        Each step's scaled Newton tolerance, > 0 (dimensionless, as ``tol`` of
        :class:`GeneralizedAlpha` and :class:`GeneralizedAlphaFirstOrder`); None: the
        integrator's default (1e-10), or, for a scene of ``model`` cable3d, rod or hybrid,
        ``simulate``'s (1e-8).

    Raises
    ------
    SymcableError
        A value that is not a number, out of its range, or not an integer.
    """

    steps: int = 100
    rho_inf: float | None = None
    newton_tol: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "steps", _number("steps", self.steps, 8, integer=True))
        if self.rho_inf is not None:
            object.__setattr__(self, "rho_inf", _number("rho_inf", self.rho_inf, 0, 1))
        if self.newton_tol is not None:
            object.__setattr__(self, "newton_tol",
                               _number("newton_tol", self.newton_tol, 0.0, lo_open=True))
