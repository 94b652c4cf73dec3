"""Command line of the comparisons: ``pim compare``, ``pim animate``, ``pim speed-error``,
``pim hard-cases``, ``pim assumptions`` (listed in :mod:`pim_cli.commands`)."""

from __future__ import annotations

import contextlib
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import click

import pim
from comparisons.animation.collision import MAX_SHOWN
from pim.model.numbers import InputError
from pim_cli.main import (
    Beta,
    FiniteFloat,
    allow_inadmissible_option,
    allow_inconsistent_option,
    beta_option,
    case_argument,
    check_answer,
    echo_json,
    eps_option,
    findings_json,
    finish_answer,
    finish_evidence,
    friction_limit_option,
    json_option,
    law_options,
    load_case_for,
    output_units,
    resolve_options,
    say_contradiction,
    solve_choice,
    solve_with_options,
    units_option,
)

__all__ = ["compare", "animate", "speed_error", "hard_cases", "assumptions"]

out_option = click.option("--out", "out", type=click.Path(file_okay=False), default=None,
                          help="Output folder (default: out/CASE).")
progress_option = click.option("--progress/--no-progress", default=None,
                               help="Progress bars on stderr (default: only on a terminal).")


def _out(out, name: str, default: str) -> Path:
    return Path(out) if out is not None else Path("out") / (name or default)


compare_eps_option = click.option(
    "--eps", type=FiniteFloat(), default=None,
    help="Coefficient of restitution epsilon in [0, 1] (default: fitted to the case's "
         "measured motion, else the case's impact.restitution). With --beta: no fit.")
compare_beta_option = click.option(
    "--beta", type=Beta(), default=None,
    help="Fraction of the critical impulse ratio, mu = beta mu0 (default: fitted to the "
         "case's measured motion, else the case's impact.beta, else 1). With --eps: no fit.")


@click.command()
@case_argument
@out_option
@compare_eps_option
@compare_beta_option
@click.option("--gif", is_flag=True, help="Also write animation.gif (slower, larger).")
@units_option
@friction_limit_option
@click.option("--no-animation", is_flag=True, help="Skip the animation.")
@click.option("--no-speed-error", is_flag=True, help="Skip the coarse speed-error sweep.")
@click.option("--no-assumptions", is_flag=True,
              help="Skip PIM's assumptions at typical values (finite-duration scene).")
@click.option("--tyre-friction", "tyre", type=FiniteFloat(0.0, 5.0, "-"), default=None,
              help="Tyre/ground friction coefficient after impact in the animation (the "
                   "ghost decelerates alike; default: the case's [evidence] friction, else "
                   "0.7, dry asphalt); 0 = free motion.")
