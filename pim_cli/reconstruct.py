"""``pim reconstruct CASE --out DIR``: evidence -> post-impact motion -> impact speeds.

The chain of :func:`pim.analysis.reconstruction.reconstruct`: the run-out inverse of each
vehicle with ``[evidence]`` (or the case's ``[measured]`` post-impact motion), the inverse PIM
for the ``[unknown]`` table, the linear-momentum check beside it, and a Monte Carlo over the
stated uncertainties (``--samples``) for each unknown's 5/50/95 % and its driving inputs.
Prints the table in the case's units, speeds in km/h (SI) or mph (US) as the field reports
them (``--units``, ``--speed-unit`` or the case file's ``[units]`` to change); ``--json``
prints each unknown by its dotted name with its value, percentiles and unit in the same
units (``units`` names the unit of each kind of quantity), and the momentum check beside
them. Writes DIR/report.md, DIR/report.html
(the same as one self-contained page, figure and video inline),
DIR/reconstruction.csv and, with run-out evidence (``[evidence]`` rest positions),
DIR/scene.png and DIR/reconstruction.mp4 (the reconstructed crash from the impact to rest).

When the data cannot decide the unknowns, one line says what is missing and the exit code
is 2: never a number. The inverse PIM applies the case's impact law (``impact.law``: Brach's
(eps, beta), the friction-capped Brach law, or Kudlich-Slibar's (k, mu_c) with
``impact.k`` / ``impact.mu_c`` in ``[unknown]``); the output names it, and a contact
friction the contact does not reach is given as the lower bound it is (">= X").
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import click

from comparisons.report.document import Figure, Video
from comparisons.report.pre_impact import pre_impact_json, pre_impact_lines, pre_impact_rows
from comparisons.report.reconstruct import (
    ReconstructionRows,
    crush_lines,
    driver_lines,
    evidence_drivers,
    law_line,
    reconstruction_document,
    reconstruction_rows,
    tyre_models_line,
)
from comparisons.report.write import write_document
from pim.analysis.pre_impact_speeds import reconstruction_pre_impact
from pim.analysis.reconstruction import Reconstruction
from pim.analysis.reconstruction import reconstruct as run_reconstruction
from pim.io.files import save_figure
from pim.io.inertia_data import estimate_records
from pim.io.output import output_folder
from pim.io.process import worker_pool
from pim.io.units import convert, display_units
from pim.model.numbers import InputError
from pim.model.plausibility import secondary_contact
from pim.plotting.reconstruction_animation import frame_states, write_reconstruction_mp4
from pim.plotting.reconstruction_scene import reconstruction_figure
from pim_cli.main import (
    SEED,
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

__all__ = ["reconstruct", "reconstruction_rows", "law_line", "evidence_drivers",
           "driver_lines", "budget", "DEFAULT_MAX_MINUTES", "runout_contact", "spread_text"]

#: Default of --max-minutes: the longest Monte Carlo with run-out evidence run without
#: being asked [min].
DEFAULT_MAX_MINUTES = 30.0


def spread_text(row, samples: int, sep: str = ", ") -> str:
    """"[p5, p50, p95]" of an unknown's row, or why there is none (never "[nan, nan, nan]")."""
    if not samples:
        return "(5/50/95 %: not computed, --samples 0)"
    if not row.has_spread:
        return "(5/50/95 %: no usable Monte Carlo sample)"
    return f"[{row.p5:.4g}{sep}{row.p50:.4g}{sep}{row.p95:.4g}]"


def _lines(rows: ReconstructionRows, samples: int) -> list[str]:
    """The table as text lines: each unknown, then the momentum check."""
    lines = [f"{r.name:32s} {(('>= ' if r.lower_bound else '') + f'{r.value:.4g}'):>10s} "
             f"{r.unit}  {spread_text(r, samples)}" for r in rows.unknowns]
    lines += [f"{'momentum check: ' + m.name:32s} {m.value:>10.4g} {m.unit}  "
              f"(1 sd = {m.sd:.3g} {m.unit})" for m in rows.momentum]
    return lines


def _json(case, rows: ReconstructionRows, samples: int, messages, units) -> dict:
    """``--json``'s data: every value in ``units`` with its unit (NaN becomes null)."""
    return {"case": case.name, "units": display_units(units).to_json(), "samples": samples,
            "messages": messages, "estimates": estimate_records(case, units),
            "unknowns": {r.name: {"unit": r.unit, "value": r.value, "p5": r.p5,
                                  "p50": r.p50, "p95": r.p95, "lower_bound": r.lower_bound}
                         for r in rows.unknowns},
            "momentum_check": {m.name: {"unit": m.unit, "value": m.value, "sd": m.sd}
                               for m in rows.momentum}}


@click.command()
@case_argument
@click.option("--out", "out", type=click.Path(file_okay=False), default=None,
              help="Directory for report.md, report.html and reconstruction.csv; with "
                   "run-out evidence ([evidence] rest positions) also scene.png and "
                   "reconstruction.mp4.")
