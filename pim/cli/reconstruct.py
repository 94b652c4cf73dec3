"""``pim reconstruct CASE --out DIR``: evidence -> post-impact motion -> impact speeds.

The chain of :func:`pim.analysis.reconstruction.reconstruct`: the run-out inverse of each
vehicle with ``[evidence]`` (or the case's ``[measured]`` post-impact motion), the inverse PIM
for the ``[unknown]`` table, the linear-momentum check beside it, and a Monte Carlo over the
stated uncertainties (``--samples``) for each unknown's 5/50/95 % and its driving inputs.
Prints the table in the case's units (``--units`` to change; speeds in mph in US units, the
customary unit of impact speeds); ``--json`` prints each unknown
by its dotted name with its value and percentiles in SI. Writes DIR/report.md,
DIR/reconstruction.csv and, with evidence, DIR/scene.png and DIR/reconstruction.mp4 (the
reconstructed crash from the impact to rest).

When the data cannot decide the unknowns, one line says what is missing and the exit code
is 2: never a number.
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import click

from ..analysis.reconstruction import Reconstruction
from ..analysis.reconstruction import reconstruct as run_reconstruction
from ..io.casefile import load_case
from ..io.files import save_figure, write_text
from ..io.units import convert
from ..model.evidence import UNKNOWN_KINDS
from ..plotting.reconstruction_animation import write_reconstruction_mp4
from ..plotting.reconstruction_scene import reconstruction_figure
from .main import case_argument, echo_json, json_option, units_option

__all__ = ["reconstruct", "reconstruction_rows"]


def reconstruction_rows(rec: Reconstruction, units: str) -> list[dict]:
    """Table rows in ``units``: name, unit, value, p5, p50, p95, main driver."""
    rows = []
    for r in rec.table():
        kind = ("impact_speed" if r["name"].endswith(".speed")
                else UNKNOWN_KINDS.get(r["name"], "dimensionless"))
        values, unit = convert([r["value"], r["p5"], r["p50"], r["p95"]], kind, units)
        driver = r["drivers"][0] if r["drivers"] else ("", float("nan"))
        rows.append({"name": r["name"], "unit": unit, "value": float(values[0]),
                     "p5": float(values[1]), "p50": float(values[2]), "p95": float(values[3]),
                     "driver": driver[0], "driver_index": float(driver[1])})
    if rec.momentum is not None:
        m = rec.momentum
        for i, (s, sd) in enumerate(((m.speed1, m.sigma1), (m.speed2, m.sigma2)), start=1):
            values, unit = convert([s, sd], "impact_speed", units)
            rows.append({"name": f"momentum check: vehicle{i}.speed", "unit": unit,
                         "value": float(values[0]), "p5": float("nan"), "p50": float("nan"),
                         "p95": float("nan"), "driver": f"1 sd = {float(values[1]):.3g} {unit}",
                         "driver_index": float("nan")})
    return rows


def tyre_models_line(rec: Reconstruction) -> str:
    """Which tyre law each vehicle's run-out used (one line for the report and the CLI)."""
    return "Run-out tyre model: " + ", ".join(
        f"vehicle {i} {fit.tyre_model}" for i, fit in sorted(rec.post.runouts.items())) + "."


def _report(rec: Reconstruction, rows: list[dict], units: str, with_scene: bool,
            with_video: bool = False) -> str:
    n = rec.samples.n if rec.samples else 0
    source = ("the run-out inverse of each vehicle's rest evidence" if rec.post else
              "the case's [measured] post-impact motion")
    lines = [f"# Reconstruction of {rec.case.name}", "",
             f"Post-impact motion from {source}; unknowns by the inverse PIM (least squares "
             f"over the measured velocities and yaw rates, exact derivatives); "
             + (f"5/50/95 % from a Monte Carlo of {n} samples over the stated uncertainties "
                f"({rec.samples.n_used} used)." if n else "no Monte Carlo (--samples 0)."),
             ""] + ([tyre_models_line(rec), ""] if rec.post else []) + [
             "| unknown | value | 5 % | 50 % | 95 % | unit | main driver of the spread |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        driver = (f"{r['driver']} ({r['driver_index']:.2f})" if r["driver_index"] == r[
            "driver_index"] else r["driver"])
        lines.append(f"| {r['name']} | {r['value']:.4g} | {r['p5']:.4g} | {r['p50']:.4g} | "
                     f"{r['p95']:.4g} | {r['unit']} | {driver} |")
    lines.append("")
    if rec.samples:
        lines += ["## What drives each unknown's spread", "",
                  "First-order variance indices (correlation ratio) of the sampled inputs.", ""]
        for r in rec.table():
            top = ", ".join(f"{k} {v:.2f}" for k, v in r["drivers"][:4] if v > 0.005)
            lines.append(f"- {r['name']}: {top or 'no single input dominates'}")
        lines.append("")
    if rec.goodness is not None:
        lines += [f"Goodness of fit: {rec.goodness.summary()}.", ""]
    lines += [f"- {m}" for m in rec.messages] or ["No warnings."]
    if with_scene:
        lines += ["", "![scene](scene.png)"]
    if with_scene and with_video:
        lines += ["", "Animation from the impact to rest: [reconstruction.mp4](reconstruction.mp4)"]
    return "\n".join(lines) + "\n"