@law_options
@progress_option
@allow_inadmissible_option
@allow_inconsistent_option
@json_option
def compare(case_name, out, eps, beta, gif, units, speed_unit, friction_limit, no_animation,
            no_speed_error, no_assumptions, tyre, law, k, mu_c, progress, allow_inadmissible,
            allow_inconsistent, as_json):
    """Write CASE's reconstruction report to a folder: PIM's answer, its plots and
    animation, and a pymunk cross-check.

    The folder holds report.html, report.md, CSVs, PNGs and an MP4; report.html is one
    self-contained page with the plots and the animation.

    The report opens with the answer a reconstruction hands on (each vehicle's delta-V, PDOF
    and post-impact speed and the energy lost, with 5-95 % intervals from the case's
    [uncertainty] table, digits as the intervals allow), the warnings (a fit that misses a
    measured quantity by more than 3 sigma among them) and the results table, then each
    measured quantity against the answer in sigmas, the coefficients with their source,
    inputs, plots and animation; the appendix compares PIM with a pymunk simulation and
    sweeps the simulator's speed against its error. Prints the answer, then the path of
    report.html last. (epsilon, beta) are fitted to the measured motion
    when the case has some; --eps and --beta together skip the fit (one of them: the other
    is fitted). Exit code 1 with one line when the vehicles do not approach at C, and
    after the report is written when its answer is inadmissible (the reasons first, and at
    the top of the report; --allow-inadmissible: exit 0). A secondary contact of the
    outlines after the impact is a note with its time and place. Exit code 1 too after the
    report when the measured evidence the fit uses contradicts itself, its chi-square's p
    below 0.001 (the reason first, and at the top of the report; --allow-inconsistent or
    --allow-inadmissible: exit 0).

    Under another impact law (the case's impact.law or --law: kudlich-slibar with --k and
    --mu-c, brach-capped) the report is that law's answer, its pymunk run (two phases for
    kudlich-slibar) and animation; a fit to measured motion is done under that law ((k, mu_c)
    for kudlich-slibar; docs/impact-laws.md).
    """
    from comparisons.report.compare import compare_case

    case = load_case_for("compare", case_name, law)
    units = output_units(case, units, speed_unit)
    folder = _out(out, case.name, "case")
    choice = resolve_options(case, eps, beta, law=law, k=k, mu_c=mu_c)
    if choice.law != "brach":
        _compare_law(case, folder, choice, units, gif=gif, tyre=tyre,
                     animation=not no_animation, progress=progress, as_json=as_json,
                     allow=allow_inadmissible)
        return
    solve_with_options(case, 0.0, 1.0, units=units)     # exit 1, one line, when no impact
    started = time.perf_counter()
    rep = compare_case(case, folder, eps=eps, beta=beta, gif=gif, animation=not no_animation,
                       speed_error=not no_speed_error, tyre=tyre,
                       assumptions=not no_assumptions, progress=progress,
                       units=units, friction_limit=friction_limit, case_path=case_name)
    units = units or case.units
    reason = rep.data.fit.contradiction if rep.data.fit is not None else None
    say_contradiction(reason, allow_inadmissible or allow_inconsistent)
    found = check_answer(case, pim.solve(case, rep.eps, rep.beta), units, friction_limit,
                         allow_inadmissible, as_json)
    secondary = _secondary_note(rep.animation, units, as_json)
    if as_json:
        echo_json({"case": case.name, "units": units.to_json(), "out": str(folder),
                   "eps": rep.eps, "beta": rep.beta, "goodness_of_fit": _goodness(rep),
                   "error": rep.error, "seconds": rep.seconds, **findings_json(found),
                   "secondary_impact": secondary,
                   "event_crosscheck": _event_check_json(rep, units),
                   "files": sorted(str(p) for p in rep.files)})
    else:
        error = ("simulation failed" if rep.error != rep.error
                 else f"pymunk vs PIM error {rep.error:.2e}")
        _answer(rep.data.result, rep.data.units, rep.data.spread)
        click.echo(f"{case.name}: epsilon = {rep.eps:.6g}, beta = {rep.beta:.6g}; {error}")
        if rep.animation is not None:
            a = rep.animation
            click.echo(f"animation: {a.frames} frames, rendered at {a.render_fps:.0f} "
                       f"frames/s")
        _poor_fit(rep.data.result, rep.data.units, rep.data.fit)
        _wrote(rep, started)
    finish_answer(found, allow_inadmissible)
    finish_evidence(reason, allow_inadmissible or allow_inconsistent)


def _goodness(rep) -> dict | None:
    """The chi-square test of the fit the report used (None: no fit, or no sigmas)."""
    fit = rep.data.fit
    return None if fit is None or fit.goodness is None else fit.goodness.to_dict()


def _event_check_json(rep, units) -> dict | None:
    """The analytic event against the pymunk event at each impact and at rest, in
    ``units`` (None without the whole event's animation)."""
    check = None if rep.data is None else rep.data.event_check
    return None if check is None else check.to_dict(units)


def _answer(result, units, spread=None) -> None:
    """The answer the report leads with, one line per card."""
    from comparisons.report.compare_tables import answer_cards

    for card in answer_cards(result, units, spread).cards:
        click.echo(f"{card.label}: {card.value}" + (f" ({card.note})" if card.note else ""))


def _poor_fit(result, units, fit) -> None:
    """A warning when the answer misses a measured quantity by more than 3 sigma."""
    from comparisons.report.compare_tables import misfit_sentence
    from pim.analysis.misfit import misfit

    sentence = misfit_sentence(misfit(result), units, fit)
    if sentence:
        click.echo(f"warning: {sentence}", err=True)


