"""``pim fit``, ``pim sensitivity`` and ``pim plot``: the least-squares optimum, its
sensitivities and the design sheet's graphs."""

from __future__ import annotations

import click

from pim.model.numbers import InputError
from pim_cli.main import (
    Beta,
    FiniteFloat,
    allow_inadmissible_option,
    case_argument,
    check_answer,
    echo_json,
    findings_json,
    finish_answer,
    json_option,
    load_case_for,
    output_units,
    units_option,
)

__all__ = ["fit", "sensitivity", "plot"]

include_yaw_option = click.option(
    "--include-yaw", is_flag=True,
    help="Also fit the measured yaw rates, weighted by each vehicle's radius of gyration.")
fixed_eps_option = click.option("--eps", type=FiniteFloat(), default=None,
                                help="Hold epsilon fixed at this value and fit beta only.")
fixed_beta_option = click.option("--beta", type=Beta(), default=None,
                                 help="Hold beta fixed at this value and fit epsilon only.")
eps_range_option = click.option("--eps-range", type=FiniteFloat(), nargs=2, default=(0.0, 1.0),
                                show_default=True, metavar="MIN MAX",
                                help="Search range of epsilon (within [0, 1]).")
beta_range_option = click.option("--beta-range", type=FiniteFloat(), nargs=2, default=(0.0, 1.0),
                                 show_default=True, metavar="MIN MAX",
                                 help="Search range of beta; the sheet's constraint is "
                                      "beta <= 1 (wider ranges are flagged).")


fixed_k_option = click.option("--k", "k", type=FiniteFloat(), default=None,
                              help="Kudlich-Slibar law: hold the restitution k fixed at this "
                                   "value and fit mu_c only.")
fixed_mu_c_option = click.option("--mu-c", "mu_c", type=FiniteFloat(), default=None,
                                 help="Kudlich-Slibar law: hold the contact friction mu_c fixed "
                                      "and fit k only (friction-capped Brach: the cap).")

free_option = click.option(
    "--free", "free", multiple=True, metavar='KEY="LO,HI"',
    help="Also fit this input within [LO, HI] (unit strings), by its case-file key, e.g. "
         '--free impact.normal_angle="0 deg,90 deg" --free vehicle1.radius_of_gyration='
         '"1 m,1.6 m"; repeatable. Keys: every [uncertainty] input, '
         "vehicleN.radius_of_gyration, vehicleN.speed, Brach's vehicleN.phi and vehicleN.d, "
         "impact.point_along (C along the contact plane), impact.k and impact.mu_c "
         "(Kudlich-Slibar; impact.mu_c's range, default 0 to 2).")


def _kind_of(key: str) -> str:
    """Unit kind of a free key, for parsing its bounds and printing its value."""
    from pim.model.evidence import UNKNOWN_KINDS
    from pim.model.quantities import INPUTS

    return INPUTS[key].kind if key in INPUTS else UNKNOWN_KINDS[key]


def _key_value(item: str, allowed, option: str, form: str) -> tuple[str, str]:
    """``KEY=TEXT`` of a repeatable option -> (key, text); ValueError naming the option and
    the allowed keys when the form or the key is wrong."""
    key, sep, text = item.partition("=")
    key = key.strip()
    if not sep or key not in allowed:
        raise InputError(f"{option} must be {form} with KEY one of {', '.join(allowed)}; "
                         f"got {item!r}")
    return key, text


def parse_free(items) -> dict:
    """``--free KEY="LO,HI"`` options -> {key: (lo, hi)} in SI (one line, exit 2, if bad)."""
    from pim.analysis.free_fit import FREE_KEYS
    from pim.io.units import parse

    out = {}
    for item in items:
        key, text = _key_value(item, FREE_KEYS, "--free", 'KEY="LO,HI"')
        parts = [t.strip() for t in text.strip().strip('"').split(",")]
        if len(parts) != 2:
            raise InputError(f"--free {key}: give two bounds separated by a comma, got {text!r}")
        kind = _kind_of(key)
        out[key] = tuple(parse(t, kind, f"--free {key}") for t in parts)
    return out


