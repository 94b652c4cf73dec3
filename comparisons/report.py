"""``pim compare``: the whole story of one case in a folder -- report.md, CSVs, PNGs, MP4.

Steps (each file written atomically; report.md last, so that it only exists when every
file it links does):

1. the case inputs (inputs.csv);
2. the least-squares (epsilon, beta) when the case has measured post-impact motion
   (:func:`pim.fit`, fit.csv), else the case's own epsilon and beta;
3. PIM's answer and the pymunk simulation at those coefficients, every post-impact quantity
   with absolute and relative error (crosscheck.csv);
4. the design sheet's plots (:func:`pim.plots.write_plots`, plots/*.png);
5. the animation (animation.mp4, optionally animation.gif);
6. a coarse speed-against-error sweep (speed_error.csv, speed_error_pareto.csv,
   speed_error.png); the full study is ``pim speed-error``;
7. PIM's assumptions at typical values (the finite-duration crush scene,
   :mod:`comparisons.assumptions`; assumptions.csv); the full study is ``pim assumptions``.

The animation and the report say so when the outlines run into each other again after the
impact (a secondary impact PIM does not model, :func:`sim.find_secondary_impact`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import pim
from pim.files import atomic_path, write_text

from .assumptions import assumption_table, run_assumptions
from .coefficients import coefficients
from .errors import compare_results, impact_error
from .tables import Table, fmt_error

__all__ = ["Report", "compare_case", "inputs_table", "fit_table", "crosscheck_table"]


def _f(x) -> float:
    return float(np.asarray(x, float).reshape(()))


@dataclass
class Report:
    """What :func:`compare_case` wrote and measured."""

    out_dir: Path
    files: list[Path] = field(default_factory=list)
    eps: float = math.nan
    beta: float = math.nan
    error: float = math.nan
    seconds: dict = field(default_factory=dict)
    animation: object = None
    study: object = None
    assumptions: object = None

    @property
    def report(self) -> Path:
        return self.out_dir / "report.md"


def inputs_table(case: pim.Case) -> Table:
    """The case's inputs in SI units."""
    rows = []
    for i, v in ((1, case.vehicle1), (2, case.vehicle2)):
        fixed = bool(v.fixed)
        cg = np.asarray(v.cg, float).reshape(2)
        vel = np.asarray(v.velocity, float).reshape(2)
        rows += [
            (f"vehicle {i}", "mass", "fixed obstacle" if fixed else _f(v.mass), "kg"),
            (f"vehicle {i}", "yaw inertia", "" if fixed else _f(v.yaw_inertia), "kg m^2"),
            (f"vehicle {i}", "CG x, y", f"{cg[0]:.6g}, {cg[1]:.6g}", "m"),
            (f"vehicle {i}", "heading", math.degrees(_f(v.heading)), "deg"),
            (f"vehicle {i}", "velocity x, y", f"{vel[0]:.6g}, {vel[1]:.6g}", "m/s"),
            (f"vehicle {i}", "yaw rate", _f(v.yaw_rate), "rad/s"),
            (f"vehicle {i}", "length x width",
             "" if v.length is None else f"{v.length:.4g} x {v.width:.4g}", "m"),
        ]
    p = np.asarray(case.impact.point, float).reshape(2)
    rows += [("impact", "point C x, y", f"{p[0]:.6g}, {p[1]:.6g}", "m"),
             ("impact", "normal angle Gamma", math.degrees(_f(case.impact.normal_angle)), "deg"),
             ("impact", "restitution in the case", case.impact.restitution, "-"),
             ("impact", "beta in the case", case.impact.beta, "-")]
    m = case.measured
    if m is not None:
        for i, vel, w in ((1, m.velocity1, m.yaw_rate1), (2, m.velocity2, m.yaw_rate2)):
            if vel is not None:
                vel = np.asarray(vel, float).reshape(2)
                rows.append((f"measured {i}", "post-impact velocity x, y",
                             f"{vel[0]:.6g}, {vel[1]:.6g}", "m/s"))
            if w is not None:
                rows.append((f"measured {i}", "post-impact yaw rate", _f(w), "rad/s"))
    return Table("inputs", "Case inputs (SI)", ("item", "quantity", "value", "unit"),
                 tuple(rows))


