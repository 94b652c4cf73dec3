"""The staged-test block of docs/event.md: RICSAC 10 through the event against its published
rest positions, written by ``python -m comparisons.docs event`` (with the page's first table).

No public source found gives a staged test with a secondary impact in numbers (the search:
docs/event.md, "Staged tests with secondary impacts"). The closest is RICSAC 10 (Honda CVCC
into the side of a Ford Torino at 14.9 m/s): its masses, yaw inertias, speeds, contact
plane, angles phi and measured post-impact motion are bundled (``ricsac`` dataset), its
rest positions too (:mod:`pim.io.staged_rest`), but not its CG-to-impact distances or its
outlines. Those are RICSAC 9's (the same two cars in the same front-to-side configuration,
Brach's geometry in ``ricsac9.toml``), and restitution and beta are fitted to test 10's
measured motion by :func:`pim.fit`. Its event runs, analytic and in pymunk, at the tyre
drag its published rest ranges imply, at the default tyres and without tyres.
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import cache

import numpy as np

import pim
import sim
from sim.secondary import part_of
from comparisons.report.render import markdown_table
from comparisons.report.tables import Num, Table
from pim.analysis.event import event_rest_many
from pim.io.datasets import load_ricsac
from pim.io.staged_rest import SOURCE, StagedRest, load_staged_rest, staged_rest
from pim.model.tyres import STANDARD_GRAVITY

__all__ = ["BEGIN", "END", "RICSAC", "FT", "ricsac10_fit", "ricsac10_case", "implied_drag",
           "frictions", "staged_table", "variations", "sensitivity_table", "measured_start",
           "side_slap_parts", "speed_checks", "block"]

BEGIN = ("<!-- event-staged: begin (written by `python -m comparisons.docs event`; edit "
         "comparisons/docs/event_staged.py, not this table) -->")
END = "<!-- event-staged: end -->"
#: The RICSAC collision reproduced.
RICSAC = 10
#: m per ft: the table speaks the published data's unit.
FT = 0.3048


@cache
def ricsac10_fit():
    """:func:`pim.fit` of Brach's law to RICSAC 10's measured post-impact motion, on the case
    of :func:`ricsac10_case` (its restitution and beta the fit's start only)."""
    test = {t.number: t for t in load_ricsac()}[RICSAC]
    r9 = pim.load_case("ricsac9")
    vehicles = []
    for i, heading in ((1, math.pi), (2, math.pi / 2)):
        like = getattr(r9, f"vehicle{i}")
        d, phi = math.hypot(*like.cg), getattr(test, f"phi{i}")
        cg = (-d * math.cos(heading + phi), -d * math.sin(heading + phi))
        vehicles.append(pim.Vehicle(getattr(test, f"mass{i}"), getattr(test, f"yaw_inertia{i}"),
                                    cg, getattr(test, f"velocity{i}_pre"), 0.0, heading,
                                    length=like.length, width=like.width))
    measured = pim.Measured(velocity1=test.velocity1_post, yaw_rate1=test.yaw_rate1_post,
                            velocity2=test.velocity2_post, yaw_rate2=test.yaw_rate2_post)
    return pim.fit(pim.Case(*vehicles, pim.Impact((0.0, 0.0), float(test.normal_angle),
                                                  restitution=0.5, beta=1.0),
                            measured=measured, name=f"ricsac{RICSAC}"))


@cache
def ricsac10_case() -> pim.Case:
    """RICSAC 10 as a case: the bundled test's masses, yaw inertias, impact velocities and
    angles phi (Vossou & Koulocheris) at C = (0, 0), Gamma = 0; RICSAC 9's CG-to-C distances
    and outlines (``ricsac9.toml``); restitution and beta fitted to test 10's measured
    post-impact motion (:func:`ricsac10_fit`)."""
    fit = ricsac10_fit()
    return replace(fit.case, impact=replace(fit.case.impact, restitution=float(fit.eps),
                                            beta=float(fit.beta)))


def implied_drag(published: StagedRest) -> np.ndarray:
    """Each vehicle's mean drag factor [-] from its measured post-impact speed and published
    rest range: ``v^2 / (2 g range)`` (a straight slide; a spinning car's path is longer)."""
    test = {t.number: t for t in load_ricsac()}[published.ricsac]
    speed = np.hypot(*np.array([test.velocity1_post, test.velocity2_post]).T)
    return speed ** 2 / (2 * STANDARD_GRAVITY * published.rest_range)


def frictions() -> tuple:
    """(label, tyre friction) of the runs: the mean implied drag, the default tyres, none."""
    mu = round(float(np.mean(implied_drag(staged_rest(RICSAC)))), 2)
    return ((f"tyres {mu:g} (the implied drag)", mu), ("default tyres 0.7", None),
            ("no tyres (3 s)", 0.0))


def _row(label: str, run: str, event) -> tuple:
    case = ricsac10_case()
    start = np.array([case.vehicle1.cg, case.vehicle2.cg])
    reach = np.hypot(*(event.rest_position - start).T) / FT
    turn = np.degrees(event.rest_heading - [case.vehicle1.heading, case.vehicle2.heading])
    second = Num(event.impacts[1].time, 3) if len(event.impacts) > 1 else "-"
    return (label, run, len(event.impacts), second, Num(reach[0], 1), Num(reach[1], 1),
            Num(turn[0], 0), Num(turn[1], 0), Num(event.end_time, 2))


@cache
def staged_table() -> Table:
    """RICSAC 10's event (analytic and pymunk) at each friction of :func:`frictions`: its
    impacts, each vehicle's range from impact to rest [ft] and turn [deg]; then the
    published ranges and headings."""
    case = ricsac10_case()
    rows = []
    for label, mu in frictions():
        rows.append(_row(label, "pim.event", pim.event(case, tyre_friction=mu)))
        rows.append(_row(label, "sim.simulate_event", sim.simulate_event(case, tyre_friction=mu)))
    pub = staged_rest(RICSAC)
    reach, heading = pub.rest_range / FT, np.degrees(pub.heading)
    rows.append(("published", SOURCE, "not stated", "", Num(reach[0], 1), Num(reach[1], 1),
                 f"{heading[0]:g} (at rest)", f"{heading[1]:g} (at rest)", ""))
    return Table("event-staged", f"RICSAC {RICSAC} through the event against its published "
                 f"rest positions (eps {case.impact.restitution:.3f}, beta "
                 f"{case.impact.beta:.3f} fitted to its measured motion)",
                 ("scene", "run", "impacts", "2nd impact [s]", "range 1 [ft]", "range 2 [ft]",
                  "turn 1 [deg]", "turn 2 [deg]", "end [s]"), tuple(rows), csv=False)


def variations() -> list:
    """(restitution, C shift [m]) of the inputs the data leave open: the fit's restitution
    and one standard error either side (clipped to [0, 1]) by C moved 0 or by the
    ``impact.point_x`` / ``point_y`` half-range of ``ricsac9.toml``'s ``[uncertainty]`` in
    each direction (the CG-to-C distances borrowed from RICSAC 9 are that uncertain)."""
    fit, table = ricsac10_fit(), pim.load_case("ricsac9").uncertainty.inputs
    se = fit.standard_errors.get("impact.restitution", 0.0)
    eps = [min(max(fit.eps + k * se, 0.0), 1.0) for k in (-1, 0, 1)]
    half = (table["impact.point_x"].b, table["impact.point_y"].b)
    shifts = [(i * half[0], j * half[1]) for i in (-1, 0, 1) for j in (-1, 0, 1)]
    return [(e, shift) for e in eps for shift in shifts]


@cache
def sensitivity_table() -> Table:
    """Per restitution of :func:`variations`: in how many of the nine C positions the
    event at the implied drag has a further impact, and the earliest and latest."""
    case, mu = ricsac10_case(), frictions()[0][1]
    found = {}
    for eps, (dx, dy) in variations():
        trial = replace(case, impact=replace(case.impact, restitution=eps, point=(dx, dy)))
        times = [i.time for i in pim.event(trial, tyre_friction=mu).impacts[1:]]
        found.setdefault(eps, []).append(times[0] if times else None)
    rows = []
    for eps, firsts in found.items():
        hit = [t for t in firsts if t is not None]
        rows.append((Num(eps, 3), f"{len(hit)} of {len(firsts)}",
                     Num(min(hit), 3) if hit else "-", Num(max(hit), 3) if hit else "-"))
    return Table("event-staged-sensitivity", f"RICSAC {RICSAC}'s further impact at tyres "
                 f"{mu:g} over the inputs the data leave open",
                 ("restitution", "C positions with a further impact", "earliest [s]",
                  "latest [s]"), tuple(rows), csv=False)


@cache
def measured_start() -> tuple:
    """RICSAC 9's event without tyres started from its published measured post-impact motion
    (the sheet's table, ``ricsac9.toml`` ``[measured]``) at PIM's configuration:
    ``(further impacts, time of the first [s])`` (:func:`pim.analysis.event.event_rest_many`).
    """
    case = pim.load_case("ricsac9")
    m = case.measured
    rest = event_rest_many(case, np.array([[m.velocity1, m.velocity2]]),
                           np.array([[m.yaw_rate1, m.yaw_rate2]]), tyre_friction=0.0)
    return int(rest.impacts[0]), float(rest.first_time[0])


def side_slap_parts() -> tuple:
    """At the implied drag: the parts of the two outlines that meet in the further impact
    (:func:`sim.secondary.part_of`) and each vehicle's turn since the impact [rad]."""
    case = ricsac10_case()
    ev = pim.event(case, tyre_friction=frictions()[0][1])
    impact = ev.impacts[1]
    k = int(np.searchsorted(ev.time, impact.time))
    parts, turns = [], []
    for track, vehicle in zip(ev.tracks, (case.vehicle1, case.vehicle2), strict=True):
        parts.append(part_of(track.outline, track.position[k], float(track.heading[k]),
                             impact.point))
        turns.append(float(track.heading[k] - vehicle.heading))
    return tuple(parts), tuple(turns)


def speed_checks() -> list:
    """(RICSAC number, Day's impact speed minus Neades' measured speed of vehicle 1 [m/s])
    of each identified row of the transcript."""
    ricsac = {t.number: t for t in load_ricsac()}
    return [(r.ricsac, float(r.speed[0] - ricsac[r.ricsac].speed1_measured))
            for r in load_staged_rest() if r.ricsac is not None]


def _lead() -> str:
    case, drag = ricsac10_case(), implied_drag(staged_rest(RICSAC))
    tests = {t.number: t for t in load_ricsac()}
    (part1, part2), (turn1, turn2) = side_slap_parts()
    count, first = measured_start()
    dphi = [math.degrees(abs(getattr(tests[10], f"phi{i}") - getattr(tests[9], f"phi{i}")))
            for i in (1, 2)]
    checks = ", ".join(f"RICSAC {n}: {round(d, 2) + 0.0:+.2f}" for n, d in sorted(speed_checks()))
    return (f"RICSAC {RICSAC} at {tests[10].speed1_measured:g} m/s (RICSAC 9: "
            f"{tests[9].speed1_measured:g} m/s), phi {dphi[0]:.1f} and {dphi[1]:.1f} deg from "
            f"RICSAC 9's. Restitution {case.impact.restitution:.3f} and beta "
            f"{case.impact.beta:.3f} fitted to its measured post-impact motion; the drag its "
            f"published rest ranges imply (v^2 / (2 g range)): {drag[0]:.2f} (Honda), "
            f"{drag[1]:.2f} (Torino). At the implied drag the further impact is the Honda's "
            f"{part1} against the Torino's {part2}, the Honda turned {math.degrees(turn1):.0f} "
            f"deg and the Torino {math.degrees(turn2):.0f} deg since the impact. RICSAC 9 "
            f"started from its published measured post-impact motion at PIM's configuration "
            f"(no tyres): {count} further impacts, the first after {first * 1000:.0f} ms. "
            f"Day's impact speed minus Neades' measured one [m/s]: {checks}.")


def block() -> str:
    """The generated block, markers included: the case and its checks in words, the table
    and the sensitivity table."""
    return "\n".join([BEGIN, "", _lead(), "", markdown_table(staged_table()), "",
                      markdown_table(sensitivity_table()), "", END])