def _wrote(rep, started: float) -> None:
    """The last line: the deliverable, report.html (and report.md beside it)."""
    click.echo(f"wrote {rep.html} (and {rep.report.name}; {len(rep.files)} files in "
               f"{rep.out_dir}) in {time.perf_counter() - started:.1f} s")


def _secondary_note(info, units: str, as_json: bool) -> dict | None:
    """The animation's secondary contact (``info``: an AnimationInfo or None) as a note on
    stderr with its time and place (not with ``as_json``), and as its JSON (None: none)."""
    found = getattr(info, "secondary_impact", None)
    if found is None:
        return None
    if not as_json:
        click.echo(f"note: {found.message(units)}", err=True)
    return found.to_json(units)


def _compare_law(case, folder, choice, units, *, as_json, allow, **kwargs):
    """``pim compare`` under an impact law other than Brach's (comparisons.report.law), the
    law and its parameters resolved from the options (``choice``: a
    :class:`pim.model.law.LawChoice`)."""
    from comparisons.report.law import compare_law_case
    from comparisons.studies.law_runs import law_setup

    started = time.perf_counter()
    result = solve_choice(case, choice, units)      # exit 1, one line, when no impact
    setup = law_setup(case, choice.law, result.eps, choice.beta, choice.contact_friction)
    rep = compare_law_case(case, folder, setup, units=units, **kwargs)
    found = check_answer(case, setup.result, units, allow=allow, as_json=as_json)
    secondary = _secondary_note(getattr(rep, "animation", None), units or case.units, as_json)
    if as_json:
        echo_json({"case": case.name, "units": units.to_json(), "out": str(folder),
                   "law": setup.law,
                   "restitution": setup.restitution, "beta": setup.beta,
                   "contact_friction": setup.contact_friction, "error": rep.error,
                   **findings_json(found), "secondary_impact": secondary,
                   "files": sorted(str(p) for p in rep.files)})
    else:
        error = ("simulation failed" if rep.error != rep.error
                 else f"pymunk vs analytic error {rep.error:.2e}")
        _answer(setup.result, units)
        click.echo(f"{case.name}: {setup.describe()}; {error}")
        _poor_fit(setup.result, units, None)
        _wrote(rep, started)
    finish_answer(found, allow)



@click.command()
@case_argument
@click.option("--out", "out", type=click.Path(dir_okay=False), default=None,
              help="MP4 file to write (default: out/CASE-animation.mp4, beside pim "
                   "compare's folder out/CASE, which each compare run replaces whole).")
@eps_option
@beta_option
@click.option("--gif", "gif", type=click.Path(dir_okay=False), default=None,
              help="Also write an animated GIF (half size) here.")
@click.option("--fps", type=int, default=30, show_default=True, help="Frames per second.")
@click.option("--before", type=FiniteFloat(0.0, MAX_SHOWN, "s"), default=None,
              help=f"Seconds shown before the impact, at most {MAX_SHOWN:g} (default: the "
                   "1 s approach).")
@click.option("--after", type=FiniteFloat(0.0, MAX_SHOWN, "s"), default=None,
              help=f"Seconds shown after the impact, at most {MAX_SHOWN:g} (default: until "
                   "both vehicles are at rest; 2 s of free motion without tyre friction).")
@click.option("--size", type=(int, int), default=None,
              help="Frame width and height [px], even numbers (default: 960 wide, the "
                   "height fitted to the motion).")
@click.option("--tyre-friction", "tyre", type=FiniteFloat(0.0, 5.0, "-"), default=None,
              help="Tyre/ground friction coefficient after the impact, ghost alike "
                   "(default: the case's [evidence] friction, else 0.7, dry asphalt; "
                   "0: free motion).")
@click.option("--no-ghost", is_flag=True, help="Do not draw PIM's answer as a ghost.")
@click.option("--single-impact", is_flag=True,
              help="PIM's single impact and its run-out against the rigid scene's simulation "
                   "of that impact, not the whole event.")
