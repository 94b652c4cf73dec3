"""What ``pim fit`` shows of a :class:`pim.analysis.fitting.FitResult`: its JSON in the user's
units and its text, line by line.

The fit itself is SI (:meth:`~pim.analysis.fitting.FitResult.to_dict`); here its velocities,
yaw rates, velocity-squared costs, residuals and freed inputs are converted through
:func:`pim.io.units.convert` into a :class:`pim.io.units.DisplayUnits`, each value with its
unit, and the words about the fit (the coefficients with their search ranges, the cost or the
chi-square with its verdict, the bounds the optimum sits on, the other minima, the residual
table) are written once for the command line and any other output.
"""

from __future__ import annotations

from pim.analysis.fitting import SHORT_NAMES, FitResult
from pim.analysis.free_inputs import free_kind
from pim.io.units import convert, display_units, unit_scale

__all__ = ["quantity_factor", "shown_value", "fit_json", "fit_values_json", "bound_notes",
           "cost_lines", "coefficient_lines", "residual_lines", "fit_lines", "error_lines",
           "errors_json"]

KS = "kudlich-slibar"
#: The law's own coefficients among a fit's values (shown as coefficients, not as inputs).
_COEFFICIENT_KEYS = ("impact.restitution", "impact.beta", "impact.k", "impact.mu_c")

#: SI unit labels of FitResult.to_dict() -> (unit kind, power): the fields converted to the
#: user's units in ``--json``; unit-free fields (a chi-square) stay as they are.
_SI_LABELS = {"m/s": ("velocity", 1), "m^2/s^2": ("velocity", 2), "(m/s)^2": ("velocity", 2)}


def quantity_factor(kind: str | None, units: str) -> tuple[float, str]:
    """Display factor and unit of a quantity kind.

    Parameters
    ----------
    kind : str or None
        A unit kind of :func:`pim.io.units.convert` ("velocity", "angle", ...); None for a
        dimensionless quantity.
    units : DisplayUnits or str
        The output's units.

    Returns
    -------
    (float, str)
        The factor that takes an SI value into ``units`` and the unit's label ("-" when
        dimensionless).
    """
    return (1.0, "-") if kind is None else unit_scale(kind, units)


def shown_value(value: float, kind: str, units: str) -> dict:
    """An SI value of ``kind`` in ``units`` as JSON: ``{"value", "unit"}``."""
    shown, unit = convert(float(value), kind, units)
    return {"value": float(shown), "unit": unit}


def _residual_kind(name: str) -> str:
    """Unit kind of a residual term by its name (yaw rates, energies, else velocities)."""
    if name.startswith("yaw_rate"):
        return "angular_velocity"
    return "energy" if name in ("energy_loss", "crush_energy") else "velocity"


def fit_json(result: FitResult, units: str) -> dict:
    """``pim fit --json``: :meth:`FitResult.to_dict` in the user's units.

    Parameters
    ----------
    result : FitResult
        The fit.
    units : DisplayUnits or str
        The output's units.

    Returns
    -------
    dict
        The SI summary with its velocities [speed unit], velocity-squared costs (the cost,
        each minimum's cost, the gradient) [(speed unit)^2] and residuals converted, each
        ``*_unit`` naming its unit, ``residual_units`` the unit of each residual, and
        ``units`` naming the unit of each kind of quantity (a chi-square stays unit-free).
    """
    data = result.to_dict()
    out = dict(data)
    for key in [k for k in data if k.endswith("_unit")]:
        field, label = key.removesuffix("_unit"), data[key]
        if label not in _SI_LABELS or field not in data:
            continue
        kind, power = _SI_LABELS[label]
        factor, unit = convert(1.0, kind, units)
        scale = float(factor) ** power
        out[field] = data[field] * scale
        out[key] = unit if power == 1 else f"({unit})^2"
        if field == "cost":
            out["minima"] = [dict(m, cost=m["cost"] * scale) for m in data.get("minima", [])]
            out["gradient"] = {k: v * scale for k, v in data.get("gradient", {}).items()}
    kinds = {name: _residual_kind(name) for name in data.get("residuals", {})}
    out["residuals"] = {name: value * quantity_factor(kinds[name], units)[0]
                        for name, value in data.get("residuals", {}).items()}
    out["residual_units"] = {name: quantity_factor(kinds[name], units)[1] for name in kinds}
    out.update(errors_json(result, units))
    out["units"] = display_units(units).to_json()
    return out


#: The short names of the law's coefficients in the standard-error lines.
_SHORT = {"impact.restitution": "epsilon", "impact.beta": "beta", "impact.k": "k",
          "impact.mu_c": "mu_c"}