def fit_table(fit) -> Table:
    """The fitted (epsilon, beta) and the quality of the fit."""
    rows = [("epsilon", fit.eps, "-"), ("beta", fit.beta, "-"),
            ("cost (sum of squared velocity errors)", fit.cost, "m^2/s^2"),
            ("rms residual", fit.rms, "m/s"),
            ("on a bound", ", ".join(f"{k} {v}" for k, v in fit.on_bound.items()) or "no", ""),
            ("local minima found", len(fit.minima), "")]
    rows += [(f"residual {name}", float(r), "m/s")
             for name, r in zip(fit.residual_names, fit.residuals, strict=True)]
    return Table("fit", "Least-squares fit of (epsilon, beta) to the measured motion",
                 ("quantity", "value", "unit"), tuple(rows))


def crosscheck_table(errors) -> Table:
    """Analytic against simulated, every post-impact quantity."""
    rows = tuple((q.label, q.unit, q.analytic, q.simulated, q.absolute, q.relative)
                 for q in errors)
    return Table("crosscheck", "PIM (analytic) against pymunk (simulated), post-impact",
                 ("quantity", "unit", "PIM", "pymunk", "absolute error", "relative error"),
                 rows, formats={"absolute error": fmt_error, "relative error": fmt_error})


def _md_table(table: Table) -> str:
    return f"**{table.title}** ([{table.name}.csv]({table.name}.csv))\n\n{table.to_markdown()}\n"