@law_options
@units_option
@progress_option
@allow_inadmissible_option
@json_option
def animate(case_name, out, eps, beta, gif, fps, before, after, size, tyre, no_ghost,
            single_impact, law, k, mu_c, units, speed_unit, progress, allow_inadmissible,
            as_json):
    """Animate CASE's whole event, from the approach to rest: the pymunk event solid, the
    analytic event (pim event) as a ghost (MP4).

    The tyre friction is the case's [evidence]'s, else 0.7 (dry asphalt), stated in the
    caption; every impact is drawn at its C with its contact plane, tyre marks where the
    wheels slide. With --single-impact, or under another impact law than Brach's (the case's
    impact.law or --law), PIM's single impact and its run-out against the pymunk run of
    that impact: Brach's PIM and friction-capped Brach play the
    rigid scene at (eps, effective beta); the Kudlich-Slibar law plays its two-phase run
    (compression by the engine at mu_c, then k times its impulse) and continues after
    separation (docs/impact-laws.md). A secondary contact of the outlines after the impact
    is marked in the frames and a note (its time and place); exit code 1 after writing when
    the analytic answer is inadmissible (the reasons first; --allow-inadmissible: exit 0).
    """
    import sim
    from comparisons.animation.collision import animate_case, animation_plan
    from comparisons.studies.law_runs import law_setup, simulate_law

    _check_suffix(out, "--out", ".mp4")
    _check_suffix(gif, "--gif", ".gif")
    case = load_case_for("animate", case_name, law)
    units = output_units(case, units, speed_unit)
    path = Path(out) if out else Path("out") / f"{case.name or 'case'}-animation.mp4"
    kwargs = dict(gif=gif, progress=progress, fps=fps, before=before, after=after, size=size,
                  tyre=tyre, ghost=not no_ghost, units=units)
    setup = None
    choice = resolve_options(case, eps, beta, law=law, k=k, mu_c=mu_c)
    if choice.law == "brach":
        eps_, beta_ = sim.scene.resolve_coefficients(case, eps, beta)
    else:
        result = solve_choice(case, choice, units)      # exit 1, one line, when no impact
        setup = law_setup(case, choice.law, result.eps, choice.beta, choice.contact_friction)
        eps_, beta_ = setup.restitution, setup.beta
    found = check_answer(case, setup.result if setup else pim.solve(case, eps_, beta_),
                         kwargs["units"], allow=allow_inadmissible, as_json=as_json)
    if setup is None and not single_impact:
        _animate_event(case, path, kwargs, (eps, beta), found, as_json)
        finish_answer(found, allow_inadmissible)
        return
    try:
        if setup is not None:
            kwargs.update(result=setup.result, title=f"{case.name or 'case'}: {setup.describe()}",
                          simulated=simulate_law(case, setup,
                                                 animation_plan(case, setup.result,
                                                                tyre, after)))
        info = animate_case(case, eps_, beta_, path, **kwargs)
    except sim.SimulationError as exc:
        click.echo(f"simulation failed ({exc.kind}): {exc}", err=True)
        sys.exit(1)
    secondary = _secondary_note(info, kwargs["units"], as_json)
    if as_json:
        echo_json({"path": str(info.path), "gif": str(info.gif) if info.gif else None,
                   "frames": info.frames, "fps": info.fps, "size": list(info.size),
                   "render_fps": info.render_fps, "write_seconds": info.write_seconds,
                   "max_ghost_offset_px": info.max_ghost_offset_px,
                   "law": setup.law if setup else "brach",
                   "restitution": eps_, "beta": beta_,
                   "contact_friction": setup.contact_friction if setup else None,
                   **findings_json(found), "secondary_impact": secondary})
    else:
        if setup is not None:
            click.echo(f"{case.name or 'case'}: {setup.describe()}")
        click.echo(f"wrote {info.path}" + (f" and {info.gif}" if info.gif else "")
                   + f": {info.frames} frames at {info.fps} fps, rendered at "
                     f"{info.render_fps:.0f} frames/s, encoded in {info.write_seconds:.2f} s; "
                     f"ghost offset after impact {info.max_ghost_offset_px:.2g} px")
    finish_answer(found, allow_inadmissible)


