"""``pim fit``, ``pim sensitivity`` and ``pim plot``: the least-squares optimum, its
sensitivities and the design sheet's graphs."""

from __future__ import annotations

import click

from pim.model.numbers import InputError
from pim_cli.main import (
    OPTION_NAMES,
    Beta,
    FiniteFloat,
    allow_inadmissible_option,
    allow_inconsistent_option,
    case_argument,
    check_answer,
    echo_json,
    findings_json,
    finish_answer,
    finish_evidence,
    json_option,
    load_case_for,
    output_units,
    say_contradiction,
    units_option,
)

__all__ = ["fit", "sensitivity", "plot"]

include_yaw_option = click.option(
    "--include-yaw/--no-yaw", "include_yaw", default=None,
    help="Fit every measured yaw rate (--include-yaw) or none (--no-yaw), each weighted by "
         "its vehicle's radius of gyration. Default: those with a yaw_rate_sigma in "
         "[measured], as every measured quantity with a sigma is fitted.")
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
    from pim.analysis.free_inputs import FREE_KEYS, free_kind
    from pim.io.units import parse

    out = {}
    for item in items:
        key, text = _key_value(item, FREE_KEYS, "--free", 'KEY="LO,HI"')
        parts = [t.strip() for t in text.strip().strip('"').split(",")]
        if len(parts) != 2:
            raise InputError(f"--free {key}: give two bounds separated by a comma, got {text!r}")
        kind = free_kind(key)
        out[key] = tuple(parse(t, kind, f"--free {key}") for t in parts)
    return out


def _fit(case, include_yaw, eps, beta, eps_range, beta_range, free=None, mu_c=None):
    from pim.analysis.fitting import fit as fit_case

    return fit_case(case, include_yaw=include_yaw, bounds=(eps_range, beta_range),
                    eps=eps, beta=beta, free=free or None, mu_c=mu_c)


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
@allow_inconsistent_option
@json_option
def fit(case_name, include_yaw, eps, beta, k, mu_c, eps_range, beta_range, free, units,
        speed_unit, allow_inadmissible, allow_inconsistent, as_json):
    """Fit the impact law's parameters (Brach's epsilon and beta, or k and mu_c) to CASE's
    measured post-impact motion.

    Least squares: Brach's (epsilon, beta), or under the case's law "kudlich-slibar" its
    (k, mu_c).

    Searches the whole box with a Sobol sample, then refines the best minima, so it finds
    the global optimum. --eps or --beta (--k or --mu-c) fits the other parameter alone;
    --free adds any other input, and the output then says whether the data determine them
    all (rank, families of equally good fits, under-determined, a mu_c that only has a
    lower bound). Exit code 1 after the output when the fitted answer is inadmissible (the
    reasons first; --allow-inadmissible: exit 0), e.g. beta > 1 with a --beta-range beyond 1,
    and when the measured evidence contradicts itself, its chi-square's p below 0.001 (the
    reason first; --allow-inconsistent or --allow-inadmissible: exit 0).
    """

    from comparisons.report.fit import fit_json, fit_lines, fit_values_json
    from pim.model.law import fit_restitution

    case = load_case_for("fit", case_name)
    units = output_units(case, units, speed_unit)
    restitution = fit_restitution(case, eps, k, names=OPTION_NAMES)
    result = _fit(case, include_yaw, restitution, beta, eps_range, beta_range,
                  parse_free(free), mu_c)
    accept = allow_inadmissible or allow_inconsistent
    say_contradiction(result.contradiction, accept)
    found = check_answer(result.case, result.result, units, allow=allow_inadmissible,
                         as_json=as_json)
    if as_json:
        echo_json(fit_json(result, units) | findings_json(found)
                  | fit_values_json(result, units, bool(free)))
    else:
        for line in fit_lines(case.name, result, units, bool(free)):
            click.echo(line)
    finish_answer(found, allow_inadmissible)
    finish_evidence(result.contradiction, accept)


def _parse_sigma(items):
    """``--sigma KEY=VALUE`` options -> (TypicalUncertainty, the keys given)."""
    from pim.analysis.sensitivity import TYPICAL_KINDS as kinds
    from pim.analysis.sensitivity import TypicalUncertainty
    from pim.io.units import parse

    out = {}
    for item in items:
        key, value = _key_value(item, kinds, "--sigma", "KEY=VALUE")
        out[key] = parse(value.strip(), kinds[key], f"--sigma {key}")
    return TypicalUncertainty(**out), tuple(out)