def errors_json(result: FitResult, units: str) -> dict:
    """``standard_errors`` (each fitted key's value, standard error and unit, in ``units``),
    ``correlation`` and ``error_basis`` of ``pim fit --json``."""
    errors = {}
    for key, sd in result.standard_errors.items():
        value, unit = convert([result.values[key], sd], free_kind(key), units)
        errors[key] = {"value": float(value[0]), "standard_error": float(value[1]),
                       "unit": unit, "on_bound": result.on_bound.get(_short_key(key))}
    return {"standard_errors": errors, "error_basis": result.error_basis,
            "correlation": [{"a": a, "b": b, "r": r} for (a, b), r in
                            result.correlation.items()]}


def _short_key(key: str) -> str:
    """A fitted key as ``on_bound`` names it ("eps", "beta", "k", "mu_c" or the key)."""
    return SHORT_NAMES.get(key, key)


def error_lines(result: FitResult, units: str) -> list[str]:
    """Each fitted parameter's value and standard error in ``units``, flagged where it sits on
    a bound (one-sided), their correlations, and the basis of both; or why there are none."""
    if not result.standard_errors:
        return [f"  {result.error_basis}"] if result.error_basis else []
    lines = [f"  {result.error_basis}:"]
    width = max(len(_SHORT.get(key, key)) for key in result.standard_errors)
    for key, sd in result.standard_errors.items():
        (value, error), unit = convert([result.values[key], sd], free_kind(key), units)
        side = result.on_bound.get(_short_key(key))
        lines.append(f"    {_SHORT.get(key, key):<{width}} = {value:.6g} +- {error:.3g}"
                     + ("" if unit == "-" else f" {unit}")
                     + (f"   (on its {side} bound: the interval is one-sided)" if side else ""))
    lines += [f"    correlation r({_SHORT.get(a, a)}, {_SHORT.get(b, b)}) = {r:+.3f}"
              for (a, b), r in result.correlation.items()]
    return lines


def _shows_values(result: FitResult, free: bool) -> bool:
    """Whether the output shows the fitted values and the identifiability: with freed inputs
    or under the Kudlich-Slibar law (whose mu_c may be only a lower bound)."""
    return bool(free) or result.law == KS


def fit_values_json(result: FitResult, units: str, free: bool = False) -> dict:
    """The fitted values in ``units`` (``values``, ``value_units``) and the identifiability,
    when the fit freed inputs (``free``) or ran under the Kudlich-Slibar law; else empty."""
    if not _shows_values(result, free):
        return {}
    shown = {k: shown_value(v, free_kind(k), units) for k, v in result.values.items()}
    ident = result.identifiability
    return {"values": {k: s["value"] for k, s in shown.items()},
            "value_units": {k: s["unit"] for k, s in shown.items()},
            "identifiability": ident.to_dict() if ident is not None else None}


def bound_notes(result: FitResult, units: str) -> list[str]:
    """One sentence per parameter on a bound of its search range: which bound, and for
    (eps, beta) the slope of the cost there (in the user's velocity unit squared unless the
    cost is a chi-square), which says the error would keep falling beyond it."""
    fv, uv = convert(1.0, "velocity", units)
    lines = []
    for name, side in result.on_bound.items():
        if name not in ("eps", "beta"):
            lines.append(f"{name} sits on its {side} bound")
            continue
        k = ("eps", "beta").index(name)
        value = result.bounds[k][0 if side == "lower" else 1]
        slope = result.gradient[k]
        cost = (f"{slope:.4g}" if result.chi_square
                else f"{slope * fv * fv:.4g} ({uv})^2")
        lines.append(f"{name} sits on its {side} bound {value:g} (d cost / d {name} = "
                     f"{cost}: the error would keep falling beyond it)")
    return lines


def cost_lines(result: FitResult, units: str) -> list[str]:
    """The cost in words: the chi-square [-] with its degrees of freedom, p-value and verdict
    when the measured values carry standard deviations, else the sum of squares in the
    user's velocity unit squared; the rms residual in the user's unit."""
    fv, uv = quantity_factor("velocity", units)
    rms = f"rms residual = {result.rms * fv:.4g} {uv}"
    if result.goodness is None:
        return [f"  cost    = {result.cost * fv * fv:.6g} ({uv})^2 (sum of squares)   {rms}"]
    line, verdict = result.goodness.summary().split("): ", 1)
    return [f"  {line})   {rms}", f"  {verdict}"]