@click.option("--samples", type=click.IntRange(min=0), default=10_000, show_default=True,
              help="Monte Carlo samples over the stated uncertainties (0: none).")
@click.option("--seed", type=SEED, default=0, show_default=True, help="Monte Carlo seed.")
@click.option("--workers", type=click.IntRange(min=1), default=1, show_default=True,
              help="Spread the Monte Carlo over this many processes (1: this process, "
                   "which already uses every core for the run-outs).")
@click.option("--video/--no-video", default=True, show_default=True,
              help="With run-out evidence, also write DIR/reconstruction.mp4 (impact to "
                   "rest).")
@click.option("--progress/--no-progress", default=None,
              help="Progress of the stages on stderr (default: only on a terminal).")
@click.option("--max-minutes", type=FiniteFloat(0.0, None, "min"), default=DEFAULT_MAX_MINUTES,
              show_default=True,
              help="With run-out evidence every Monte Carlo sample refits the run-outs: the "
                   "Monte Carlo's time is measured on a pilot before it starts, said on "
                   "stderr when over 10 s, and refused (exit 2, with the sample count that "
                   "fits) when over this.")
@units_option
@allow_inadmissible_option
@json_option
def reconstruct(case_name, out, samples, seed, workers, video, progress, max_minutes, units,
                speed_unit, allow_inadmissible, as_json):
    """Reconstruct CASE's unknowns, such as the impact speeds, from its evidence.

    With --out DIR: DIR/report.md, DIR/report.html and DIR/reconstruction.csv; a case
    with run-out evidence ([evidence] rest positions) adds DIR/scene.png (the run-outs
    drawn) and DIR/reconstruction.mp4 (unless --no-video).

    With --out the folder is written whole at the end (or not at all: an error or an
    interrupt leaves an earlier run there as it was); its lock is taken before the work.
    Exit code 1 after the output when the reconstructed answer is inadmissible (the
    reasons first; --allow-inadmissible: exit 0).
    """
    case = load_case_for("reconstruct", case_name)
    units = output_units(case, units, speed_unit)
    with output_folder(out, command="pim reconstruct") if out else \
            contextlib.nullcontext() as tmp:
        with _stages(case, samples, workers, progress) as say:
            rec, rows, pre, found = _reconstruct(
                case, samples, seed, workers, units, as_json, say=say,
                estimate=budget(samples, workers, max_minutes), allow=allow_inadmissible)
        if tmp is not None:
            _write_folder(tmp, rec, rows, units, video, pre)
    if out and not as_json:
        click.echo(f"wrote {Path(out) / 'report.html'} (and report.md)")
    finish_answer(found, allow_inadmissible)


@contextlib.contextmanager
def _stages(case, samples: int, workers: int, progress):
    """A tqdm bar over the reconstruction's stages (run-out fits, inverse PIM, Monte Carlo
    and its blocks); yields the callback that moves it."""
    from tqdm import tqdm

    has_evidence = case.evidence is not None and (case.evidence.vehicle1 is not None
                                                   or case.evidence.vehicle2 is not None)
    total = int(has_evidence) + 1 + (0 if not samples else 1 if workers == 1 else
                                     1 + 2 * workers)
    with tqdm(total=total, desc="pim reconstruct", unit="stage", leave=False,
              disable=None if progress is None else not progress) as bar:
        def say(stage: str) -> None:
            if bar.n < bar.total:
                bar.update(1)
            bar.set_postfix_str(stage)
        yield say


def budget(samples: int, workers: int, max_minutes: float):
    """The ``estimate`` callback of :func:`pim.analysis.reconstruction.reconstruct`: says the
    Monte Carlo's estimated time on stderr when over 10 s, refuses it (InputError naming
    --max-minutes and the --samples that fit) when over ``max_minutes``."""
    def check(seconds: float) -> None:
        seconds /= workers
        if seconds > 60.0 * max_minutes:
            fit = int(samples * 60.0 * max_minutes / seconds)
            raise InputError(f"--max-minutes {max_minutes:g}: the Monte Carlo of {samples} "
                             f"samples refits the run-outs of each sample, about "
                             f"{_duration(seconds)} here; give --samples {fit} or fewer, or "
                             f"raise --max-minutes")
        if seconds > 10.0:
            click.echo(f"note: Monte Carlo: {samples} samples, each refitting the run-outs: "
                       f"about {_duration(seconds)}", err=True)
    return check