@click.command()
@case_argument
@include_yaw_option
@click.option("--eps", type=FiniteFloat(), default=None,
              help="Evaluate delta-V at this epsilon instead of fitting.")
@click.option("--beta", type=Beta(), default=None,
              help="Evaluate delta-V at this beta instead of fitting.")
@click.option("--sigma", "sigmas", multiple=True, metavar="KEY=VALUE",
              help="Set an uncertainty for this run, over the case's own, e.g. --sigma "
                   "point='0.2 m' --sigma normal_angle='3 deg' --sigma mass_fraction=0.05. "
                   "Keys: point, normal_angle, mass_fraction, inertia_fraction, velocity, "
                   "yaw_rate, measured_velocity, measured_yaw_rate.")
@click.option("--top", type=click.IntRange(min=1), default=None,
              help="Show only the N largest effects.")
@units_option
@allow_inadmissible_option
@allow_inconsistent_option
@json_option
def sensitivity(case_name, include_yaw, eps, beta, sigmas, top, units, speed_unit,
                allow_inadmissible, allow_inconsistent, as_json):
    """Rank CASE's uncertain inputs by how much they move the fitted (epsilon, beta) and
    delta-V.

    For each answer, the inputs are ranked by the change that one uncertainty (sigma) of
    the input causes; the derivative per unit is shown too. Each sigma is the case's own
    where it states one ([uncertainty], [measured] sigmas, an estimate's scatter), else a
    typical value; the source column says which (--sigma sets one over both). Exit code 1
    after the output when the answer at (epsilon, beta) is inadmissible (the reasons first;
    --allow-inadmissible: exit 0), and when the measured evidence the fit uses
    contradicts itself, its chi-square's p below 0.001 (the reason first;
    --allow-inconsistent or --allow-inadmissible: exit 0).
    """
    from comparisons.report.sensitivity import sensitivity_json, sensitivity_lines
    from pim.analysis.sensitivity import sensitivity as compute
    from pim.model.solver import solve

    case = load_case_for("sensitivity", case_name)
    units = output_units(case, units, speed_unit)
    typical, given = _parse_sigma(sigmas)
    sens = compute(case, eps=eps, beta=beta, uncertainty=typical, include_yaw=include_yaw,
                   prefer=given)
    accept = allow_inadmissible or allow_inconsistent
    reason = sens.fit.contradiction if sens.fit is not None else None
    say_contradiction(reason, accept)
    found = check_answer(case, solve(case, sens.eps, sens.beta), units,
                         allow=allow_inadmissible, as_json=as_json)
    if as_json:
        echo_json(sensitivity_json(sens, units) | findings_json(found))
    else:
        for line in sensitivity_lines(case.name, sens, units, top):
            click.echo(line)
    finish_answer(found, allow_inadmissible)
    finish_evidence(reason, accept)


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
@allow_inconsistent_option
def plot(case_name, out_dir, formats, include_yaw, eps_range, beta_range, units, speed_unit,
         allow_inadmissible, allow_inconsistent):
    """Draw the design sheet's graphs for CASE into --out (PNG and SVG).

    Cost vs epsilon, impulse ratio, impulse on vehicle 2, PDOF, energy loss, post-impact
    velocities with the measured values, and the cost map over (epsilon, beta). Exit code 1
    after writing when the fitted answer is inadmissible (the reasons first;
    --allow-inadmissible: exit 0), and when the measured evidence contradicts itself, its
    chi-square's p below 0.001 (the reason first; --allow-inconsistent or
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
    reason = result.contradiction if result else None
    accept = allow_inadmissible or allow_inconsistent
    say_contradiction(reason, accept)
    found = check_answer(result.case if result else case, result.result if result else None,
                         units, allow=allow_inadmissible)
    with output_folder(out_dir, command="pim plot") as tmp:
        files = write_plots(case, result, tmp, formats=formats, units=units)
    for path in rebase(files, tmp, out_dir):
        click.echo(str(path))
    finish_answer(found, allow_inadmissible)
    finish_evidence(reason, accept)
