"""The result of :func:`symcable.sensitivity`: exact derivatives of named outputs of a
static state with respect to named numbers of its scene."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Sensitivity"]


@dataclass(frozen=True)
class Sensitivity:
    """d(outputs)/d(parameters) at a scene's static state, or of statistics over its
    periodic steady state (:mod:`symcable.api.periodic_sensitivity`).

    Attributes
    ----------
    scene_name : str
    outputs : tuple of str
        Each output entry's name: a vector output's entries as ``"NAME[i]"``.
    units : tuple of str
        Each output entry's unit.
    parameters : tuple of str
        Each parameter's dotted path in the scene (``"line_types.chain.diameter"``,
        ``"points.anchor0.position[0]"``).
    values : numpy.ndarray
        (n_out,) the outputs at the static state.
    parameter_values : numpy.ndarray
        (n_par,) the parameters' values in the scene.
    jacobian : numpy.ndarray
        (n_out, n_par): d output_i / d parameter_j, in the output's unit per the
        parameter's (N/m for a tension against a length).
    stats : dict
        ``parameter_steps`` (the steps of the parameters' central differences through the
        model's numbers, :func:`symcable.sensitivity`), ``residual_norm`` (N) of the state,
        ``wall_time`` (s), ``slopes`` (the model's numbers' slopes, (n_p + n_aux, n_par),
        for another load case of the design), ``slopes_reused`` (whether they were taken
        from one) and ``state`` ((q, z, p) of the static state, a start for a nearby
        design); periodic: ``period`` (s), ``harmonics`` and ``residual`` (the harmonic
        balance's, scaled) instead of the state's.
    """

    scene_name: str
    outputs: tuple
    units: tuple
    parameters: tuple
    values: np.ndarray
    parameter_values: np.ndarray
    jacobian: np.ndarray
    stats: dict

    def __getitem__(self, key) -> float:
        """``s[output, parameter]``: one derivative, by names."""
        out, par = key
        try:
            i, j = self.outputs.index(out), self.parameters.index(par)
        except ValueError:
            raise KeyError(f"{key!r}: outputs {list(self.outputs)}, parameters "
                           f"{list(self.parameters)}") from None
        return float(self.jacobian[i, j])

    def relative(self) -> np.ndarray:
        """(n_out, n_par) the elasticities (d y / y) / (d x / x): the share an output changes
        per share of a parameter (NaN where an output or a parameter is zero)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            r = self.jacobian * self.parameter_values[None, :] / self.values[:, None]
        return np.where(np.isfinite(r), r, np.nan)

    def to_dict(self) -> dict:
        """Plain data (lists, numbers): outputs with units and values, parameters with
        values, the Jacobian by rows (outputs), and the stats (but ``slopes``, the model's
        internal numbers)."""
        return {"scene_name": self.scene_name, "outputs": list(self.outputs),
                "units": list(self.units), "values": self.values.tolist(),
                "parameters": list(self.parameters),
                "parameter_values": self.parameter_values.tolist(),
                "jacobian": self.jacobian.tolist(),
                "stats": {k: (list(v) if isinstance(v, (list, tuple)) else v)
                          for k, v in self.stats.items() if k not in ("slopes", "state")}}

    def summary(self) -> str:
        """A table: each output with its value and its derivative in each parameter."""
        period = self.stats.get("period")
        where = "at its static state" if period is None else (
            f"over its periodic steady state (period {float(period):g} s, harmonic balance "
            f"of {self.stats.get('harmonics')} harmonics)")
        rows = [f"sensitivities of scene {self.scene_name!r} {where}"]
        for i, (name, unit) in enumerate(zip(self.outputs, self.units)):
            rows.append(f"  {name} = {self.values[i]:.6g} {unit}")
            for j, par in enumerate(self.parameters):
                rows.append(f"      d/d {par} (= {self.parameter_values[j]:.6g}): "
                            f"{self.jacobian[i, j]:.6g}")
        return "\n".join(rows)
