"""The figures of docs/event.md, written by ``python -m comparisons.docs event``: the analytic
event's impacts and rest positions on RICSAC 9 (without tyres and with the default ones), on
a T-bone whose struck car slaps the bullet car's side, and on a straight slide checked by
hand (between :data:`BEGIN` and :data:`END`); and how often a further impact of generated
side slaps gains energy under the default law and is solved frictionless, and why
(:func:`energy_table`, between :data:`ENERGY_BEGIN` and :data:`ENERGY_END`); the staged
test's block is :mod:`comparisons.docs.event_staged`'s; and the Monte Carlo of a reconstruction
through the event on that side slap (:func:`monte_carlo_table`: its intervals through the
event against the single-impact run-outs', the fast route against the full fit on a subset of
draws; between :data:`MC_BEGIN` and :data:`MC_END`). The rest of the page is prose. Each
table is a :class:`~comparisons.report.tables.Table` rendered by the one Markdown renderer; a
test fails when the page differs from what the code gives.
"""

from __future__ import annotations

import math
from pathlib import Path

from dataclasses import replace

import numpy as np

import pim
from sim.event_check import side_slap_case as generated_side_slap
from comparisons.report.render import markdown_table
from comparisons.report.tables import Num, Table
from comparisons.docs import event_staged
from comparisons.report.write import write_block
from pim.analysis.event import event_vehicle
from pim.analysis.event_fit import fit_through_event_many
from pim.analysis.event_samples import fit_event_samples
from pim.analysis.reconstruction import evidence_nominal, evidence_sampler, reconstruct
from pim.analysis.reconstruction_mc import reconstruction_samples, rest_draws
from pim.model.event_formula import MAX_IMPACTS, box, contact_geometry
from pim.model.evidence import Evidence, VehicleEvidence
from pim.model.tyres import STANDARD_GRAVITY

__all__ = ["COMMAND", "BEGIN", "END", "PAGE", "side_slap_case", "slide_case", "scenes",
           "with_rest_evidence", "impact_table", "block", "regenerate", "ENERGY_BEGIN",
           "ENERGY_END", "GENERATED_SCENES", "generated_side_slaps", "energy_counts",
           "energy_table", "energy_block", "MC_BEGIN", "MC_END", "MC_SAMPLES", "MC_SUBSET",
           "MC_UNKNOWN", "monte_carlo_table", "monte_carlo_block"]

COMMAND = "python -m comparisons.docs event"
BEGIN = (f"<!-- event: begin (written by `{COMMAND}`; edit comparisons/docs/event.py, not "
         "this table) -->")
END = "<!-- event: end -->"
ENERGY_BEGIN = (f"<!-- event-energy: begin (written by `{COMMAND}`; edit "
                "comparisons/docs/event.py, not this table) -->")
ENERGY_END = "<!-- event-energy: end -->"
#: How many side slaps :func:`generated_side_slaps` draws (seed 0).
GENERATED_SCENES = 300
MC_BEGIN = (f"<!-- event-mc: begin (written by `{COMMAND}`; edit comparisons/docs/event.py, "
            "not this table) -->")
MC_END = "<!-- event-mc: end -->"
#: Monte Carlo samples of the reconstruction through the event, and the draws its fast route
#: and the full fit both fit.
MC_SAMPLES, MC_SUBSET = 200, 30
#: The reconstruction's unknowns (the side slap's impact speeds) [m/s].
MC_UNKNOWN = {"vehicle1.speed": (0.0, 40.0), "vehicle2.speed": (0.0, 40.0)}
#: The page of docs/ that holds the table.
PAGE = "event.md"


def side_slap_case() -> pim.Case:
    """A T-bone: vehicle 1 (1500 kg, heading +y, 50 km/h) into the right side of vehicle 2
    (1400 kg, heading +x, 10 km/h) 0.8 m behind its CG, outlines 4.5 x 1.8 m overlapping by
    0.3 m at PIM's configuration; eps 0.2, beta 1."""
    length, width, crush, along = 4.5, 1.8, 0.3, -0.8
    v1 = pim.Vehicle(1500.0, 2500.0, (along, -width / 2 - length / 2 + crush),
                     (0.0, 50 / 3.6), 0.0, math.pi / 2, length=length, width=width)
    v2 = pim.Vehicle(1400.0, 2300.0, (0.0, 0.0), (10 / 3.6, 0.0), 0.0, 0.0, length=length,
                     width=width)
    return pim.Case(v1, v2, pim.Impact((along, -width / 2 + crush / 2), -math.pi / 2,
                                       restitution=0.2, beta=1.0), name="side slap")


