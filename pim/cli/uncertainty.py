"""``pim uncertainty``: Monte Carlo percentiles and variance-based sensitivity of a case."""

from __future__ import annotations

import click

from .main import FiniteFloat, case_argument, echo_json, json_option, units_option

__all__ = ["uncertainty"]


@click.command()
@case_argument
@click.option("--samples", "-n", type=click.IntRange(min=10), default=100_000,
              show_default=True, help="Number of Monte Carlo samples.")
@click.option("--seed", type=int, default=0, show_default=True, help="Random seed.")
@click.option("--eps", type=FiniteFloat(), default=None,
              help="Nominal epsilon (default: the case's).")
@click.option("--beta", type=FiniteFloat(), default=None,
              help="Nominal beta (default: the case's).")
@click.option("--png", "png", type=click.Path(dir_okay=False), default=None,
              help="Write histograms of the outputs to this PNG (or .svg) file.")
@click.option("--top", type=click.IntRange(min=1), default=3, show_default=True,
              help="Inputs listed per output in the sensitivity ranking.")
@units_option
@json_option
def uncertainty(case_name, samples, seed, eps, beta, png, top, units, as_json):
    """Monte Carlo of CASE's [uncertainty] table: 5/50/95 % and ranked input contributions.

    Contributions are first-order variance-based (Sobol) indices: the share of an output's
    variance explained by one input alone.
    """
    from ..analysis.montecarlo import OUTPUTS
    from ..analysis.montecarlo import uncertainty as run
    from ..io.casefile import load_case
    from ..io.units import convert
    from ..model.quantities import OUTPUTS as QUANTITIES

    case = load_case(case_name)
    units = units or case.units
    result = run(case, n=samples, seed=seed, eps=eps, beta=beta)
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
        from ..plotting.histograms import write_histograms

        write_histograms(result, png, units)
    if as_json:
        echo_json({"case": case.name, "samples": result.n, "seed": seed,
                   "admissible": result.n_admissible, "problems": result.problems,
                   "units": units, "outputs": rows})
        return
    for text in result.problems:        # before the table, where a reader sees them
        click.echo(f"warning: {text}; those samples are left out", err=True)
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
