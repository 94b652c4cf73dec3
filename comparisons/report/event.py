"""``pim event``'s report: the whole event from the approach to rest, answer first.

:func:`run_event` computes the event and its cross-check: the analytic event
(:func:`pim.event`) with the pymunk event (:func:`sim.simulate_event`)
as its cross-check, or, with ``single_impact``, PIM's single impact and its decelerated
run-out against the rigid scene's simulation of that one impact (the collision's animation
until now). :func:`write_event` writes the folder's files through the one report pipeline:
``event.mp4`` (the one renderer, the cross-check solid and the analytic event as a ghost),
``plan.png`` (:func:`comparisons.animation.plan.plan_view`), ``timeline.csv`` (every
sample of the event in the user's units, each column's unit in its header),
``impacts.csv``, ``report.html`` and ``report.md``. :func:`event_json` is ``--json``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import pim
import sim
from comparisons.animation.collision import Framing, build_renderer, event_renderer, \
    measured_rest
from comparisons.animation.plan import plan_view
from comparisons.animation.render import Renderer, write_animation
from comparisons.report.document import Cards, Card, Document, Figure, Paragraph, Section, \
    Video
from pim.model.number_format import format_number
from comparisons.report.tables import Table
from comparisons.report.write import write_document
from pim.io.files import save_figure
from pim.io.units import DisplayUnits, convert, unit_scale
from pim.model.event import DEFAULT_APPROACH, Event

__all__ = ["EventRun", "run_event", "event_json", "event_document", "timeline_table",
           "impacts_table", "write_event", "event_lines", "crosscheck_table",
           "CROSSCHECK_GROUPS"]


@dataclass(frozen=True)
class EventRun:
    """An event with its cross-check.

    Attributes
    ----------
    case : pim.Case
        The case.
    event : Event
        The answer: the analytic event (:func:`pim.event`), sampled as it was stored.
    check : Event or None
        The cross-check (the other producer's event).
    tyre : str
        The tyre friction and its source, in words.
    single_impact : bool
        PIM's single impact (``--single-impact``) rather than the whole event.
    renderer : Renderer
        The animation's frames (the cross-check solid, the answer as a ghost).
    crosscheck : sim.EventCheck or None
        ``event`` against ``check`` (:func:`sim.event_crosscheck`) at each impact and at
        rest; None without a cross-check.
    """

    case: pim.Case
    event: Event
    check: Event | None
    tyre: str
    single_impact: bool
    renderer: Renderer
    crosscheck: object = None


def _whole(case, tyre, approach, units, fps) -> EventRun:
    """The whole event: the analytic one, pymunk's as its cross-check."""
    renderer, analytic, simulated = event_renderer(
        case, framing=Framing(before=approach, fps=fps), tyre=tyre, units=units)
    return EventRun(case, analytic, simulated, renderer.look.note, False, renderer,
                    sim.event_crosscheck(analytic, simulated))


def _single(case, tyre, approach, units, fps) -> EventRun:
    """PIM's single impact and its run-out against the rigid scene's simulation."""
    eps, beta = sim.scene.resolve_coefficients(case, None, None)
    renderer = build_renderer(case, eps, beta, tyre=tyre, units=units,
                              framing=Framing(before=approach, fps=fps))
    return EventRun(case, renderer.ghost, renderer.sim, renderer.look.note, True, renderer,
                    sim.event_crosscheck(renderer.ghost, renderer.sim))


def run_event(case: pim.Case, *, tyre: float | None = None,
              approach: float = DEFAULT_APPROACH, single_impact: bool = False,
              units="si", fps: int = 30) -> EventRun:
    """The event of ``case`` and its cross-check (module notes); ``tyre`` [-] the tyre
    friction (None: the case's evidence, else the default), ``approach`` [s] the time shown
    before the first impact."""
    make = _single if single_impact else _whole
    return make(case, tyre, approach, units, fps)


def _impact_rows(event: Event, units) -> list[dict]:
    """Each impact in the user's units (JSON and the impacts table)."""
    rows = []
    for k, imp in enumerate(event.impacts, start=1):
        point, length = convert(imp.point, "length", units)
        dv, speed = convert(imp.delta_v, "velocity", units)
        dvm, _ = convert(imp.delta_v_magnitude, "velocity", units)
        energy, e_unit = convert(imp.energy_loss, "energy", units)
        rows.append({"number": k, "time": float(imp.time),
                     "C": [float(v) for v in point],
                     "Gamma": float(np.degrees(imp.normal_angle)), "law": imp.law,
                     "coefficients": {n: float(v) for n, v in imp.coefficients.items()},
                     "delta_v": [[float(v) for v in row] for row in dv],
                     "delta_v_magnitude": [float(v) for v in dvm],
                     "pdof": [None if np.isnan(p) else float(np.degrees(p))
                              for p in imp.pdof],         # None: a fixed obstacle
                     "energy_loss": float(energy), "source": imp.source,
                     "units": {"length": length, "speed": speed, "energy": e_unit,
                               "angle": "deg", "time": "s"}})
    return rows


def _rest_rows(event: Event, units) -> list[dict]:
    position, length = convert(event.rest_position, "length", units)
    return [{"vehicle": i + 1, "position": [float(v) for v in position[i]],
             "heading": float(np.degrees(event.rest_heading[i])),
             "stopped": bool(event.stopped[i]), "units": {"length": length, "angle": "deg"}}
            for i in range(2)]


def _differences(run: EventRun, units) -> dict | None:
    """The cross-check's differences at each impact and at rest, in the user's units
    (:meth:`sim.event_check.EventCheck.to_dict`)."""
    return None if run.crosscheck is None else run.crosscheck.to_dict(units)


#: How the cross-check's table splits on a screen (the impact, then each vehicle).
CROSSCHECK_GROUPS = (("The impact", ("time", "time difference", "C apart",
                                     "Gamma difference")),
                     ("Each vehicle", ("delta-V difference", "PDOF difference", "CG apart",
                                       "heading difference", "speed difference before",
                                       "speed difference after")))


def _check_rows(check, units) -> list[tuple]:
    """Rows of :func:`crosscheck_table`: each pair of impacts per vehicle, each impact
    without a partner, each vehicle at rest."""
    length, speed = unit_scale("length", units)[0], unit_scale("velocity", units)[0]
    deg = math.degrees(1.0)
    rows = []
    for d in check.impacts:
        for i in (0, 1):
            rows.append((f"impact {d.index}, vehicle {i + 1}", float(d.times[0]), d.time,
                         d.point * length, d.normal_angle * deg, d.delta_v[i] * speed,
                         d.pdof[i] * deg, d.position[i] * length, d.heading[i] * deg,
                         d.speed_before[i] * speed, d.speed_after[i] * speed))
    for u in check.unmatched:
        rows.append((f"impact {u.index} ({u.event} only)", u.time) + (None,) * 9)
    end = float(check.trajectory.time[-1]) if len(check.trajectory.time) else None
    for i in (0, 1):
        rows.append((f"rest, vehicle {i + 1}", end, None, None, None, None, None,
                     check.rest_position[i] * length, check.rest_heading[i] * deg, None,
                     check.rest_speed[i] * speed))
    return rows


def crosscheck_table(check, units) -> Table:
    """The cross-check (:func:`sim.event_crosscheck`, ``a - b``) at each impact and at
    rest in ``units``: the impact's time, C and Gamma, each vehicle's delta-V, PDOF, CG,
    heading and speeds at it, the impacts without a partner, the rest."""
    a, b = check.sources
    length, speed = unit_scale("length", units)[1], unit_scale("velocity", units)[1]
    columns = ("at", "time [s]", "time difference [s]", f"C apart [{length}]",
               "Gamma difference [deg]", f"delta-V difference [{speed}]",
               "PDOF difference [deg]", f"CG apart [{length}]", "heading difference [deg]",
               f"speed difference before [{speed}]", f"speed difference after [{speed}]")
    note = (f"The {a} event minus the {b} event; {check.count_text()}. Time: the {a} "
            f"event's. delta-V difference: the length of the difference of the delta-V "
            f"vectors; CG apart: the distance between the CGs at each event's own impact "
            f"(at rest: the rest positions); speeds just before and after the impact (at "
            f"rest: the last sample's).")
    return Table("event_crosscheck", f"The {a} event against the {b} event, at each impact "
                 f"and at rest", columns, tuple(_check_rows(check, units)), note=note,
                 groups=CROSSCHECK_GROUPS)


def event_json(run: EventRun, units: DisplayUnits) -> dict:
    """``pim event --json``: impacts, rest, the approach's duration and the cross-check's
    differences, in ``units`` (named in ``units``)."""
    return {"case": run.case.name, "units": units.to_json(), "source": run.event.source,
            "single_impact": run.single_impact, "tyre_friction": run.tyre,
            "approach_duration": run.event.approach_duration, "end_time": run.event.end_time,
            "impacts": _impact_rows(run.event, units), "rest": _rest_rows(run.event, units),
            "crosscheck": _differences(run, units), "notes": list(run.event.notes)}


def timeline_table(event: Event, units) -> Table:
    """Every sample of ``event`` in ``units``, each column's unit in its header
    (``timeline.csv``; not shown in the page)."""
    length, speed = unit_scale("length", units), unit_scale("velocity", units)
    columns = ["time [s]", "phase"]
    for i in (1, 2):
        columns += [f"x{i} [{length[1]}]", f"y{i} [{length[1]}]", f"heading{i} [deg]",
                    f"vx{i} [{speed[1]}]", f"vy{i} [{speed[1]}]", f"yaw_rate{i} [deg/s]"]
    scales = [length[0], length[0], math.degrees(1.0), speed[0], speed[0], math.degrees(1.0)]
    rows = []
    for r in event.records():
        row = [r["time"], r["phase"]]
        for i in (1, 2):
            row += [r[f"{k}{i}"] * s for k, s in zip(("x", "y", "heading", "vx", "vy",
                                                       "yaw_rate"), scales, strict=True)]
        rows.append(tuple(row))
    return Table("timeline", "The event's timeline", tuple(columns), tuple(rows),
                 show=False, note="Every sample of the event (SI inside, shown in the "
                                  "report's units).")


def impacts_table(event: Event, units) -> Table:
    """The impacts in time order: time, C, Gamma, law, delta-V and PDOF per vehicle."""
    rows = _impact_rows(event, units)
    u = rows[0]["units"] if rows else {"length": "", "speed": "", "energy": ""}
    columns = ("impact", "time [s]", f"C x [{u['length']}]", f"C y [{u['length']}]",
               "Gamma [deg]", "law", f"delta-V 1 [{u['speed']}]", "PDOF 1 [deg]",
               f"delta-V 2 [{u['speed']}]", "PDOF 2 [deg]", f"energy lost [{u['energy']}]")
    return Table("impacts", "The impacts, in time order", columns, tuple(
        (r["number"], r["time"], *r["C"], r["Gamma"],
         r["law"] + " " + ", ".join(f"{k} = {format_number(v)}"
                                    for k, v in r["coefficients"].items()),
         r["delta_v_magnitude"][0], r["pdof"][0], r["delta_v_magnitude"][1], r["pdof"][1],
         r["energy_loss"]) for r in rows))


def _answer(run: EventRun, units) -> Cards:
    """The answer: the number of impacts, each vehicle's rest position."""
    cards = [Card("impacts", str(len(run.event.impacts)),
                  ", ".join(f"{format_number(i.time, sig=3)} s" for i in run.event.impacts))]
    for r in _rest_rows(run.event, units):
        x, y = (format_number(v) for v in r["position"])
        cards.append(Card(f"rest, vehicle {r['vehicle']}",
                          f"({x}, {y}) {r['units']['length']}",
                          f"heading {format_number(r['heading'])} deg"
                          + ("" if r["stopped"] else ", still moving at the end")))
    return Cards(tuple(cards))


def event_document(run: EventRun, units, media=()) -> Document:
    """The report: the answer (impacts, rest), the impacts table, the plan view and video,
    the cross-check, the notes."""
    what = ("PIM's single impact and its run-out (--single-impact)" if run.single_impact
            else "the whole event: approach, every impact, run-out to rest")
    check = _differences(run, units)
    check_blocks = (Paragraph(f"{run.tyre}. No cross-check."),) if check is None else (
        Paragraph(f"{run.tyre}. Cross-check ({run.event.source} against "
                  f"{run.check.source}): rest positions differ by "
                  f"{', '.join(format_number(v) for v in check['rest_position'])} "
                  f"{check['units']['length']}, rest headings by "
                  f"{', '.join(format_number(v) for v in check['rest_heading'])} deg; "
                  f"{check['counts']}."), crosscheck_table(run.crosscheck, units))
    sections = (
        Section("answer", "Answer", (_answer(run, units), impacts_table(run.event, units))),
        Section("event", "The event", (*media, *check_blocks)),
        Section("timeline", "Timeline", (timeline_table(run.event, units),
                                         Paragraph("timeline.csv: every sample."))),
    )
    if run.event.notes:
        sections += (Section("notes", "Notes", tuple(Paragraph(n) for n in run.event.notes)),)
    return Document(f"{run.case.name or 'case'}: {what}", "pim event", sections,
                    subtitle=f"Units: {units}.")


def write_event(run: EventRun, folder, units, progress=None) -> list[Path]:
    """event.mp4, plan.png and the report (through the one pipeline) into ``folder``."""
    folder = Path(folder)
    info = write_animation(run.renderer, folder / "event.mp4", progress=progress)
    save_figure(plan_view(run.event, units=units, measured_rest=measured_rest(run.case),
                          title=f"{run.case.name or 'case'}: {run.event.source} event"),
                folder / "plan.png")
    media = (Figure("plan.png", "plan view", "The event in plan view."),
             Video("event.mp4", "The event from the approach to rest.", info.frames,
                   info.fps, info.size))
    return [info.path, folder / "plan.png",
            *write_document(event_document(run, units, media), folder)]


def event_lines(run: EventRun, units) -> list[str]:
    """What ``pim event`` prints: each impact, each rest position."""
    lines = []
    for r in _impact_rows(run.event, units):
        dv = ", ".join(f"vehicle {i + 1} {format_number(v)} {r['units']['speed']} "
                       f"(PDOF {format_number(p)} deg)"
                       for i, (v, p) in enumerate(zip(r["delta_v_magnitude"], r["pdof"],
                                                      strict=True)) if p is not None)
        lines.append(f"impact {r['number']} at t = {format_number(r['time'], sig=3)} s: "
                     f"delta-V {dv}")
    for r in _rest_rows(run.event, units):
        x, y = (format_number(v) for v in r["position"])
        lines.append(f"rest, vehicle {r['vehicle']}: ({x}, {y}) {r['units']['length']}, "
                     f"heading {format_number(r['heading'])} deg")
    return lines