def compare_case(case: pim.Case, out_dir, *, eps: float | None = None,
                 beta: float | None = None, gif: bool = False, animation: bool = True,
                 speed_error: bool = True, tyre: float = 0.0, assumptions: bool = True,
                 progress: bool | None = None) -> Report:
    """Write the comparison report of one case to ``out_dir`` (see the module docstring).

    Parameters
    ----------
    case : pim.Case
        A single case.
    out_dir : path
        Folder to write (created; existing files of the same names are replaced).
    eps, beta : float, optional
        Use these instead of fitting (either one fixed: the other is fitted when the case
        has measurements).
    gif : bool
        Also write animation.gif.
    animation, speed_error : bool
        Include the animation and the coarse speed-error sweep.
    assumptions : bool
        Include PIM's assumptions at typical values (the full study: ``pim assumptions``).
    tyre : float
        Tyre friction coefficient after the impact in the animation (0: none).
    progress : bool or None
        tqdm bars on stderr (None: only on a terminal).
    """
    from tqdm import tqdm

    import sim
    from pim.files import save_figure
    from pim.plots import write_plots

    from .animation import build_renderer, write_animation
    from .speed_error import COARSE, pareto_table, plot_speed_error, study_table, sweep

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rep = Report(out_dir=out)
    steps = ["fit", "simulate", "plots"] + (["animation"] if animation else []) \
        + (["speed-error"] if speed_error else []) \
        + (["assumptions"] if assumptions else []) + ["report"]
    bar = tqdm(total=len(steps), desc=f"compare {case.name or ''}".strip(), unit="step",
               disable=None if progress is None else not progress)

    def tick(name, t0):
        rep.seconds[name] = time.perf_counter() - t0
        bar.update(1)

    # 1-2: inputs and fit ------------------------------------------------------------------
    t0 = time.perf_counter()
    tables = [inputs_table(case)]
    eps, beta, fit = coefficients(case, eps, beta)
    if fit is not None:
        tables.append(fit_table(fit))
    rep.eps, rep.beta = eps, beta
    result = pim.solve(case, eps, beta)
    tick("fit", t0)

    # 3: cross-check -------------------------------------------------------------------------
    t0 = time.perf_counter()
    limits = sim.limitations(case, eps, beta)
    sim_error = None
    simulated = None
    try:
        simulated = sim.simulate(case, eps, beta, analytic=pim.solve(case, eps, 1.0))
    except sim.SimulationError as exc:
        sim_error = exc
    if simulated is not None:
        errors = compare_results(case, result, simulated)
        tables.append(crosscheck_table(errors))
        rep.error = float(impact_error(case, result, simulated.velocity1, simulated.velocity2,
                                       simulated.yaw_rate1, simulated.yaw_rate2))
    tick("simulate", t0)

    # 4: plots ------------------------------------------------------------------------------
    t0 = time.perf_counter()
    plot_files = write_plots(case, fit, out / "plots", formats=("png",))
    rep.files += plot_files
    tick("plots", t0)

    # 5: animation --------------------------------------------------------------------------
    info = None
    anim_error = None
    if animation:
        t0 = time.perf_counter()
        try:
            renderer = build_renderer(case, eps, beta, result=result, tyre=tyre)
            info = write_animation(renderer, out / "animation.mp4",
                                   gif=out / "animation.gif" if gif else None,
                                   progress=progress)
            rep.files.append(info.path)
            if info.gif:
                rep.files.append(info.gif)
        except sim.SimulationError as exc:
            anim_error = exc
        rep.animation = info
        tick("animation", t0)

    # 6: speed against error ------------------------------------------------------------------
    study = None
    if speed_error:
        t0 = time.perf_counter()
        study = sweep(case, eps, beta, progress=progress, **COARSE)
        rep.study = study
        tables += [pareto_table(study), study_table(study)]
        rep.files.append(save_figure(plot_speed_error(study), out / "speed_error.png"))
        tick("speed-error", t0)

    # 7: assumptions at typical values ----------------------------------------------------------
    if assumptions:
        t0 = time.perf_counter()
        rep.assumptions = run_assumptions(case, eps, beta, executor="serial", progress=False,
                                          animation_after=None, sweeps=False)
        tables.append(assumption_table(rep.assumptions))
        tick("assumptions", t0)

    # 8: CSVs and report.md ---------------------------------------------------------------------
    t0 = time.perf_counter()
    for table in tables:
        rep.files.append(table.write_csv(out))
    text = _markdown(case, fit, eps, beta, result, simulated, sim_error, limits, tables,
                     plot_files, out, info, anim_error, study, rep)
    rep.files.append(write_text(out / "report.md", text))
    tick("report", t0)
    bar.close()
    return rep


