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

from comparisons.animation.reconstruction import reconstruction_plan, write_reconstruction_video
from comparisons.report.document import Figure, Video
from pim.model.number_format import duration_text
from comparisons.report.pre_impact import pre_impact_rows
from comparisons.report.reconstruct import (
    reconstruction_document,
    reconstruction_json,
    reconstruction_lines,
    reconstruction_rows,
    runout_contact,
)
from comparisons.report.write import write_document
from pim.analysis.pre_impact_speeds import reconstruction_pre_impact
from pim.analysis.progress import reporting
from pim.analysis.reconstruction import MonteCarloBudget, progress_stages, worker_blocks
from pim.analysis.reconstruction import reconstruct as run_reconstruction
from pim.io.files import save_figure
from pim.io.output import output_folder
from pim.io.process import worker_pool
from pim.model.numbers import InputError
from pim_cli.main import (
    SEED,
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

__all__ = ["reconstruct", "budget", "DEFAULT_MAX_MINUTES"]

#: Default of --max-minutes: the longest Monte Carlo with run-out evidence run without
#: being asked [min].
DEFAULT_MAX_MINUTES = 30.0


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
              help="With run-out evidence every Monte Carlo sample refits the run-outs (through "
                   "the event when they re-contact): the "
                   "Monte Carlo's time is measured on a pilot before it starts, said on "
                   "stderr when over 10 s, and refused (exit 2, with the sample count that "
                   "fits) when over this.")
@units_option
@allow_inadmissible_option
@allow_inconsistent_option
@json_option
def reconstruct(case_name, out, samples, seed, workers, video, progress, max_minutes, units,
                speed_unit, allow_inadmissible, allow_inconsistent, as_json):
    """Reconstruct CASE's unknowns, such as the impact speeds, from its evidence.

    With --out DIR: DIR/report.md, DIR/report.html and DIR/reconstruction.csv; a case
    with run-out evidence ([evidence] rest positions) adds DIR/scene.png (the run-outs
    drawn) and DIR/reconstruction.mp4 (unless --no-video).

    With --out the folder is written whole at the end (or not at all: an error or an
    interrupt leaves an earlier run there as it was); its lock is taken before the work.
    Exit code 1 after the output when the reconstructed answer is inadmissible (the
    reasons first; --allow-inadmissible: exit 0), and when the evidence contradicts itself,
    its chi-square's p below 0.001 (the reason first; --allow-inconsistent or
    --allow-inadmissible: exit 0).
    """
    case = load_case_for("reconstruct", case_name)
    units = output_units(case, units, speed_unit)
    with output_folder(out, command="pim reconstruct") if out else \
            contextlib.nullcontext() as tmp:
        with _stages(case, samples, workers, progress) as say:
            rec, rows, pre, found = _reconstruct(
                case, samples, seed, workers, units, as_json, say=say,
                estimate=budget(samples, workers, max_minutes), allow=allow_inadmissible,
                accept=allow_inadmissible or allow_inconsistent)
        if tmp is not None:
            _write_folder(tmp, rec, rows, units, video, pre)
    if out and not as_json:
        click.echo(f"wrote {Path(out) / 'report.html'} (and report.md)")
    finish_answer(found, allow_inadmissible)
    finish_evidence(rec.contradiction, allow_inadmissible or allow_inconsistent)


@contextlib.contextmanager
def _stages(case, samples: int, workers: int, progress):
    """A tqdm bar over the reconstruction's stages (run-out fits, inverse PIM, Monte Carlo
    and its blocks); yields the callback that moves it."""
    from tqdm import tqdm

    with tqdm(total=progress_stages(case, samples, workers), desc="pim reconstruct", unit="stage",
              leave=False,
              disable=None if progress is None else not progress) as bar:
        def say(stage: str) -> None:
            if bar.n < bar.total:
                bar.update(1)
            bar.set_postfix_str(stage)

        def within(done: int, total: int, what: str) -> None:    # inside the Monte Carlo
            bar.set_postfix_str(f"Monte Carlo: {done}/{total} {what}")
        with reporting(within):
            yield say


def budget(samples: int, workers: int, max_minutes: float):
    """The ``estimate`` callback of :func:`pim.analysis.reconstruction.reconstruct`: says the
    Monte Carlo's estimated time on stderr when over 10 s, refuses it (InputError naming
    --max-minutes and the --samples that fit) when over ``max_minutes``
    (:class:`pim.analysis.reconstruction.MonteCarloBudget`)."""
    limit = MonteCarloBudget(samples, workers, max_minutes)

    def check(seconds: float) -> None:
        seconds = limit.wall_seconds(seconds)
        if limit.over(seconds):
            raise InputError(f"--max-minutes {max_minutes:g}: the Monte Carlo of {samples} "
                             f"samples refits the run-outs of each sample, about "
                             f"{duration_text(seconds)} here; give --samples "
                             f"{limit.affordable(seconds)} or fewer, or raise --max-minutes")
        if limit.noted(seconds):
            click.echo(f"note: Monte Carlo: {samples} samples, each refitting the run-outs: "
                       f"about {duration_text(seconds)}", err=True)
    return check


def _reconstruct(case, samples, seed, workers, units, as_json, *, say=None, estimate=None,
                 allow=False, accept=False):
    """Run the reconstruction and print its table (or JSON) after what is wrong or doubtful
    about its answer (evidence that contradicts itself as an error unless ``accept``);
    return it, its rows, the rows of the speeds before the impact
    (:mod:`comparisons.report.pre_impact`) and those findings."""
    if workers > 1:
        with worker_pool(workers) as pool:
            rec = run_reconstruction(case, samples=samples, seed=seed, executor=pool,
                                     blocks=worker_blocks(workers), progress=say,
                                     estimate=estimate)
    else:
        rec = run_reconstruction(case, samples=samples, seed=seed, progress=say,
                                 estimate=estimate)
    if not rec.determined:
        raise InputError(rec.undetermined_reason)
    rows = reconstruction_rows(rec, units)
    pre = pre_impact_rows(reconstruction_pre_impact(rec, seed), units)
    say_contradiction(rec.contradiction, accept)
    found = check_answer(rec.fit.case, rec.fit.result, units, allow=allow, as_json=as_json)
    contact = runout_contact(rec, units)
    if contact is not None and not as_json:
        click.echo(f"note: {contact['message']}", err=True)
    if as_json:
        echo_json(reconstruction_json(rec, rows, units, samples=samples, pre=pre,
                                      contact=contact, findings=findings_json(found)))
    else:
        for line in reconstruction_lines(rec, rows, units, samples=samples, pre=pre):
            click.echo(line)
    if contact is not None:
        rec.messages.append(contact["message"])         # into the report too
    return rec, rows, pre, found


def _write_folder(directory: Path, rec, rows, units: str, video: bool, pre=()) -> None:
    """scene.png, reconstruction.mp4 (with evidence), the CSVs, report.html and report.md
    (through the one report pipeline) into ``directory``."""
    media = []
    if rec.post is not None:
        save_figure(reconstruction_plan(rec.post, rec.fit.result, units),
                    directory / "scene.png")
        media.append(Figure("scene.png", alt="scene", caption="The reconstructed scene in "
                            "plan view: the fitted run-outs' outlines at the stated interval "
                            "with their times, the impact, the measured rest positions."))
        if video:
            write_reconstruction_video(rec.post, rec.fit.result, directory / "reconstruction.mp4",
                                       units=units, progress=False)
            media.append(Video("reconstruction.mp4", "From the impact to rest."))
    write_document(reconstruction_document(rec, rows, units, pre, tuple(media)), directory)