def _shown(value, kind: str, units: str) -> dict:
    """{"value", "unit"} of an SI value of ``kind`` in ``units``."""
    from pim.io.units import convert

    shown, unit = convert(float(value), kind, units)
    return {"value": float(shown), "unit": unit}


#: SI unit labels of FitResult.to_dict() -> (unit kind, power): the fields converted to the
#: user's units in ``--json``; unit-free fields (a chi-square) stay as they are.
_SI_LABELS = {"m/s": ("velocity", 1), "m^2/s^2": ("velocity", 2), "(m/s)^2": ("velocity", 2)}


def fit_json(data: dict, units: str) -> dict:
    """FitResult.to_dict() (SI) with its velocities, yaw rates and velocity-squared costs in
    ``units`` (a :class:`pim.io.units.DisplayUnits`), each with its unit, and ``units``
    naming the unit of each kind of quantity."""
    from pim.io.units import convert, display_units

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
    fv, uv = convert(1.0, "velocity", units)
    fw, uw = convert(1.0, "angular_velocity", units)
    kinds = {name: ("angular_velocity" if name.startswith("yaw_rate") else "energy"
                    if name in ("energy_loss", "crush_energy") else "velocity")
             for name in data.get("residuals", {})}
    out["residuals"] = {name: value * _factor(kinds[name], units)[0]
                        for name, value in data.get("residuals", {}).items()}
    out["residual_units"] = {name: _factor(kinds[name], units)[1] for name in kinds}
    out["units"] = display_units(units).to_json()
    return out


def _fit(case, include_yaw, eps, beta, eps_range, beta_range, free=None, mu_c=None):
    from pim.analysis.fitting import fit as fit_case

    return fit_case(case, include_yaw=include_yaw, bounds=(eps_range, beta_range),
                    eps=eps, beta=beta, free=free or None, mu_c=mu_c)


def _describe_bounds(result, units) -> list[str]:
    from pim.io.units import convert

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


def _cost_lines(result, fv: float, uv: str) -> list[str]:
    """The cost in words: the chi-square [-] with its degrees of freedom, p-value and verdict
    when the measured values carry standard deviations, else the sum of squares in the
    user's velocity unit squared; the rms residual in the user's unit."""
    rms = f"rms residual = {result.rms * fv:.4g} {uv}"
    if result.goodness is None:
        return [f"  cost    = {result.cost * fv * fv:.6g} ({uv})^2 (sum of squares)   {rms}"]
    g = result.goodness
    line, verdict = g.summary().split("): ", 1)
    return [f"  {line})   {rms}", f"  {verdict}"]


@click.command()
@case_argument
@include_yaw_option
@fixed_eps_option
@fixed_beta_option
@fixed_k_option
@fixed_mu_c_option
@eps_range_option
@beta_range_option
@free_option
@units_option
@allow_inadmissible_option
@json_option
def fit(case_name, include_yaw, eps, beta, k, mu_c, eps_range, beta_range, free, units,
        speed_unit, allow_inadmissible, as_json):
    """Fit the impact law's parameters (Brach's epsilon and beta, or k and mu_c) to CASE's
    measured post-impact motion.

    Least squares: Brach's (epsilon, beta), or under the case's law "kudlich-slibar" its
    (k, mu_c).

    Searches the whole box with a Sobol sample, then refines the best minima, so it finds
    the global optimum. --eps or --beta (--k or --mu-c) fits the other parameter alone;
    --free adds any other input, and the output then says whether the data determine them
    all (rank, families of equally good fits, under-determined, a mu_c that only has a
    lower bound). Exit code 1 after the output when the fitted answer is inadmissible (the
    reasons first; --allow-inadmissible: exit 0), e.g. beta > 1 with a --beta-range beyond 1.
    """

    case = load_case_for("fit", case_name)
    units = output_units(case, units, speed_unit)
    ks = (case.impact.law or "brach") == "kudlich-slibar"
    if k is not None and not ks:
        raise InputError("--k is the restitution of law kudlich-slibar (use --eps)")
    if ks and eps is not None:
        raise InputError("--eps: the case's law is kudlich-slibar; hold k with --k")
    result = _fit(case, include_yaw, k if ks else eps, beta, eps_range, beta_range,
                  parse_free(free), mu_c)
    ident = result.identifiability
    found = check_answer(result.case, result.result, units, allow=allow_inadmissible,
                         as_json=as_json)
    if as_json:
        data = fit_json(result.to_dict(), units) | findings_json(found)
        if free or ks:
            shown = {k: _shown(v, _kind_of(k), units) for k, v in result.values.items()}
            data["values"] = {k: s["value"] for k, s in shown.items()}
            data["value_units"] = {k: s["unit"] for k, s in shown.items()}
            data["identifiability"] = ident.to_dict() if ident is not None else None
        echo_json(data)
    else:
        _print_fit(case, result, include_yaw, free, units)
    finish_answer(found, allow_inadmissible)


