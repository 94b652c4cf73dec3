"""What ``pim sensitivity`` shows of a :class:`pim.analysis.sensitivity.Sensitivity`: its JSON
and its text tables in the user's units.

Every answer's value, every input's typical uncertainty (sigma), the derivative per unit and
the effect of one sigma are converted through :func:`pim.io.units.convert` into a
:class:`pim.io.units.DisplayUnits`; the unit of a derivative is the ratio of the two
(:func:`ratio_unit`).

What is not an effect is not shown as one: a derivative below the resolution of the finite
differences it comes from (:func:`resolved_derivative`) is 0, and the delta-V of a fixed
barrier (0 whatever the inputs) is one line saying so, not a table of zeros.
"""

from __future__ import annotations

import numpy as np

from comparisons.report.fit import quantity_factor
from pim.analysis.sensitivity import INPUT_STEP, INPUTS, SENSITIVITY_OUTPUTS, Sensitivity
from pim.io.units import display_units

__all__ = ["ratio_unit", "sensitivity_json", "sensitivity_lines", "resolved_derivative",
           "fixed_vehicle", "RESOLUTION"]

#: An effect below this fraction of its answer's scale (the larger of its value and its
#: largest effect) is what the central differences leave where the derivative is 0: their
#: truncation error is about INPUT_STEP**2 of the effects' scale (an exact 0 comes out as
#: 1.6e-9 of 0.40 m/s at INPUT_STEP = 1e-4, and 100 times that at 1e-3), their round-off
#: about 1e-16 / INPUT_STEP = 1e-12 of the value (6e-11 km/h beside 33 km/h).
RESOLUTION = 10 * INPUT_STEP ** 2


def resolved_derivative(sens: Sensitivity) -> np.ndarray:
    """:attr:`Sensitivity.derivative` with what lies below the finite differences'
    resolution (:data:`RESOLUTION` of the answer's scale) set to 0 [SI]."""
    effect = sens.effect
    scale = np.maximum(np.abs(np.asarray(sens.values, float)), effect.max(axis=1))
    return np.where(effect < RESOLUTION * scale[:, None], 0.0, sens.derivative)


def fixed_vehicle(sens: Sensitivity, output: str) -> int | None:
    """The number of the fixed barrier whose delta-V ``output`` is (None otherwise)."""
    for i in (1, 2):
        if output == f"delta_v{i}_magnitude" and np.all(getattr(sens.case, f"vehicle{i}").fixed):
            return i
    return None


def ratio_unit(out_unit: str, in_unit: str) -> str:
    """Unit of d out / d in.

    Parameters
    ----------
    out_unit, in_unit : str
        The output's and the input's unit labels ("-" when dimensionless).

    Returns
    -------
    str
        E.g. ``1/m``, ``(m/s)/deg``; ``-`` when both are the same.
    """
    if out_unit == in_unit:
        return "-"

    def wrap(u):
        return f"({u})" if ("/" in u or " " in u) else u

    return f"{'1' if out_unit == '-' else wrap(out_unit)}/{wrap(in_unit)}"


def sensitivity_json(sens: Sensitivity, units: str) -> dict:
    """:meth:`Sensitivity.to_dict` with every value, sigma and derivative in ``units``, each
    with its unit, and ``units`` naming the unit of each kind of quantity."""
    data = sens.to_dict()
    derivative = resolved_derivative(sens)
    for name, entry in data["outputs"].items():
        fo, uo = quantity_factor(SENSITIVITY_OUTPUTS[name].kind, units)
        k = sens.outputs.index(name)
        entry["value"] *= fo
        entry["unit"] = uo
        if fixed_vehicle(sens, name):
            entry.update(inputs=[], note=f"vehicle {fixed_vehicle(sens, name)} is a fixed "
                                         "barrier: its delta-V is 0 whatever the inputs")
        for row in entry["inputs"]:
            fi, ui = quantity_factor(INPUTS[row["input"]].kind, units)
            d = float(derivative[k, sens.inputs.index(row["input"])])
            row.update(sigma=row["sigma"] * fi, sigma_unit=ui,
                       per_unit=d * fo / fi, per_unit_unit=ratio_unit(uo, ui),
                       per_sigma=abs(d) * row["sigma"] * fo)
    data["units"] = display_units(units).to_json()
    return data


