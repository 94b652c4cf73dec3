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

from pim.model.plausibility import secondary_contact
from comparisons.report.pre_impact import (
    pre_impact_html,
    pre_impact_json,
    pre_impact_lines,
    pre_impact_markdown,
    pre_impact_rows,
)
from pim.analysis.pre_impact_speeds import reconstruction_pre_impact
from pim.analysis.reconstruction import Reconstruction
from pim.analysis.reconstruction import reconstruct as run_reconstruction
from pim.io import html
from pim.io.files import save_figure, write_text
from pim.io.inertia_data import estimate_notes, estimate_records
from pim.io.output import output_folder, worker_pool
from pim.io.units import convert, display_units
from pim.model.evidence import UNKNOWN_KINDS
from pim.model.law import LAW_NAMES, LAW_PARAMETERS
from pim.model.numbers import InputError
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
           "driver_lines", "budget", "DEFAULT_MAX_MINUTES", "runout_contact"]

#: Default of --max-minutes: the longest Monte Carlo with run-out evidence run without
#: being asked [min].
DEFAULT_MAX_MINUTES = 30.0


def law_line(rec: Reconstruction) -> str:
    """The impact law the inverse PIM applied (one line for the report and the CLI)."""
    law = rec.fit.law if rec.fit is not None else (rec.case.impact.law or "brach")
    return f"Impact law: {LAW_NAMES[law]} ({LAW_PARAMETERS[law]}) (docs/impact-laws.md)."


def reconstruction_rows(rec: Reconstruction, units: str) -> list[dict]:
    """Table rows in ``units``: name, unit, value, p5, p50, p95, main driver."""
    rows = []
    lower = rec.fit.lower_bounds if rec.fit is not None else {}
    for r in rec.table():
        values, unit = convert([r["value"], r["p5"], r["p50"], r["p95"]], _kind(r["name"]),
                               units)
        driver = r["drivers"][0] if r["drivers"] else ("", float("nan"))
        rows.append({"name": r["name"], "unit": unit, "value": float(values[0]),
                     "p5": float(values[1]), "p50": float(values[2]), "p95": float(values[3]),
                     "driver": driver[0], "driver_index": float(driver[1]),
                     "lower_bound": r["name"] in lower})
    if rec.momentum is not None:
        m = rec.momentum
        for i, (s, sd) in enumerate(((m.speed1, m.sigma1), (m.speed2, m.sigma2)), start=1):
            values, unit = convert([s, sd], "impact_speed", units)
            rows.append({"name": f"momentum check: vehicle{i}.speed", "unit": unit,
                         "value": float(values[0]), "p5": float("nan"), "p50": float("nan"),
                         "p95": float("nan"), "driver": f"1 sd = {float(values[1]):.3g} {unit}",
                         "driver_index": float("nan"), "sd": float(values[1])})
    return rows


def _kind(name: str) -> str:
    """Unit kind of an unknown (impact speeds in the system's impact-speed unit)."""
    return ("impact_speed" if name.endswith(".speed")
            else UNKNOWN_KINDS.get(name, "dimensionless"))


def evidence_drivers(rec: Reconstruction, units: str) -> dict:
    """Which evidence drove each unknown: name -> {"sd", "unit", "shares": {evidence: share}}
    in ``units`` (the standard error from the weighted Jacobian and each evidence group's
    share of the variance, :func:`pim.analysis.free_fit.variance_shares`); empty without
    standard deviations or a fit. A vehicle's post-impact motion from its run-out is called
    its rest position."""
    fit = rec.fit
    if fit is None or not fit.evidence_shares:
        return {}
    runouts = rec.post.runouts if rec.post else {}

    def label(group: str) -> str:
        for i in runouts:
            if group == f"vehicle{i} post-impact motion":
                return f"vehicle{i} rest position (run-out)"
        return group

    out = {}
    for key, shares in fit.evidence_shares.items():
        sd, unit = convert(fit.standard_errors[key], _kind(key), units)
        out[key] = {"sd": float(sd), "unit": unit,
                    "shares": {label(g): v for g, v in sorted(shares.items(),
                                                              key=lambda kv: -kv[1])}}
    return out


def driver_lines(drivers: dict) -> list[str]:
    """One line per unknown: its standard error and the evidence shares, largest first."""
    return [f"{key} (1 sd = {d['sd']:.3g} {d['unit']}): " + ", ".join(
        f"{g} {100 * v:.0f} %" for g, v in d["shares"].items() if v >= 0.005)
        for key, d in drivers.items()]


def crush_lines(rec: Reconstruction, units: str) -> list[str]:
    """Per vehicle with a crush profile: crush energy (times its force-balance factor), EES,
    and the crush-energy delta-V beside the solution's, in ``units``."""
    lines = []
    for c in rec.crush:
        (e, sd, ef), e_unit = convert([c.energy, c.energy_sigma, c.energy * c.factor],
                                      "energy", units)
        (ees, dv, dvm), v_unit = convert([c.ees, c.delta_v_crush, c.delta_v_model],
                                         "impact_speed", units)
        lines.append(f"vehicle{c.vehicle}: crush energy {e:.4g} +- {sd:.2g} {e_unit} x "
                     f"force-balance {c.factor:.3f} = {ef:.4g} {e_unit}; EES {ees:.4g} "
                     f"{v_unit}; delta-V from crush {dv:.4g} {v_unit} (PIM solution "
                     f"{dvm:.4g} {v_unit})")
    return lines