def _coefficient_lines(result) -> list[str]:
    """The fitted law's coefficients, one line each, with their search ranges."""
    solved = result.result

    def where(k, name):
        if name in result.fixed:
            return "(fixed)"
        return f"search range [{result.bounds[k][0]:g}, {result.bounds[k][1]:g}]"

    if result.law != "kudlich-slibar":
        return [f"  epsilon = {result.eps:.6f}   {where(0, 'eps')}",
                f"  beta    = {result.beta:.6f}   {where(1, 'beta')}   "
                f"(mu = {float(solved.mu):.4f}, mu0 = {float(solved.mu0):.4f})"]
    mu_c = result.contact_friction
    lower = result.lower_bounds.get("impact.mu_c")
    shown = (f">= {lower:.6f}   (only a lower bound: the contact sticks)" if lower is not None
             else f"= {mu_c:.6f}   {where(1, 'mu_c')}")
    return [f"  k       = {result.eps:.6f}   {where(0, 'k')}", f"  mu_c    {shown}",
            f"  (impulse ratio Pt / Pn = {float(solved.mu):.4f}; the same answer is Brach's "
            f"at eps = {result.eps:.6g}, beta = {result.beta:.6g})"]


def _print_fit(case, result, include_yaw, free, units) -> None:
    """``pim fit``'s text output."""
    from pim.io.units import convert

    ident = result.identifiability
    fv, uv = convert(1.0, "velocity", units)
    fw, uw = convert(1.0, "angular_velocity", units)
    fixed = f" (fixed: {', '.join(result.fixed)})" if result.fixed else ""
    law = ""
    if result.law == "kudlich-slibar":
        law = " under the Kudlich-Slibar law (k, mu_c)"
    elif result.law == "brach-capped":
        law = (" under the friction-capped Brach law (eps, beta; cap mu_c = "
               f"{result.contact_friction:g})")
    click.echo(f"{case.name}: least-squares fit{law} of the post-impact "
               f"{'velocities and yaw rates' if include_yaw else 'velocities'}{fixed}")
    for line in _coefficient_lines(result):
        click.echo(line)
    for line in _cost_lines(result, fv, uv):
        click.echo(line)
    for key, value in (result.values.items() if free else ()):
        if key in ("impact.restitution", "impact.beta", "impact.k", "impact.mu_c"):
            continue
        shown, unit = convert(value, _kind_of(key), units)
        click.echo(f"  {key} = {float(shown):.6g} {unit}")
    if (free or result.law == "kudlich-slibar") and ident is not None:
        click.echo(f"  identifiability: rank {ident.rank} of {len(ident.names)} parameters, "
                   f"{ident.n_data} measured quantities")
        for text in ident.warnings:
            click.echo(f"  warning: {text}")
    for line in _describe_bounds(result, units):
        click.echo(f"  note: {line}")
    if len(result.minima) > 1:
        scale = 1.0 if result.chi_square else fv * fv
        names = "k, mu_c" if result.law == "kudlich-slibar" else "eps, beta"
        click.echo(f"  other local minima ({names}, cost): " + ", ".join(
            f"({e:.4f}, {b:.4f}, {c * scale:.4g})" for e, b, c in result.minima[1:]))
    click.echo("")
    header = f"  {'term':<14} {'model':>10} {'measured':>10} {'residual':>10}  unit"
    click.echo(header)
    click.echo("  " + "-" * (len(header) - 2))
    for row in result.residual_table:
        f, unit = _factor(row["kind"], units)
        model, meas = row["fitted"] * f, row["measured"] * f
        click.echo(f"  {row['name']:<14} {model:10.4f} {meas:10.4f} {model - meas:10.4f}  {unit}")