def with_rest_evidence(case: pim.Case, *, position_sigma: float = 0.05,
                       heading_sigma: float = math.radians(1.0)) -> pim.Case:
    """``case`` with ``[evidence]`` for both vehicles: the rest states of its own analytic
    event (default tyres, :func:`pim.analysis.event.event_vehicle`'s geometry) measured
    with the given sigmas [m, rad]: rest evidence reached through the event at known
    post-impact motion (PIM's)."""
    ev = pim.event(case)
    vehicles = []
    for i in (1, 2):
        rv = event_vehicle(getattr(case, f"vehicle{i}"), None, None, f"vehicle{i}")
        vehicles.append(VehicleEvidence(ev.rest_position[i - 1], float(ev.rest_heading[i - 1]),
                                        rv.wheelbase, rv.track, rv.cg_to_front_axle,
                                        rv.friction, position_sigma=position_sigma,
                                        heading_sigma=heading_sigma))
    return replace(case, evidence=Evidence(*vehicles))


def slide_case() -> pim.Case:
    """A car (10 m/s) square into a barrier, its CG on the line of C: PIM (eps 0.5, beta 1)
    returns it straight back at 5 m/s."""
    car = pim.Vehicle(1500.0, 2500.0, (0.0, 0.0), (10.0, 0.0), 0.0, 0.0, length=4.5,
                      width=1.8)
    wall = pim.Vehicle.obstacle(cg=(2.7, 0.0), length=1.0, width=20.0)
    return pim.Case(car, wall, pim.Impact((2.25, 0.0), math.pi, restitution=0.5, beta=1.0),
                    name="slide")


def scenes() -> list:
    """(label, case, tyre friction) of the table."""
    ricsac = pim.load_case("ricsac9")
    return [("RICSAC 9, no tyres", ricsac, 0.0), ("RICSAC 9, tyres 0.7", ricsac, None),
            ("side slap, tyres 0.7", side_slap_case(), None),
            ("barrier slide, tyres 0.7", slide_case(), 0.7)]


def impact_table() -> Table:
    """Per scene and impact: time, C, Gamma, law, each vehicle's |delta-V| and the energy
    lost; then the rest positions (SI; the slide's hand value in the last column)."""
    rows = []
    for label, case, mu in scenes():
        ev = pim.event(case, tyre_friction=mu)
        for k, imp in enumerate(ev.impacts, start=1):
            dv = imp.delta_v_magnitude
            rows.append((label, k, Num(imp.time, 3), f"({imp.point[0]:.2f}, {imp.point[1]:.2f})",
                         Num(math.degrees(imp.normal_angle), 1), imp.law,
                         Num(dv[0] * 3.6, 1), Num(dv[1] * 3.6, 1) if np.isfinite(
                             imp.pdof[1]) else "-", Num(imp.energy_loss / 1000, 2)))
        rest = ev.rest_position
        rows.append((label, "rest", Num(ev.end_time, 2),
                     f"({rest[0, 0]:.2f}, {rest[0, 1]:.2f}) / ({rest[1, 0]:.2f}, "
                     f"{rest[1, 1]:.2f})", "", "stopped" if all(ev.stopped) else "moving",
                     "", "", ""))
    hand = 25.0 / (2 * 0.7 * STANDARD_GRAVITY)
    rows.append(("barrier slide, by hand", "rest", "", f"({-hand:.2f}, 0.00)", "",
                 "(eps v)^2 / (2 mu g)", "", "", ""))
    return Table("event", "The analytic event's impacts and rest positions",
                 ("scene", "impact", "time [s]", "C [m] / rest CGs [m]", "Gamma [deg]", "law",
                  "|dV1| [km/h]", "|dV2| [km/h]", "energy lost [kJ]"), tuple(rows),
                 csv=False)


def block() -> str:
    """The generated block of docs/event.md, markers included."""
    return "\n".join([BEGIN, "", markdown_table(impact_table()), "", END])


def generated_side_slaps(count: int = GENERATED_SCENES, seed: int = 0) -> list:
    """``count`` side slaps (:func:`sim.event_check.side_slap_case`) drawn uniformly from
    the ranges of the simulated event's random side slaps (tests/sim/test_event.py): C
    -2.2 to 2.2 m along the struck car, 5-20 m/s into 0-8 m/s, eps 0-0.5, beta 0.3-1."""
    rng = np.random.default_rng(seed)
    draws = rng.uniform([-2.2, 5.0, 0.0, 0.0, 0.3], [2.2, 20.0, 8.0, 0.5, 1.0], (count, 5))
    return [generated_side_slap(off, speed1=s1, speed2=s2, eps=eps, beta=beta)
            for off, s1, s2, eps, beta in draws]