def _heading(name: str, sens: Sensitivity) -> str:
    """The first line: where the sensitivities are taken and how."""
    how = ("fitted to the measured motion" if sens.fit is not None
           else "at fixed epsilon, beta (nothing measured)")
    if sens.fit is not None and sens.fit.chi_square:
        how += ", weighted by the [measured] standard deviations"
    return (f"{name}: sensitivity at epsilon = {sens.eps:.4f}, beta = {sens.beta:.4f} "
            f"({how})")


#: What each source of a sigma means, for the line under the heading.
SOURCE_WORDS = {"case": "the case file's [uncertainty] or [measured] sigma",
                "estimate": "the scatter of an estimated input",
                "typical": "a typical value (pim.analysis.sensitivity.TypicalUncertainty)",
                "option": "--sigma"}


def _sources_line(sens: Sensitivity) -> str:
    """Which sources the sigmas come from, in words (source column of the tables)."""
    used = [s for s in SOURCE_WORDS if s in (sens.sources or ("typical",))]
    return "  sigma source: " + "; ".join(f"{s} = {SOURCE_WORDS[s]}" for s in used)


def _table(sens: Sensitivity, k: int, top: int | None, units: str) -> list[str]:
    """The ranked inputs of output ``k``: sigma, derivative per unit and per sigma."""
    fo, uo = quantity_factor(SENSITIVITY_OUTPUTS[sens.outputs[k]].kind, units)
    derivative = resolved_derivative(sens)[k]
    rows = []
    for i in sens.ranked(sens.outputs[k])[:top]:
        fi, ui = quantity_factor(INPUTS[sens.inputs[i]].kind, units)
        per_unit = f"{derivative[i] * fo / fi:+.4g}" if derivative[i] else "0"
        rows.append((INPUTS[sens.inputs[i]].label, f"{sens.sigma[i] * fi:.4g} {ui}",
                     sens.sources[i] if sens.sources else "typical",
                     per_unit, ratio_unit(uo, ui),
                     f"{abs(derivative[i]) * sens.sigma[i] * fo:.4g}"))
    head = ("input", "sigma", "source", "per unit", "unit", f"per sigma [{uo}]")
    widths = [max(len(r[c]) for r in [head, *rows]) for c in range(6)]
    fmt = "  " + "  ".join(f"{{:{a}{w}}}" for a, w in zip("<><><>", widths, strict=True))
    return [fmt.format(*head), "  " + "  ".join("-" * w for w in widths),
            *(fmt.format(*r) for r in rows)]


def sensitivity_lines(name: str, sens: Sensitivity, units: str,
                      top: int | None = None) -> list[str]:
    """``pim sensitivity``'s text, one line each.

    Parameters
    ----------
    name : str
        The case's name.
    sens : Sensitivity
        The sensitivities.
    units : DisplayUnits or str
        The output's units.
    top : int, optional
        Show only the ``top`` largest effects of each answer (default: all).

    Returns
    -------
    list of str
        The heading, the inputs held on an active bound, then per answer a blank line, its
        value and the table of its inputs ranked by the effect of one sigma.
    """
    lines = [_heading(name, sens), _sources_line(sens)]
    if sens.active_bounds:
        lines.append(f"  {', '.join(sens.active_bounds)} on an active bound: held there "
                     "(derivative 0)")
    for k, out in enumerate(sens.outputs):
        fo, uo = quantity_factor(SENSITIVITY_OUTPUTS[out].kind, units)
        lines += ["", f"{SENSITIVITY_OUTPUTS[out].label} = {sens.values[k] * fo:.5g} "
                      f"{uo if uo != '-' else ''}".rstrip()
                  + ("  (includes the refit of epsilon, beta)"
                     if out.startswith("delta") and sens.fit is not None else "")]
        if out in sens.active_bounds:
            lines.append("  held on an active bound: small input changes do not move it")
            continue
        if fixed_vehicle(sens, out):
            lines.append(f"  vehicle {fixed_vehicle(sens, out)} is a fixed barrier: its "
                         "delta-V is 0 whatever the inputs")
            continue
        lines += _table(sens, k, top, units)
    return lines