@click.command()
@case_argument
@click.option("--out", "out", type=click.Path(file_okay=False), default=None,
              help="Directory for report.md, reconstruction.csv and scene.png.")
@click.option("--samples", type=click.IntRange(min=0), default=10_000, show_default=True,
              help="Monte Carlo samples over the stated uncertainties (0: none).")
@click.option("--seed", type=int, default=0, show_default=True, help="Monte Carlo seed.")
@click.option("--workers", type=click.IntRange(min=1), default=1, show_default=True,
              help="Spread the Monte Carlo over this many processes (1: this process, "
                   "which already uses every core for the run-outs).")
@click.option("--video/--no-video", default=True, show_default=True,
              help="With evidence, also write DIR/reconstruction.mp4 (impact to rest).")
@units_option
@json_option
def reconstruct(case_name, out, samples, seed, workers, video, units, as_json):
    """Reconstruct CASE's unknowns (e.g. the impact speeds) from its evidence."""
    case = load_case(case_name)
    units = units or case.units
    if workers > 1:
        with ProcessPoolExecutor(workers) as pool:
            rec = run_reconstruction(case, samples=samples, seed=seed, executor=pool,
                                     blocks=2 * workers)
    else:
        rec = run_reconstruction(case, samples=samples, seed=seed)
    if not rec.determined:
        raise ValueError(next((m for m in rec.messages if "under-determined" in m
                               or "family" in m or "equally well" in m),
                              "; ".join(rec.messages)))
    rows = reconstruction_rows(rec, units)
    if as_json:
        echo_json({"case": case.name, "units": "si", "samples": samples,
                   "messages": rec.messages,
                   "tyre_models": ({f"vehicle{i}": fit.tyre_model for i, fit in
                                    rec.post.runouts.items()} if rec.post else {}),
                   "goodness_of_fit": rec.goodness.to_dict() if rec.goodness else None,
                   "unknowns": {r["name"]: {k: r[k] for k in ("value", "p5", "p50", "p95")}
                                for r in rec.table()}})
    else:
        if rec.post is not None:
            click.echo(tyre_models_line(rec))
        for r in rows:
            click.echo(f"{r['name']:32s} {r['value']:10.4g}  [{r['p5']:.4g}, {r['p50']:.4g}, "
                       f"{r['p95']:.4g}] {r['unit']}")
        if rec.goodness is not None:
            click.echo(f"goodness of fit: {rec.goodness.summary()}")
        for message in rec.messages:
            click.echo(f"warning: {message}")
    if out:
        directory = Path(out)
        directory.mkdir(parents=True, exist_ok=True)
        csv = ["name,unit,value,p5,p50,p95,main_driver"] + [
            f"{r['name']},{r['unit']},{r['value']:.6g},{r['p5']:.6g},{r['p50']:.6g},"
            f"{r['p95']:.6g},{r['driver']}" for r in rows]
        write_text(directory / "reconstruction.csv", "\n".join(csv) + "\n")
        if rec.post is not None:
            save_figure(reconstruction_figure(rec.post, units), directory / "scene.png")
            if video:
                write_reconstruction_mp4(rec.post, directory / "reconstruction.mp4",
                                         units=units)
        write_text(directory / "report.md",
                   _report(rec, rows, units, rec.post is not None, video))
