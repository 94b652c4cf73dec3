"""``pim uncertainty``: Monte Carlo percentiles and variance-based sensitivity of a case."""

from __future__ import annotations

import math

import click

from pim.model.numbers import InputError
from pim_cli.main import (
    SEED,
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
    say_findings,
    units_option,
)

__all__ = ["uncertainty", "SampleCount"]


class SampleCount(click.ParamType):
    """A whole number of samples >= 10, written as an integer or in exponent form (1e8)."""

    name = "integer"

    def convert(self, value, param, ctx):
        text = str(value).strip().replace("_", "")
        try:
            x = float(text)
        except ValueError:
            self.fail(f"{value!r} is not a number of samples", param, ctx)
        if not math.isfinite(x) or x != int(x):
            self.fail(f"{value!r} is not a whole number of samples", param, ctx)
        n = int(text) if text.lstrip("+").isdigit() else int(x)
        if n < 10:
            self.fail(f"{value!r}: samples must be >= 10", param, ctx)
        return n


@click.command()
@case_argument
@click.option("--samples", "-n", type=SampleCount(), default=100_000, show_default=True,
              help="Number of Monte Carlo samples (e.g. 100000 or 1e8; over 524288 they are "
                   "solved chunk by chunk on bounded memory).")
@click.option("--seed", type=SEED, default=0, show_default=True, help="Random seed.")
@click.option("--eps", type=FiniteFloat(), default=None,
              help="Nominal epsilon (default: the case's).")
@click.option("--beta", type=Beta(), default=None,
              help="Nominal beta (default: the case's).")
@click.option("--png", "png", type=click.Path(dir_okay=False), default=None,
              help="Write histograms of the outputs to this PNG (or .svg) file.")
@click.option("--top", type=click.IntRange(min=1), default=3, show_default=True,
              help="Inputs listed per output in the sensitivity ranking.")
@click.option("--progress/--no-progress", default=None,
              help="Progress bar on stderr (default: only on a terminal).")
@units_option
@allow_inadmissible_option
@json_option
def uncertainty(case_name, samples, seed, eps, beta, png, top, progress, units, speed_unit,
                allow_inadmissible, as_json):
    """Propagate CASE's [uncertainty] table by Monte Carlo: the 5/50/95 % of each result and
    the inputs that drive its spread.

    The scatter of the inputs pim estimated (e.g. a missing yaw inertia) is drawn too.
    Contributions are first-order variance-based (Sobol) indices: the share of an output's
    variance explained by one input alone. Samples whose impact is inadmissible are left
    out of both (their share and reasons are printed first). Exit code 1 after the output
    when the nominal answer is inadmissible or no sample is admissible (--allow-inadmissible:
    exit 0).
    """
    from tqdm import tqdm

    from comparisons.report.uncertainty import (
        uncertainty_json,
        uncertainty_lines,
        uncertainty_rows,
    )
    from pim.analysis.montecarlo import memory_shortfall
    from pim.analysis.montecarlo import uncertainty as run

    case = load_case_for("uncertainty", case_name)
    units = output_units(case, units, speed_unit)
    shortfall = memory_shortfall(samples)
    if shortfall is not None:
        raise InputError(f"--samples {samples:,} {shortfall}")
    with tqdm(total=samples, unit="sample", unit_scale=True, desc="Monte Carlo", leave=False,
              disable=None if progress is None else not progress) as bar:
        result = run(case, n=samples, seed=seed, eps=eps, beta=beta, progress=bar.update)
    rows = uncertainty_rows(case, result, units)
    if png:
        from pim.plotting.histograms import write_histograms

        write_histograms(result, png, units)
    found = _mc_findings(case, result, eps, beta, units, allow_inadmissible, as_json)
    if as_json:
        echo_json(uncertainty_json(case, result, rows, units, seed=seed,
                                   findings=findings_json(found)))
    else:
        for line in uncertainty_lines(case.name, result, rows, seed=seed, top=top):
            click.echo(line)
        if png:
            click.echo(f"histograms: {png}")
    finish_answer(found, allow_inadmissible)


def _mc_findings(case, result, eps, beta, units, allow, as_json):
    """The nominal answer's findings (printed), after one line on the share of inadmissible
    samples and how they were treated, and one per reason with its count; no admissible
    sample at all is an error."""
    from comparisons.report.uncertainty import inadmissible_note, no_admissible_error
    from pim.model.solver import solve

    for line in inadmissible_note(result):
        click.echo(line, err=True)
    found = check_answer(case, solve(case, eps, beta), units, allow=allow, as_json=as_json)
    error = no_admissible_error(result)
    if error is not None:
        found.errors.append(error)
        say_findings(type(found)(found.errors[-1:], []), allow)
    return found