def coefficient_lines(result: FitResult) -> list[str]:
    """The fitted law's coefficients, one line each, with their search ranges (Brach's
    epsilon and beta with mu and mu0; or Kudlich-Slibar's k and mu_c, a mu_c the contact
    does not reach given as the lower bound it is, with Brach's equivalent)."""
    solved = result.result

    def where(k, name):
        if name in result.fixed:
            return "(fixed)"
        return f"search range [{result.bounds[k][0]:g}, {result.bounds[k][1]:g}]"

    if result.law != KS:
        return [f"  epsilon = {result.eps:.6f}   {where(0, 'eps')}",
                f"  beta    = {result.beta:.6f}   {where(1, 'beta')}   "
                f"(mu = {float(solved.mu):.4f}, mu0 = {float(solved.mu0):.4f})"]
    lower = result.lower_bounds.get("impact.mu_c")
    shown = (f">= {lower:.6f}   (only a lower bound: the contact sticks)" if lower is not None
             else f"= {result.contact_friction:.6f}   {where(1, 'mu_c')}")
    return [f"  k       = {result.eps:.6f}   {where(0, 'k')}", f"  mu_c    {shown}",
            f"  (impulse ratio Pt / Pn = {float(solved.mu):.4f}; the same answer is Brach's "
            f"at eps = {result.eps:.6g}, beta = {result.beta:.6g})"]


def residual_lines(result: FitResult, units: str) -> list[str]:
    """The table of measured terms: model, measured and residual in the user's units."""
    header = f"  {'term':<14} {'model':>10} {'measured':>10} {'residual':>10}  unit"
    lines = [header, "  " + "-" * (len(header) - 2)]
    for row in result.residual_table:
        f, unit = quantity_factor(row["kind"], units)
        model, meas = row["fitted"] * f, row["measured"] * f
        lines.append(f"  {row['name']:<14} {_cell(model)} {_cell(meas)} {_cell(model - meas)}  "
                     f"{unit}")
    return lines


def _cell(value: float) -> str:
    """A table number to 4 decimals, a value that rounds to zero as 0.0000 (not -0.0000)."""
    return f"{round(value, 4) + 0.0:10.4f}"


def _title(name: str, result: FitResult) -> str:
    """The first line: the case, the law and what was fitted."""
    fixed = f" (fixed: {', '.join(result.fixed)})" if result.fixed else ""
    law = ""
    if result.law == KS:
        law = " under the Kudlich-Slibar law (k, mu_c)"
    elif result.law == "brach-capped":
        law = (" under the friction-capped Brach law (eps, beta; cap mu_c = "
               f"{result.contact_friction:g})")
    what = "velocities and yaw rates" if result.include_yaw else "velocities"
    return f"{name}: least-squares fit{law} of the post-impact {what}{fixed}"


def _value_lines(result: FitResult, units: str, free: bool) -> list[str]:
    """The freed inputs' values in ``units`` and the identifiability with its warnings."""
    lines = []
    for key, value in (result.values.items() if free else ()):
        if key in _COEFFICIENT_KEYS:
            continue
        shown, unit = convert(value, free_kind(key), units)
        lines.append(f"  {key} = {float(shown):.6g} {unit}")
    ident = result.identifiability
    if _shows_values(result, free) and ident is not None:
        lines.append(f"  identifiability: rank {ident.rank} of {len(ident.names)} "
                     f"parameters, {ident.n_data} measured quantities")
        lines += [f"  warning: {text}" for text in ident.warnings]
    return lines


def _minima_line(result: FitResult, units: str) -> list[str]:
    """The other local minima (their costs in the user's units), if any."""
    if len(result.minima) <= 1:
        return []
    fv = quantity_factor("velocity", units)[0]
    scale = 1.0 if result.chi_square else fv * fv
    names = "k, mu_c" if result.law == KS else "eps, beta"
    return [f"  other local minima ({names}, cost): " + ", ".join(
        f"({e:.4f}, {b:.4f}, {c * scale:.4g})" for e, b, c in result.minima[1:])]


def fit_lines(name: str, result: FitResult, units: str, free: bool = False) -> list[str]:
    """``pim fit``'s text, one line each.

    Parameters
    ----------
    name : str
        The case's name (the first line's subject).
    result : FitResult
        The fit.
    units : DisplayUnits or str
        The output's units.
    free : bool
        The fit freed inputs beyond the law's coefficients (their values are shown).

    Returns
    -------
    list of str
        The title, the coefficients, the cost, the freed values and the identifiability,
        the notes on bounds, the other minima, a blank line and the residual table.
    """
    return ([_title(name, result), *coefficient_lines(result), *cost_lines(result, units),
             *_value_lines(result, units, free), *error_lines(result, units)]
            + [f"  note: {line}" for line in bound_notes(result, units)]
            + [f"  note: {line}" for line in _left_out_notes(result)]
            + _minima_line(result, units) + ["", *residual_lines(result, units)])


def _left_out_notes(result: FitResult) -> list[str]:
    """Which measured yaw rates the fit left out, and how to fit them."""
    if not result.left_out:
        return []
    return [f"measured {', '.join(result.left_out)} not fitted (no yaw_rate_sigma in "
            f"[measured]; give one, or --include-yaw to fit every measured yaw rate)"]