def spread_text(row: dict, samples: int, sep: str = ", ") -> str:
    """"[p5, p50, p95]" of a table row, or why there is none (never "[nan, nan, nan]")."""
    if row["name"].startswith("momentum check"):
        return f"({row['driver']})"
    if not samples:
        return "(5/50/95 %: not computed, --samples 0)"
    if row["p5"] != row["p5"]:
        return "(5/50/95 %: no usable Monte Carlo sample)"
    return f"[{row['p5']:.4g}{sep}{row['p50']:.4g}{sep}{row['p95']:.4g}]"


def tyre_models_line(rec: Reconstruction) -> str:
    """Which tyre law each vehicle's run-out used (one line for the report and the CLI)."""
    return "Run-out tyre model: " + ", ".join(
        f"vehicle {i} {fit.tyre_model}" for i, fit in sorted(rec.post.runouts.items())) + "."


def _driver(row: dict) -> str:
    """The main driver of a row's spread, with its index when it has one."""
    index = row["driver_index"]
    return f"{row['driver']} ({index:.2f})" if index == index else row["driver"]


def _spread_drivers(rec: Reconstruction) -> list[str]:
    """One line per unknown: the inputs that drive its spread, with their indices."""
    lines = []
    for r in rec.table():
        top = ", ".join(f"{k} {v:.2f}" for k, v in r["drivers"][:4] if v > 0.005)
        lines.append(f"{r['name']}: {top or 'no single input dominates'}")
    return lines


