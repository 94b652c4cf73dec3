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

    from pim.analysis.montecarlo import OUTPUTS, available_memory, memory_estimate
    from pim.analysis.montecarlo import uncertainty as run
    from pim.io.inertia_data import estimate_records
    from pim.io.units import convert
    from pim.model.quantities import OUTPUTS as QUANTITIES

    case = load_case_for("uncertainty", case_name)
    units = output_units(case, units, speed_unit)
    need, free = memory_estimate(samples), available_memory()
    if free is not None and need > free:
        raise InputError(f"--samples {samples:,} needs about {need / 2**30:.1f} GiB of memory "
                         f"and {free / 2**30:.1f} GiB are available")
    with tqdm(total=samples, unit="sample", unit_scale=True, desc="Monte Carlo", leave=False,
              disable=None if progress is None else not progress) as bar:
        result = run(case, n=samples, seed=seed, eps=eps, beta=beta, progress=bar.update)
    rows = []
    barrier = bool(case.vehicle2.fixed)
    for name in OUTPUTS:
        if barrier and name in ("pdof2", "delta_v2_magnitude", "speed2", "yaw_rate2"):
            continue        # a fixed obstacle does not move and has no PDOF
        label, kind = QUANTITIES[name].label, QUANTITIES[name].kind
        s = result.stats[name]
        values, unit = convert([s.nominal, s.p5, s.p50, s.p95], kind, units)
        rows.append({"output": name, "label": label, "unit": unit,
                     "nominal": float(values[0]), "p5": float(values[1]),
                     "p50": float(values[2]), "p95": float(values[3]),
                     "sensitivity": [{"input": k, "first_order": round(v, 4)}
                                     for k, v in result.sensitivity[name]]})
    if png:
        from pim.plotting.histograms import write_histograms

        write_histograms(result, png, units)
    found = _mc_findings(case, result, eps, beta, units, allow_inadmissible, as_json)
    if as_json:
        echo_json({"case": case.name, "samples": result.n, "seed": seed,
                   "units": units.to_json(), "estimates": estimate_records(case, units),
                   **findings_json(found), "samples_admissible": result.n_admissible,
                   "samples_inadmissible": result.n - result.n_admissible,
                   "inadmissible_samples": "left out of the percentiles and indices",
                   "sample_problems": result.problems, "outputs": rows})
    else:
        _print_table(case, result, seed, rows, top, png)
    finish_answer(found, allow_inadmissible)


def _mc_findings(case, result, eps, beta, units, allow, as_json):
    """The nominal answer's findings (printed), after one line on the share of inadmissible
    samples and how they were treated, and one per reason with its count; no admissible
    sample at all is an error."""
    from pim.model.solver import solve

    bad = result.n - result.n_admissible
    if bad:
        click.echo(f"note: {bad:,} of {result.n:,} samples ({100 * bad / result.n:.3g} %) are "
                   f"inadmissible impacts, left out of the percentiles and the indices (those "
                   f"describe the admissible impacts); why:", err=True)
        for text in result.problems:
            click.echo(f"warning: samples: {text}", err=True)
    found = check_answer(case, solve(case, eps, beta), units, allow=allow, as_json=as_json)
    if result.n_admissible == 0:
        found.errors.append(f"no sample of {result.n:,} is an admissible impact: no statistics")
        say_findings(type(found)(found.errors[-1:], []), allow)
    return found


def _print_table(case, result, seed, rows, top, png) -> None:
    """``pim uncertainty``'s table."""
    click.echo(f"{case.name}: {result.n:,} samples (seed {seed}), "
               f"{result.n_admissible:,} admissible")
    width = max(len(r["label"]) for r in rows)
    click.echo(f"{'output':<{width}}  {'unit':>6}  {'nominal':>10}  {'5 %':>10}  {'50 %':>10}  "
               f"{'95 %':>10}  main contributions (first-order index)")
    for r in rows:
        contrib = ", ".join(f"{c['input']} {c['first_order']:.2f}"
                            for c in r["sensitivity"][:top])
        click.echo(f"{r['label']:<{width}}  {r['unit']:>6}  {r['nominal']:>10.4g}  "
                   f"{r['p5']:>10.4g}  {r['p50']:>10.4g}  {r['p95']:>10.4g}  {contrib}")
    if png:
        click.echo(f"histograms: {png}")