def _before(case: pim.Case, ev, imp) -> list:
    """Both vehicles of ``case`` as the event ``ev`` has them just before its impact
    ``imp`` (its row before the impulse)."""
    k = int(np.flatnonzero(ev.time == imp.time)[0])
    return [replace(v, cg=t.position[k], heading=float(t.heading[k]),
                    velocity=imp.velocity_before[i], yaw_rate=imp.yaw_rate_before[i])
            for i, (v, t) in enumerate(zip((case.vehicle1, case.vehicle2), ev.tracks))]


def _pulling(vehicles: list, imp) -> bool:
    """Whether the sticking impulse of a further impact at eps (PIM's critical impulse,
    beta 1, of the ``vehicles`` just before it) pulls: Pn0 < 0."""
    impact = pim.Impact(imp.point, imp.normal_angle, restitution=imp.coefficients["eps"])
    return bool(pim.solve(pim.Case(*vehicles, impact), beta=1.0).critical_impulse_n < 0)


def _one_corner(vehicles: list) -> bool:
    """Whether the contact rule found one closing corner inside the other outline (a corner
    into a side: C that corner), not two (sides meeting flat: C between them)."""
    states = [(*v.cg, float(v.heading), *v.velocity, float(v.yaw_rate)) for v in vehicles]
    boxes = [box(s[0], s[1], s[2], v.length / 2 if v.cg_to_front is None else v.cg_to_front,
                 v.length, v.width) for s, v in zip(states, vehicles)]
    return contact_geometry(*boxes, *states)[5] == 1.0


def energy_counts(cases) -> dict:
    """Of the analytic events of ``cases`` (default tyres): scenes, scenes refused and why,
    further impacts, those whose friction-capped answer gains energy (solved frictionless:
    their effective beta is 0), those of them whose sticking impulse pulls
    (:func:`_pulling`) and those at one corner into a side (:func:`_one_corner`), and the
    scenes with at least one."""
    out = dict(scenes=0, energy=0, impacts_refused=0, further=0, frictionless=0, pulling=0,
               corner=0, scenes_frictionless=0)
    for case in cases:
        out["scenes"] += 1
        try:
            ev = pim.event(case)
        except pim.InputError as exc:
            out["energy" if "gains energy" in str(exc) else "impacts_refused"] += 1
            continue
        gained = [i for i in ev.impacts[1:] if i.law == "brach-capped"
                  and i.coefficients["beta"] == 0.0]
        out["further"] += len(ev.impacts) - 1
        out["frictionless"] += len(gained)
        before = [_before(case, ev, i) for i in gained]
        out["pulling"] += sum(_pulling(v, i) for v, i in zip(before, gained))
        out["corner"] += sum(_one_corner(v) for v in before)
        out["scenes_frictionless"] += bool(gained)
    return out


def energy_table() -> Table:
    """:func:`energy_counts` of :func:`generated_side_slaps`: counts and shares."""
    c = energy_counts(generated_side_slaps())

    def share(part, whole):
        return Num(100.0 * part / whole, 1) if whole else "-"

    rows = (("generated side slaps", c["scenes"], ""),
            ("refused: an impact gains energy", c["energy"], share(c["energy"], c["scenes"])),
            (f"refused: more than {MAX_IMPACTS} impacts after the first",
             c["impacts_refused"], share(c["impacts_refused"], c["scenes"])),
            ("with a further impact solved frictionless", c["scenes_frictionless"],
             share(c["scenes_frictionless"], c["scenes"])),
            ("further impacts", c["further"], ""),
            ("further impacts whose capped answer gains energy (solved frictionless)",
             c["frictionless"], share(c["frictionless"], c["further"])),
            ("of these, the sticking impulse pulls (Pn0 < 0)", c["pulling"],
             share(c["pulling"], c["frictionless"])),
            ("of these, at one corner into a side (else two sides flat)", c["corner"],
             share(c["corner"], c["frictionless"])))
    return Table("event_energy", "Further impacts that gain energy under brach-capped",
                 ("generated side slaps (default law and tyres)", "count", "share [%]"),
                 rows, csv=False)


def energy_block() -> str:
    """The generated energy block of docs/event.md, markers included."""
    return "\n".join([ENERGY_BEGIN, "", markdown_table(energy_table()), "", ENERGY_END])