def _animate_event(case, path, kwargs, coefficients, found, as_json) -> None:
    """``pim animate``'s whole event (the analytic event over the pymunk event)."""
    import sim
    from comparisons.animation.collision import animate_event

    eps, beta = coefficients
    try:
        info = animate_event(case, path, eps=eps, beta=beta, **kwargs)
    except sim.SimulationError as exc:
        click.echo(f"simulation failed ({exc.kind}): {exc}", err=True)
        sys.exit(1)
    if as_json:
        echo_json({"path": str(info.path), "gif": str(info.gif) if info.gif else None,
                   "frames": info.frames, "fps": info.fps, "size": list(info.size),
                   "render_fps": info.render_fps, "write_seconds": info.write_seconds,
                   "max_ghost_offset_px": info.max_ghost_offset_px, "whole_event": True,
                   "impacts": len(info.event.impacts), **findings_json(found)})
        return
    click.echo(f"wrote {info.path}" + (f" and {info.gif}" if info.gif else "")
               + f": the whole event, {len(info.event.impacts)} impact(s), {info.frames} "
                 f"frames at {info.fps} fps, rendered at {info.render_fps:.0f} frames/s")


def _check_suffix(path, option: str, suffix: str) -> None:
    """A file option must name a ``suffix`` file (checked before any work)."""
    if path is not None and Path(path).suffix.lower() != suffix:
        raise InputError(f"{option} {path}: the file must end in {suffix}")


@click.command("speed-error")
@click.argument("case_names", metavar="CASE...", nargs=-1, required=True)
@click.option("--out", "out", type=click.Path(file_okay=False), default=None,
              help="Output folder (default: out/speed-error).")
@eps_option
@beta_option
@click.option("--repeats", type=int, default=3, show_default=True,
              help="Runs per setting (the best wall time is kept).")
@click.option("--coarse", is_flag=True, help="The report's coarse grid instead of the full one.")
@click.option("--compliant/--no-compliant", default=True, show_default=True,
              help="Also the finite-duration contact: the fixed-step scene over dt, "
                   "solve_ivp over rtol.")
@click.option("--engine", type=click.Choice(["numba", "pymunk"]), default="numba",
              show_default=True, help="The finite-duration scene's fixed-step integrator: "
                                      "compiled, or pymunk (the cross-check).")
@click.option("--event", "event", is_flag=True,
              help="Also the whole event: pymunk over dt and iterations and the analytic "
                   "event over its step, against a tight pymunk event.")
@progress_option
@json_option
def speed_error(case_names, out, eps, beta, repeats, coarse, compliant, engine, event,
                progress, as_json):
    """Sweep the simulator's dt, iterations, contact start and geometry for each CASE.

    Writes, per case, speed-error-CASE.md and .html (table of the Pareto front and every
    run), speed-error-CASE.csv and speed-error-CASE.png (log-log error against wall time per
    impact, with the Pareto front, PIM's own time and error and the recommended setting).
    With --compliant (default) also speed-error-compliant-CASE.md/.html/.csv/.png: the
    finite-duration contact stepped over dt (compiled, or by pymunk with --engine pymunk)
    and integrated by solve_ivp over rtol, against a tight solve_ivp reference, its two
    scenes on two worker processes. With --event also speed-error-event-CASE.md/.html/
    .csv/.png: the whole event (approach, every impact, run-out to rest), pymunk over dt and
    iterations and the analytic event over its step, against pymunk at dt = 1e-4 s.
    "hard" stands for every bundled hard case.
    """
    from pim.io.casefile import list_cases
    from pim.io.output import output_folder, rebase
    from pim.io.process import worker_pool

    if repeats < 1:
        raise InputError(f"--repeats must be >= 1, got {repeats}")
    names = []
    for n in case_names:
        names += [c for c, _ in list_cases() if c.startswith("hard-")] if n == "hard" else [n]
    cases = [load_case_for("speed-error", name) for name in names]     # before the lock
    folder = Path(out) if out else Path("out") / "speed-error"
    opts = _SpeedErrorOptions(out, eps, beta, repeats, coarse, engine if compliant else None,
                              progress, as_json, event=event)
    wall, cpu = time.perf_counter(), time.process_time()
    with output_folder(folder, command="pim speed-error", merge=True) as tmp, \
            contextlib.ExitStack() as stack:
        pool = stack.enter_context(worker_pool(2)) if compliant else None
        results = [_speed_error_case(name, case, tmp, opts, pool)
                   for name, case in zip(names, cases)]
    for r in results:
        r["files"] = [str(p) for p in rebase(r["files"], tmp, folder)]
    if as_json:
        echo_json(results)
        return
    for r in results:
        for line in r.pop("lines"):
            click.echo(line)
        click.echo(f"wrote {r['files'][0]}")
    click.echo(f"pim speed-error: {time.perf_counter() - wall:.1f} s wall, "
               f"{time.process_time() - cpu:.1f} s CPU in this process")