def _report(rec: Reconstruction, rows: list[dict], units: str, with_scene: bool,
            with_video: bool = False, pre_impact=()) -> str:
    n = rec.samples.n if rec.samples else 0
    source = ("the run-out inverse of each vehicle's rest evidence" if rec.post else
              "the case's [measured] post-impact motion")
    lines = [f"# Reconstruction of {rec.case.name}", "", law_line(rec), "",
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
        spread = (f"{r['p5']:.4g} | {r['p50']:.4g} | {r['p95']:.4g}" if r["p5"] == r["p5"]
                  else " | ".join(["-"] * 3))
        lines.append(f"| {r['name']} | {_value(r)} | {spread} | {r['unit']} | {driver} |")
    lines.append("")
    estimates = estimate_notes(rec.case, units)
    if estimates:
        lines += ["Estimated inputs (drawn with their scatter in the Monte Carlo unless the "
                  "`[uncertainty]` table says otherwise):", ""]
        lines += [f"- {line}" for line in estimates] + [""]
    lines += pre_impact_markdown(pre_impact)
    if rec.samples:
        lines += ["## What drives each unknown's spread", "",
                  "First-order variance indices (correlation ratio) of the sampled inputs.", ""]
        lines += [f"- {line}" for line in _spread_drivers(rec)]
        lines.append("")
    if rec.crush:
        lines += ["## Crush energy", ""] + [f"- {c}" for c in crush_lines(rec, units)] + [""]
    drivers = driver_lines(evidence_drivers(rec, units))
    if drivers:
        lines += ["## Which evidence drove each unknown", "",
                  "Share of each unknown's variance from each piece of evidence (weighted "
                  "Jacobian at the solution: (J^T J)^-1 split by evidence).", ""]
        lines += [f"- {line}" for line in drivers] + [""]
    if rec.goodness is not None:
        lines += [f"Goodness of fit: {rec.goodness.summary()}.", ""]
    lines += [f"- {m}" for m in rec.messages] or ["No warnings."]
    if with_scene:
        lines += ["", "![scene](scene.png)"]
    if with_scene and with_video:
        lines += ["", "Animation from the impact to rest: [reconstruction.mp4](reconstruction.mp4)"]
    return "\n".join(lines) + "\n"


def _value(row: dict) -> str:
    """A row's value; ">= X" where it only has a lower bound."""
    return (">= " if row.get("lower_bound") else "") + f"{row['value']:.4g}"


def _json(case, rows: list[dict], samples: int, messages, units: str) -> dict:
    """``--json``'s data: every value in ``units`` with its unit (NaN becomes null)."""
    def pick(r, keys):
        return {"unit": r["unit"], **{k: r[k] for k in keys}}

    unknowns = [r for r in rows if not r["name"].startswith("momentum check")]
    momentum = [r for r in rows if r["name"].startswith("momentum check")]
    return {"case": case.name, "units": display_units(units).to_json(), "samples": samples,
            "messages": messages, "estimates": estimate_records(case, units),
            "unknowns": {r["name"]: pick(r, ("value", "p5", "p50", "p95", "lower_bound"))
                         for r in unknowns},
            "momentum_check": {r["name"].removeprefix("momentum check: "): pick(r, ("value",))
                               | {"sd": r["sd"]} for r in momentum}}


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
    """Reconstruct CASE's unknowns (e.g. the impact speeds) from its evidence.

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
            rec, rows, pre, found = _reconstruct(case, samples, seed, workers, units, as_json,
                                                 say, budget(samples, workers, max_minutes),
                                                 allow_inadmissible)
        if tmp is not None:
            _write_folder(tmp, rec, rows, units, video, pre)
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


def _reconstruct(case, samples, seed, workers, units, as_json, say=None, estimate=None,
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
        for r in rows:
            click.echo(f"{r['name']:32s} {_value(r):>10s} {r['unit']}  "
                       f"{spread_text(r, samples)}")
        for line in pre_impact_lines(pre):
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
    """reconstruction.csv, scene.png, reconstruction.mp4, report.html and report.md into
    ``directory``."""
    csv = ["name,unit,value,p5,p50,p95,main_driver"] + [
        f"{r['name']},{r['unit']},{r['value']:.6g},{r['p5']:.6g},{r['p50']:.6g},"
        f"{r['p95']:.6g},{r['driver']}" for r in rows] + [
        f"{r['name']},{r['unit']},{r['value']:.6g},{r['p5']:.6g},{r['p50']:.6g},"
        f"{r['p95']:.6g},\"{r['what']}\"" for r in pre]
    write_text(directory / "reconstruction.csv", "\n".join(csv) + "\n")
    if rec.post is not None:
        save_figure(reconstruction_figure(rec.post, units), directory / "scene.png")
        if video:
            write_reconstruction_mp4(rec.post, directory / "reconstruction.mp4", units=units)
    write_text(directory / "report.html", _html_report(rec, rows, directory, video, pre,
                                                       units))
    write_text(directory / "report.md", _report(rec, rows, units, rec.post is not None, video,
                                                pre))


def _html_report(rec: Reconstruction, rows: list[dict], directory: Path, video: bool,
                 pre=(), units: str = "si") -> str:
    """report.html: the table, what drives each spread, the warnings, the scene and the
    animation inline (read from ``directory``), by the blocks of :mod:`pim.io.html`."""
    def g(x):
        return "" if x != x else f"{x:.4g}"          # no percentiles: an empty cell

    cells = [(r["name"], _value(r) if r["value"] == r["value"] else "", g(r["p5"]),
              g(r["p50"]), g(r["p95"]), r["unit"],
              _driver(r)) for r in rows]
    n = rec.samples.n if rec.samples else 0
    body = [html.paragraph(
        "Post-impact motion from " + ("the run-out inverse of each vehicle's rest evidence"
                                      if rec.post else "the case's [measured] post-impact "
                                      "motion") + "; unknowns by the inverse PIM; "
        + (f"5/50/95 % from a Monte Carlo of {n} samples ({rec.samples.n_used} used)."
           if n else "no Monte Carlo (--samples 0).") + " " + law_line(rec)),
        *([html.paragraph(tyre_models_line(rec))] if rec.post else []),
        html.table(("unknown", "value", "5 %", "50 %", "95 %", "unit",
                    "main driver of the spread"), cells, title="Reconstructed unknowns",
                   note="CSV: `reconstruction.csv`", id="table-reconstruction"),
        html.bullets(rec.messages or ["No warnings."], cls="messages")]
    estimates = estimate_notes(rec.case, units)
    if estimates:
        body += [html.paragraph("Estimated inputs (drawn with their scatter in the Monte "
                                "Carlo unless the `[uncertainty]` table says otherwise):"),
                 html.bullets(estimates)]
    if rec.crush:
        body += [html.paragraph("Crush energy:"), html.bullets(crush_lines(rec, units))]
    drivers = driver_lines(evidence_drivers(rec, units))
    if drivers:
        body += [html.paragraph("Which evidence drove each unknown (share of its variance):"),
                 html.bullets(drivers)]
    sections = [html.section("Results", body, id="results", cls="keep")]
    sections += pre_impact_html(pre)
    if rec.samples:
        sections.append(html.section("What drives each unknown's spread", [html.paragraph(
            "First-order variance indices (correlation ratio) of the sampled inputs."),
            html.bullets(_spread_drivers(rec))], id="drivers"))
    if (directory / "scene.png").exists():
        media = [html.figure(directory / "scene.png", alt="scene", caption="`scene.png`")]
        mp4 = directory / "reconstruction.mp4"
        if video and mp4.exists():
            media.append(html.video(mp4, caption="From the impact to rest: "
                                    "`reconstruction.mp4`.", still=html.still_frame(mp4, 0.5)))
        sections.append(html.section("Scene and animation", media, id="scene"))
    return html.page(f"Reconstruction of {rec.case.name}", sections,
                     subtitle="Written by `pim reconstruct` (the same as text: `report.md`).",
                     contents=[("results", "Results"),
                               *([("pre-impact", "Before the impact")] if pre else []),
                               ("drivers", "Drivers"), ("scene", "Scene")][:len(sections)],
                     generator="pim reconstruct")