def monte_carlo_table() -> Table:
    """The side slap's impact speeds reconstructed from its own event's rest positions
    (sigmas 5 cm, 1 deg), with :data:`MC_SAMPLES` Monte Carlo samples (seed 0): the truth,
    the nominal fit through the event, the 5/50/95 % with every sample fitted through the
    event, and with the samples' single-impact run-outs (the route before); the note gives
    the fits' counts and the fast route against the full fit on :data:`MC_SUBSET` draws."""
    case = with_rest_evidence(side_slap_case())
    event = reconstruct(case, unknown=MC_UNKNOWN, samples=MC_SAMPLES)
    single = reconstruction_samples(     # the samples' single-impact run-outs (the route before)
        event.case, event.fit, MC_UNKNOWN, n=MC_SAMPLES,
        post_impact=evidence_sampler(case, replace(event.post, event_fit=None)),
        extra_nominal=evidence_nominal(case, event.post))
    truth = {"vehicle1.speed": 50.0, "vehicle2.speed": 10.0}
    rows = []
    for key, label in (("vehicle1.speed", "vehicle 1"), ("vehicle2.speed", "vehicle 2")):
        a, b = event.samples.stats[key], single.stats[key]
        rows.append((label, Num(truth[key], 1), Num(event.values[key] * 3.6, 2),
                     *(Num(v * 3.6, 2) for v in (a.p5, a.p50, a.p95, b.p5, b.p50, b.p95))))
    c = event.samples.through_event
    fast, full, diff = _against_full_fit(case, event.post)
    note = (f"{MC_SAMPLES} samples through the event: {c['converged']} fits converged "
            f"({c['fast']} by secant steps, {c['refitted']} by the full fit), "
            f"{c['unconverged']} left out; {event.samples.n_used} samples used. On "
            f"{MC_SUBSET} draws of the rest evidence the fast route converged on {fast}, the "
            f"full fit from the nominal motion on {full}; where both did, their post-impact "
            f"speeds differ by at most {diff:.3f} km/h")
    return Table("event_mc", "Impact speeds [km/h] through the event's Monte Carlo",
                 ("vehicle", "true", "nominal", "5 %", "50 %", "95 %",
                  "5 % single-impact", "50 % single-impact", "95 % single-impact"),
                 tuple(rows), note=note, csv=False)


def _against_full_fit(case: pim.Case, post) -> tuple:
    """(fast route converged, full fit converged, largest post-impact speed difference
    [km/h] where both did) on :data:`MC_SUBSET` draws of the rest evidence (seed 1)."""
    rng = np.random.default_rng(1)
    rest, heading = np.zeros((MC_SUBSET, 2, 2)), np.zeros((MC_SUBSET, 2))
    for i in (1, 2):
        rest[:, i - 1], heading[:, i - 1], _ = rest_draws(
            getattr(case.evidence, f"vehicle{i}"), i, rng, MC_SUBSET)
    fit = post.event_fit
    x0 = np.array([*fit.velocity[0], fit.yaw_rate[0], *fit.velocity[1], fit.yaw_rate[1]])
    fast = fit_event_samples(post.case, x0, (rest, heading))
    x, full = fit_through_event_many(post.case, np.repeat(x0[None], MC_SUBSET, 0),
                                     (rest, heading))
    both = fast.converged & full.converged
    speeds = [3.6 * np.hypot(m[:, [0, 3]], m[:, [1, 4]]) for m in (fast.x, x)]
    return (int(fast.converged.sum()), int(full.converged.sum()),
            float(np.max(np.abs(speeds[0] - speeds[1])[both])))


def monte_carlo_block(table: Table | None = None) -> str:
    """The generated Monte Carlo block of docs/event.md, markers included (of ``table``,
    default :func:`monte_carlo_table`)."""
    table = monte_carlo_table() if table is None else table
    return "\n".join([MC_BEGIN, "", markdown_table(table), "", table.note + ".", "", MC_END])


def regenerate(docs_dir) -> list[Path]:
    """Rewrite the tables of ``docs_dir/event.md`` (between their markers): this module's
    (the impacts, the energy figures, the Monte Carlo through the event) and the staged
    test's (:mod:`comparisons.docs.event_staged`)."""
    page = Path(docs_dir) / PAGE
    write_block(page, BEGIN, END, block())
    write_block(page, ENERGY_BEGIN, ENERGY_END, energy_block())
    write_block(page, MC_BEGIN, MC_END, monte_carlo_block())
    return [write_block(page, event_staged.BEGIN, event_staged.END, event_staged.block())]