@dataclass(frozen=True)
class _SpeedErrorOptions:
    """The options of ``pim speed-error`` (``engine`` None: no finite-duration study)."""

    out: str | None
    eps: float | None
    beta: float | None
    repeats: int
    coarse: bool
    engine: str | None
    progress: bool | None
    as_json: bool
    event: bool = False

    def command(self, name: str) -> str:
        return _command(name, self.coarse, self.repeats, self.out) + (
            " --event" if self.event else "")


def _speed_error_case(name: str, case, folder, opts: _SpeedErrorOptions, pool) -> dict:
    """Sweep one case (``case``, loaded from ``name`` before the output lock was taken) and
    write its files into ``folder``: a JSON-ready dict (with the lines to print under
    ``"lines"``)."""
    from comparisons.report.speed_error import speed_error_json, speed_error_line
    from comparisons.report.speed_error import write_speed_error as write_study
    from comparisons.studies.speed_error import COARSE, sweep

    grid = dict(COARSE) if opts.coarse else {}
    study = sweep(case, opts.eps, opts.beta, progress=opts.progress,
                  **{**grid, "repeats": opts.repeats})
    stem = case.name or Path(name).stem
    cstudy = None if opts.engine is None else _compliant_sweep(case, opts, pool)
    # every timed run is done: the rigid study's plot is drawn on a worker while this
    # process draws the finite-duration one
    written = pool.submit(write_study, study, folder, stem, command=opts.command(name)) \
        if pool is not None else None
    result = speed_error_json(study, stem) | {"lines": []}
    if cstudy is not None:
        _compliant_result(cstudy, stem, folder, opts, result)
    files = write_study(study, folder, stem, command=opts.command(name)) \
        if written is None else written.result()
    result["files"] = [str(f) for f in files] + result["files"]
    result["lines"].append(speed_error_line(study, stem))
    if opts.event:
        _event_result(case, stem, folder, opts, result)
    if opts.as_json:
        result.pop("lines")
    return result


def _compliant_sweep(case, opts: _SpeedErrorOptions, pool):
    """The finite-duration study of one case, its two scenes on the pool's workers."""
    from comparisons.studies import speed_error_compliant as S

    grid = S.COARSE if opts.coarse else S.Grid(repeats=opts.repeats)
    return S.compliant_sweep(case, opts.eps, grid=grid, progress=opts.progress,
                             engine=opts.engine, executor=pool)


def _compliant_result(cstudy, stem: str, folder, opts: _SpeedErrorOptions,
                      result: dict) -> None:
    """Write the finite-duration study and put its files, recommendations and lines into
    ``result``."""
    from comparisons.report.speed_error import compliant_json, compliant_summary, write_compliant

    cfiles = write_compliant(cstudy, folder, stem, command=opts.command(stem))
    result["files"] += [str(f) for f in cfiles]
    result.update(compliant_json(cstudy))
    result["lines"] += compliant_summary(cstudy, stem)


def _event_result(case, stem: str, folder, opts: _SpeedErrorOptions, result: dict) -> None:
    """The whole event's sweep of one case, written; its files, JSON and line into
    ``result``."""
    from comparisons.report.speed_error import (
        event_speed_json,
        event_speed_line,
        write_event_speed,
    )
    from comparisons.studies.event_speed_error import EVENT_COARSE, event_sweep

    grid = dict(EVENT_COARSE) if opts.coarse else {}
    study = event_sweep(case, progress=opts.progress, repeats=opts.repeats, **grid)
    files = write_event_speed(study, folder, stem, command=opts.command(stem))
    result["files"] += [str(f) for f in files]
    result.update(event_speed_json(study))
    result["lines"].append(event_speed_line(study, stem))


def _command(name: str, coarse: bool, repeats: int, out) -> str:
    return (f"pim speed-error {name}" + (" --coarse" if coarse else "")
            + (f" --repeats {repeats}" if repeats != 3 else "")
            + (f" --out {out}" if out else ""))