def _markdown(case, fit, eps, beta, result, simulated, sim_error, limits, tables, plot_files,
              out, info, anim_error, study, rep) -> str:
    by_name = {t.name: t for t in tables}
    name = case.name or "case"
    lines = [f"# {name}: PIM against a pymunk simulation", ""]
    if getattr(case, "description", None):
        lines += [case.description, ""]
    lines += ["Written by `pim compare`. Brach's Planar Impact Mechanics (PIM) gives the "
              "post-impact motion in closed form; a pymunk (Chipmunk2D) scene recreates the "
              "same impact -- one contact point at C with normal n, the case's masses, "
              "inertias and velocities -- and the two are compared quantity by quantity.", ""]
    lines += ["## Case inputs", "", _md_table(by_name["inputs"])]
    lines += ["## Coefficients", ""]
    if fit is not None:
        lines += [f"Fitted to the measured post-impact velocities (least squares, "
                  f"`pim fit`): **epsilon = {fit.eps:.6g}, beta = {fit.beta:.6g}** "
                  f"(rms residual {fit.rms:.4g} m/s).", "", _md_table(by_name["fit"])]
    else:
        lines += [f"The case's own coefficients: **epsilon = {eps:.6g}, beta = {beta:.6g}** "
                  f"(nothing measured to fit).", ""]
    problems = result.problems()
    if problems:
        lines += ["PIM flags this answer:", ""] + [f"- {p}" for p in problems] + [""]
    lines += ["## Analytic against simulated", ""]
    if simulated is not None:
        s = simulated
        lines += [f"pymunk settings: dt = {s.settings.dt:g} s, {s.iterations} solver iterations "
                  f"(automatic), {s.settings.contact} contact, {s.settings.start} start; "
                  f"wall time {s.wall_time * 1e3:.3g} ms. Largest error in the impact's "
                  f"velocity changes: **{rep.error:.2e}** (relative to the largest change; "
                  f"see docs/comparisons.md).", "", _md_table(by_name["crosscheck"])]
    else:
        lines += [f"The simulation failed ({sim_error.kind}): {sim_error}", ""]
    if limits:
        lines += ["Where the simulator cannot reproduce PIM here:", ""]
        lines += [f"- {t}" for t in limits] + [""]
    lines += ["## Animation", ""]
    if info is not None:
        lines += [f"[animation.mp4](animation.mp4) ({info.frames} frames at {info.fps} fps, "
                  f"{info.size[0]} x {info.size[1]} px"
                  + (", also [animation.gif](animation.gif)" if info.gif else "") + "). "
                  "Filled outlines: the pymunk simulation; dashed magenta outlines: PIM's "
                  "post-impact motion (free rigid motion from the impact configuration with "
                  "PIM's velocities and yaw rates); red: the impulse on vehicle 1 at C; green: "
                  "C, the contact plane and the normal n. "
                  f"Largest offset between ghost and simulation after the impact: "
                  f"{info.max_ghost_offset_px:.2g} px.", ""]
        if info.secondary_impact is not None:
            lines += [f"**Plausibility:** {info.secondary_impact.message()}; the animation "
                      f"marks it.", ""]
    elif anim_error is not None:
        lines += [f"No animation: the simulation failed ({anim_error.kind}): {anim_error}", ""]
    else:
        lines += ["(not written: --no-animation)", ""]
    lines += ["## The design sheet's plots", ""]
    for path in plot_files:
        rel = path.relative_to(out).as_posix()
        lines += [f"![{path.stem}]({rel})", ""]
    if study is not None:
        rec = study.recommended()
        lines += ["## Speed against error (coarse)", ""]
        lines += [f"{len(study.points)} simulator runs over dt, solver iterations, contact "
                  f"start and contact geometry; the full study is `pim speed-error {name}`.", ""]
        if rec is not None:
            its = "automatic" if rec.iterations is None else rec.iterations
            lines += [f"Recommended: dt = {rec.dt:g} s, {its} iterations "
                      f"({rec.iterations_used} sweeps), {rec.start} start, {rec.contact} "
                      f"contact: error {rec.error:.2e} in {rec.wall_time * 1e3:.3g} ms per "
                      f"impact, against PIM's {study.analytic_time * 1e3:.3g} ms per call "
                      f"({study.analytic_batch_time * 1e6:.3g} us per case in a batch).", ""]
        else:
            lines += [f"No run reached the target error {study.target:g}.", ""]
        lines += ["![speed against error](speed_error.png)", "",
                  _md_table(by_name["speed_error_pareto"]),
                  "Every run: [speed_error.csv](speed_error.csv).", ""]
    if rep.assumptions is not None:
        lines += ["## PIM's assumptions (finite-duration crush scene)", ""]
        lines += ["Each scene relaxes one of PIM's assumptions at a typical value (100 ms "
                  "contact, tyre friction 0.7, the case's outlines, friction 0.5 between the "
                  "vehicles); docs/contact-model.md has the model. The sweeps, plots and an "
                  f"animation are `pim assumptions {name}`.", ""]
        lines += [f"- {v}" for v in rep.assumptions.verdicts()] + [""]
        lines += [_md_table(by_name["assumptions"])]
    lines += ["## Files", ""]
    for path in sorted({p.relative_to(out).as_posix() for p in rep.files}):
        lines.append(f"- [{path}]({path})")
    lines += ["", "Timings: " + ", ".join(f"{k} {v:.2f} s" for k, v in rep.seconds.items()), ""]
    return "\n".join(lines)


del atomic_path