def _factor(kind, units: str) -> tuple[float, str]:
    """Display factor and unit of a quantity kind (None: dimensionless)."""
    from pim.io.units import convert

    if kind is None:
        return 1.0, "-"
    value, unit = convert(1.0, kind, units)
    return float(value), unit


def sensitivity_json(sens, units: str) -> dict:
    """Sensitivity.to_dict() with every value, sigma and derivative in ``units``."""
    from pim.analysis.sensitivity import INPUTS, SENSITIVITY_OUTPUTS
    from pim.io.units import display_units

    data = sens.to_dict()
    for name, entry in data["outputs"].items():
        fo, uo = _factor(SENSITIVITY_OUTPUTS[name].kind, units)
        entry["value"] *= fo
        entry["unit"] = uo
        for row in entry["inputs"]:
            fi, ui = _factor(INPUTS[row["input"]].kind, units)
            row.update(sigma=row["sigma"] * fi, sigma_unit=ui,
                       per_unit=row["per_unit"] * fo / fi, per_unit_unit=_ratio_unit(uo, ui),
                       per_sigma=row["per_sigma"] * fo)
    data["units"] = display_units(units).to_json()
    return data


def _ratio_unit(out_unit: str, in_unit: str) -> str:
    """Unit of d out / d in, e.g. 1/m, (m/s)/deg; '-' when both are the same."""
    if out_unit == in_unit:
        return "-"

    def wrap(u):
        return f"({u})" if ("/" in u or " " in u) else u

    return f"{'1' if out_unit == '-' else wrap(out_unit)}/{wrap(in_unit)}"


def _parse_sigma(items) -> dict:
    from pim.analysis.sensitivity import TypicalUncertainty
    from pim.io.units import parse

    kinds = {"point": "length", "normal_angle": "angle", "mass_fraction": "dimensionless",
             "inertia_fraction": "dimensionless", "velocity": "velocity",
             "yaw_rate": "angular_velocity", "measured_velocity": "velocity",
             "measured_yaw_rate": "angular_velocity"}
    out = {}
    for item in items:
        key, value = _key_value(item, kinds, "--sigma", "KEY=VALUE")
        out[key] = parse(value.strip(), kinds[key], f"--sigma {key}")
    return TypicalUncertainty(**out)


@click.command()
@case_argument
@include_yaw_option
@click.option("--eps", type=FiniteFloat(), default=None,
              help="Evaluate delta-V at this epsilon instead of fitting.")
@click.option("--beta", type=Beta(), default=None,
              help="Evaluate delta-V at this beta instead of fitting.")
@click.option("--sigma", "sigmas", multiple=True, metavar="KEY=VALUE",
              help="Override a typical uncertainty, e.g. --sigma point='0.2 m' "
                   "--sigma normal_angle='3 deg' --sigma mass_fraction=0.05. Keys: point, "
                   "normal_angle, mass_fraction, inertia_fraction, velocity, yaw_rate, "
                   "measured_velocity, measured_yaw_rate.")
@click.option("--top", type=click.IntRange(min=1), default=None,
              help="Show only the N largest effects.")
@units_option
@allow_inadmissible_option
@json_option
def sensitivity(case_name, include_yaw, eps, beta, sigmas, top, units, speed_unit,
                allow_inadmissible, as_json):
    """Rank CASE's uncertain inputs by how much they move the fitted (epsilon, beta) and
    delta-V.

    For each answer, the inputs are ranked by the change that one typical uncertainty
    (sigma) of the input causes; the derivative per unit is shown too. Exit code 1 after
    the output when the answer at (epsilon, beta) is inadmissible (the reasons first;
    --allow-inadmissible: exit 0).
    """
    from pim.analysis.sensitivity import sensitivity as compute
    from pim.model.solver import solve

    case = load_case_for("sensitivity", case_name)
    units = output_units(case, units, speed_unit)
    sens = compute(case, eps=eps, beta=beta, uncertainty=_parse_sigma(sigmas),
                   include_yaw=include_yaw)
    found = check_answer(case, solve(case, sens.eps, sens.beta), units,
                         allow=allow_inadmissible, as_json=as_json)
    if as_json:
        echo_json(sensitivity_json(sens, units) | findings_json(found))
    else:
        _print_sensitivity(case, sens, top, units)
    finish_answer(found, allow_inadmissible)