def _duration(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 120 else (
        f"{seconds / 60:.0f} min" if seconds < 7200 else f"{seconds / 3600:.1f} h")


def _reconstruct(case, samples, seed, workers, units, as_json, *, say=None, estimate=None,
                 allow=False):
    """Run the reconstruction and print its table (or JSON) after what is wrong or doubtful
    about its answer; return it, its rows, the rows of the speeds before the impact
    (:mod:`comparisons.report.pre_impact`) and those findings."""
    if workers > 1:
        with worker_pool(workers) as pool:
            rec = run_reconstruction(case, samples=samples, seed=seed, executor=pool,
                                     blocks=2 * workers, progress=say, estimate=estimate)
    else:
        rec = run_reconstruction(case, samples=samples, seed=seed, progress=say,
                                 estimate=estimate)
    if not rec.determined:
        raise InputError(next((m for m in rec.messages if "under-determined" in m
                               or "family" in m or "equally well" in m),
                              "; ".join(rec.messages)))
    rows = reconstruction_rows(rec, units)
    pre = pre_impact_rows(reconstruction_pre_impact(rec, seed), units)
    found = check_answer(rec.fit.case, rec.fit.result, units, allow=allow, as_json=as_json)
    contact = runout_contact(rec, units)
    if contact is not None and not as_json:
        click.echo(f"note: {contact['message']}", err=True)
    if as_json:
        data = _json(case, rows, samples, rec.messages, units) | findings_json(found)
        data["secondary_impact"] = contact
        data["pre_impact"] = pre_impact_json(pre)
        data["tyre_models"] = ({f"vehicle{i}": fit.tyre_model for i, fit in
                                rec.post.runouts.items()} if rec.post else {})
        data["goodness_of_fit"] = rec.goodness.to_dict() if rec.goodness else None
        data["evidence_drivers"] = evidence_drivers(rec, units)
        data["crush"] = _crush_json(rec, units)
        data["law"] = rec.fit.law
        echo_json(data)
    else:
        click.echo(law_line(rec))
        if rec.post is not None:
            click.echo(tyre_models_line(rec))
        for message in rec.messages:        # before the table, where a reader sees them
            click.echo(f"warning: {message}")
        for line in _lines(rows, samples) + pre_impact_lines(pre):
            click.echo(line)
        for line in crush_lines(rec, units):
            click.echo(f"crush: {line}")
        for line in driver_lines(evidence_drivers(rec, units)):
            click.echo(f"evidence: {line}")
        if rec.goodness is not None:
            click.echo(f"goodness of fit: {rec.goodness.summary()}")
    if contact is not None:
        rec.messages.append(contact["message"])         # into the report too
    return rec, rows, pre, found


def runout_contact(rec: Reconstruction, units: str) -> dict | None:
    """Where the two fitted run-outs (those the animation plays) run into each other again
    after the impact (:func:`pim.model.plausibility.secondary_contact`): time [s], place
    (x, y) in ``units`` and the message; None without both run-outs and outlines, or when
    they do not."""
    post = rec.post
    if post is None or set(post.runouts) != {1, 2}:
        return None
    frames = frame_states(post, fps=100, hold=0.0)
    hit = secondary_contact(frames.times, frames.states[1], frames.states[2],
                            rec.case.vehicle1, rec.case.vehicle2)
    if hit is None:
        return None
    time, point = hit
    (x, y), unit = convert(point, "length", units)
    return {"time": time, "x": float(x), "y": float(y), "length_unit": unit,
            "message": f"secondary impact at t = {time:.2f} s after the impact at (x, y) = "
                       f"({x:.4g} {unit}, {y:.4g} {unit}): the two fitted run-outs run into "
                       f"each other again, a second impact the run-out model leaves out (the "
                       f"motion after it, and the speeds fitted to the rest positions through "
                       f"it, are not reliable)"}


def _crush_json(rec: Reconstruction, units: str) -> dict:
    """``--json``'s crush outputs per vehicle, each value with its unit in ``units``."""
    out = {}
    for c in rec.crush:
        (e, sd), e_unit = convert([c.energy, c.energy_sigma], "energy", units)
        (ees, dv, dvm), v_unit = convert([c.ees, c.delta_v_crush, c.delta_v_model],
                                         "impact_speed", units)
        out[f"vehicle{c.vehicle}"] = {
            "energy": {"value": float(e), "sd": float(sd), "unit": e_unit},
            "force_balance_factor": c.factor,
            "ees": {"value": float(ees), "unit": v_unit},
            "delta_v_crush": {"value": float(dv), "unit": v_unit},
            "delta_v_model": {"value": float(dvm), "unit": v_unit}}
    return out


def _write_folder(directory: Path, rec, rows, units: str, video: bool, pre=()) -> None:
    """scene.png, reconstruction.mp4 (with evidence), the CSVs, report.html and report.md
    (through the one report pipeline) into ``directory``."""
    media = []
    if rec.post is not None:
        save_figure(reconstruction_figure(rec.post, units), directory / "scene.png")
        media.append(Figure("scene.png", alt="scene", caption="The reconstructed scene."))
        if video:
            write_reconstruction_mp4(rec.post, directory / "reconstruction.mp4", units=units)
            media.append(Video("reconstruction.mp4", "From the impact to rest."))
    write_document(reconstruction_document(rec, rows, units, pre, tuple(media)), directory)