@click.command("hard-cases")
@click.option("--out", "out", type=click.Path(file_okay=False), default=None,
              help="Output folder (default: out/hard-cases).")
@units_option
@progress_option
@json_option
def hard_cases(out, units, speed_unit, progress, as_json):
    """Run every bundled hard case through PIM and the simulator.

    Prints and writes (into --out) the table of results, errors, and the dt / iterations
    the simulator needs to reach 1e-6 (or why it cannot).
    """
    from comparisons.report.hard_cases import write_hard_cases
    from comparisons.report.render import markdown_table
    from comparisons.studies.hard_cases import run_hard_cases
    from pim.io.output import output_folder, rebase

    folder = Path(out) if out else Path("out") / "hard-cases"
    units = output_units(None, units, speed_unit)      # the hard cases are written in SI
    with output_folder(folder, command="pim hard-cases", merge=True) as tmp:
        study = run_hard_cases(progress=progress)
        files = rebase(write_hard_cases(study, tmp, units), tmp, folder)
    if as_json:
        echo_json({"units": units.to_json(), "files": [str(f) for f in files],
                   "cases": study.to_json()})
        return
    click.echo(markdown_table(study.results_table(units)))
    click.echo("")
    click.echo(markdown_table(study.needs_table()))
    click.echo(f"\nwrote {', '.join(str(f) for f in files)}")


@click.command("assumptions")
@case_argument
@click.option("--out", "out", type=click.Path(file_okay=False), default=None,
              help="Output folder (default: out/CASE-assumptions, beside pim compare's "
                   "out/CASE: each command's folder holds its own run whole).")
@eps_option
@beta_option
@click.option("--executor", type=click.Choice(["process", "serial"]), default="process",
              show_default=True, help="Run the pymunk scenes (--engine pymunk) on a local "
                                      "process pool or serially.")
@click.option("--no-animation", is_flag=True, help="Skip the MP4 of the finite-duration scene.")
@click.option("--engine", type=click.Choice(["numba", "pymunk"]), default="numba",
              show_default=True, help="The compiled crush scene for the point contacts, or "
                                      "pymunk for every scene (the cross-check).")
@units_option
@progress_option
@json_option
def assumptions(case_name, out, eps, beta, executor, no_animation, engine, units, speed_unit,
                progress, as_json):
    """Test PIM's assumptions for CASE, one at a time, on a ladder of crush scenes.

    Each scene differs from its baseline in one assumption (Newton's restitution and
    mu = beta mu0, instantaneous impulse, one contact point, no external forces with the
    wheels rolling or locked, PIM's tangential law); each effect is stated over 50-150 ms
    of contact (and the tangential recovery 0-1 for friction), in % and as the delta-V and
    yaw rate it moves, in the case's units. Where C is stands beside the ladder as input
    uncertainty. Writes assumptions.md and .html, CSVs, a plot and an MP4 with PIM's ghost.
    """
    from comparisons.report.assumptions import study_json, verdicts, write_assumptions
    from comparisons.studies.assumptions import run_assumptions
    from pim.io.output import output_folder, rebase
    from pim.io.process import worker_pool

    case = load_case_for("assumptions", case_name)
    units = output_units(case, units, speed_unit)
    folder = Path(out) if out is not None else Path("out") / f"{case.name or 'case'}-assumptions"
    command = f"pim assumptions {case_name}" + (f" --out {out}" if out else "")
    with output_folder(folder, command="pim assumptions") as tmp, \
            contextlib.ExitStack() as stack:
        if executor == "process" and engine == "pymunk":     # the compiled scene batches
            executor = stack.enter_context(worker_pool())
        study = run_assumptions(case, eps, beta, executor=executor, progress=progress,
                                animation_after=None if no_animation else 2.0, engine=engine)
        files = rebase(write_assumptions(study, tmp, animation=not no_animation,
                                         progress=progress, command=command, units=units),
                       tmp, folder)
    if as_json:
        echo_json({**study_json(study, units), "seconds": study.seconds,
                   "files": [str(f) for f in files]})
        return
    for verdict in verdicts(study, units):
        click.echo(f"- {verdict}")
    click.echo(f"wrote {folder / 'assumptions.md'} ({len(files)} files) in "
               f"{study.seconds:.1f} s of simulation ({study.engine})")