def _print_sensitivity(case, sens, top, units) -> None:
    """``pim sensitivity``'s text output."""
    from pim.analysis.sensitivity import INPUTS, SENSITIVITY_OUTPUTS


    how = ("fitted to the measured motion" if sens.fit is not None
           else "at fixed epsilon, beta (nothing measured)")
    if sens.fit is not None and sens.fit.chi_square:
        how += ", weighted by the [measured] standard deviations"
    click.echo(f"{case.name}: sensitivity at epsilon = {sens.eps:.4f}, beta = {sens.beta:.4f} "
               f"({how})")
    if sens.active_bounds:
        click.echo(f"  {', '.join(sens.active_bounds)} on an active bound: held there "
                   "(derivative 0)")
    for k, out in enumerate(sens.outputs):
        label, out_kind = SENSITIVITY_OUTPUTS[out].label, SENSITIVITY_OUTPUTS[out].kind
        fo, uo = _factor(out_kind, units)
        click.echo("")
        click.echo(f"{label} = {sens.values[k] * fo:.5g} {uo if uo != '-' else ''}".rstrip()
                   + ("  (includes the refit of epsilon, beta)"
                      if out.startswith("delta") and sens.fit is not None else ""))
        if out in sens.active_bounds:
            click.echo("  held on an active bound: small input changes do not move it")
            continue
        rows = []
        for i in sens.ranked(out)[:top]:
            in_label, in_kind = INPUTS[sens.inputs[i]].label, INPUTS[sens.inputs[i]].kind
            fi, ui = _factor(in_kind, units)
            rows.append((in_label, f"{sens.sigma[i] * fi:.4g} {ui}",
                         f"{sens.derivative[k, i] * fo / fi:+.4g}",
                         _ratio_unit(uo, ui),
                         f"{sens.effect[k, i] * fo:.4g}"))
        head = ("input", "sigma", "per unit", "unit", f"per sigma [{uo}]")
        widths = [max(len(r[c]) for r in [head, *rows]) for c in range(5)]
        fmt = "  " + "  ".join(f"{{:{a}{w}}}" for a, w in zip("<>><>", widths, strict=True))
        click.echo(fmt.format(*head))
        click.echo("  " + "  ".join("-" * w for w in widths))
        for r in rows:
            click.echo(fmt.format(*r))


@click.command()
@case_argument
@click.option("--out", "out_dir", type=click.Path(file_okay=False), required=True,
              help="Directory for the figures (created if missing).")
@click.option("--format", "formats", type=click.Choice(["png", "svg", "pdf"]), multiple=True,
              default=("png", "svg"), show_default=True, help="File format (repeatable).")
@include_yaw_option
@eps_range_option
@beta_range_option
@units_option
@allow_inadmissible_option
def plot(case_name, out_dir, formats, include_yaw, eps_range, beta_range, units, speed_unit,
         allow_inadmissible):
    """Draw the design sheet's graphs for CASE into --out (PNG and SVG).

    Cost vs epsilon, impulse ratio, impulse on vehicle 2, PDOF, energy loss, post-impact
    velocities with the measured values, and the cost map over (epsilon, beta). Exit code 1
    after writing when the fitted answer is inadmissible (the reasons first;
    --allow-inadmissible: exit 0).
    """
    from pim.analysis.residuals import has_measured_terms
    from pim.io.output import output_folder, rebase
    from pim.plotting.sheet import write_plots

    case = load_case_for("plot", case_name)
    units = output_units(case, units, speed_unit)
    if has_measured_terms(case, include_yaw):
        result = _fit(case, include_yaw, None, None, eps_range, beta_range)
    else:
        result = None
        click.echo("note: nothing measured; plotting without the fit", err=True)
    found = check_answer(result.case if result else case, result.result if result else None,
                         units, allow=allow_inadmissible)
    with output_folder(out_dir, command="pim plot") as tmp:
        files = write_plots(case, result, tmp, formats=formats, units=units)
    for path in rebase(files, tmp, out_dir):
        click.echo(str(path))
    finish_answer(found, allow_inadmissible)
