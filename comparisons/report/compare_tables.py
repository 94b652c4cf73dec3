"""The tables and key figures of ``pim compare``'s report, typed and in the user's units.

What a reconstruction hands on (:func:`estimates`: each vehicle's delta-V, PDOF, speeds,
yaw rates and the energy, each with its 5-95 % interval when the case has an
``[uncertainty]`` table) is computed once and shown twice: as the cards the report opens with
(:func:`answer_cards`) and as the results table (:func:`results_table`). Every value shows
the digits its interval allows (two significant digits of the half-width,
:func:`pim.model.number_format.interval_decimals`; a component borrows its
magnitude's), round-off is 0 (:func:`pim.model.number_format.round_off`, against the
scale of its quantity: the closing speed, the kinetic energy before the impact), and the CSV
keeps full precision. Then the fit's misfit (:func:`misfit_table`, :func:`misfit_sentence`),
the coefficients (:func:`fit_table`), the inputs (:func:`inputs_table`) and the speeds
before the impact (:func:`pre_impact_table`); the simulator's agreement is
:func:`comparisons.report.compare.crosscheck_table`. Nothing here imports the simulator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import pim
from comparisons.report.document import Card, Cards
from pim.model.number_format import format_number, interval_decimals, round_off
from comparisons.report.pre_impact import TITLE as PRE_IMPACT_TITLE
from comparisons.report.pre_impact import pre_impact_rows
from comparisons.report.tables import Num, Table
from pim.analysis.misfit import NOMINAL_SIGMAS, POOR, Misfit
from pim.analysis.pre_impact_speeds import case_pre_impact
from pim.io.units import convert, display_units
from pim.model.geometry import radius_of_gyration
from pim.model.result_table import summarize

__all__ = ["Estimate", "estimates", "answer_cards", "results_table", "inputs_table",
           "fit_table", "pre_impact_table", "misfit_table",
           "misfit_sentence", "RESULT_ROWS", "roundoff_scales"]


def _f(x) -> float:
    return float(np.asarray(x, float).reshape(()))


#: Rows of the results table: (key of :func:`pim.model.result_table.summarize`, unit kind,
#: Monte Carlo output per vehicle or None, key of the row whose interval sets the digits).
RESULT_ROWS = (
    ("delta_v", "speed", ("delta_v1_magnitude", "delta_v2_magnitude"), None),
    ("delta_v_x", "velocity", None, "delta_v"),
    ("delta_v_y", "velocity", None, "delta_v"),
    ("pdof", "angle", ("pdof1", "pdof2"), None),
    ("clock", None, None, None),
    ("speed", "speed", ("speed1", "speed2"), None),
    ("velocity_x", "velocity", None, "speed"),
    ("velocity_y", "velocity", None, "speed"),
    ("yaw_rate", "angular_velocity", ("yaw_rate1", "yaw_rate2"), None),
    ("energy_loss", "energy", ("energy_loss",), None),
    ("crush_normal", "energy", None, "energy_loss"),
    ("crush_tangential", "energy", None, "energy_loss"),
    ("tangential_share", "percent", None, None))


@dataclass(frozen=True)
class Estimate:
    """One value of the answer in display units, with its 5-95 % interval.

    Attributes
    ----------
    label : str
        What it is ("|delta-V|").
    value : float or None
        The value (None: the quantity does not exist, e.g. a fixed obstacle's PDOF).
    low, high : float
        The 5 % and 95 % points (NaN without a Monte Carlo).
    decimals : int or None
        Decimal places shown (None: :data:`pim.model.number_format.SIGNIFICANT`
        significant digits).
    unit : str
        Display unit.
    """

    label: str
    value: float | None
    low: float
    high: float
    decimals: int | None
    unit: str

    def cell(self) -> Num | None:
        """The value as a table cell."""
        return None if self.value is None else Num(self.value, self.decimals)

    def bound(self, x: float) -> Num | None:
        """An interval end as a table cell."""
        return None if x != x else Num(x, self.decimals)

    def text(self) -> str:
        """The value in the report's number format."""
        return format_number(self.value, decimals=self.decimals)

    def interval(self) -> str:
        """"LOW to HIGH" with the value's decimals ("" without an interval)."""
        if self.low != self.low:
            return ""
        return (f"{format_number(self.low, decimals=self.decimals)} to "
                f"{format_number(self.high, decimals=self.decimals)}")


def roundoff_scales(result: pim.Result, units: str) -> dict:
    """The scale of each unit kind of the answer, in display units: what a value must be
    compared with to tell round-off from a result (the larger impact speed, the kinetic
    energy before the impact, the yaw rate that speed gives at the smaller radius of
    gyration, half a turn, 100 %)."""
    case = result.case
    speed = max(float(np.hypot(*np.asarray(v.velocity, float).reshape(2)))
                for v in (case.vehicle1, case.vehicle2))
    radii = [float(radius_of_gyration(v.mass, v.yaw_inertia))
             for v in (case.vehicle1, case.vehicle2) if not bool(np.asarray(v.fixed))]
    radius = min(r for r in radii if r > 0) if any(r > 0 for r in radii) else math.nan

    def shown(x, kind):
        return float(convert(x, kind, units)[0])

    return {"velocity": shown(speed, "velocity"), "speed": shown(speed, "speed"),
            "energy": shown(_f(result.kinetic_energy_before), "energy"),
            "angular_velocity": shown(speed / radius, "angular_velocity"),
            "angle": shown(math.pi, "angle"), "percent": 100.0}


def _interval(spread, name, kind, units) -> tuple[float, float]:
    if spread is None or name is None:
        return math.nan, math.nan
    stats = spread.stats[name]
    (low, high), _ = convert(np.array([stats.p5, stats.p95]), kind, units)
    return float(low), float(high)


def estimates(result: pim.Result, units: str = "si", spread=None) -> dict:
    """(key, vehicle) -> :class:`Estimate` of every row of :data:`RESULT_ROWS` (vehicle 1 for
    a quantity of the impact, e.g. the energy), in ``units``; ``spread`` (a
    :class:`pim.analysis.montecarlo.UncertaintyResult`) gives the intervals and the digits."""
    rows = {r.key: r for r in summarize(result, units)}
    scales = roundoff_scales(result, units)
    out = {}
    for key, kind, mc, digits_from in RESULT_ROWS:
        row = rows[key]
        for i in (1,) if row.single else (1, 2):
            value = row.vehicle1 if i == 1 else row.vehicle2
            if value is not None and kind is not None:
                value = round_off(value, scales[kind])
            low, high = _interval(spread, mc[i - 1] if mc else None, kind, units)
            decimals = interval_decimals(low, high)
            if digits_from is not None:
                decimals = out[(digits_from, i)].decimals
            out[(key, i)] = Estimate(row.label, value, low, high, decimals, row.unit)
    return out


def answer_cards(result: pim.Result, units: str = "si", spread=None) -> Cards:
    """What a reconstruction hands on, as the cards a report opens with: each vehicle's
    delta-V, its PDOF (with the clock position), its post-impact speed, and the energy
    lost, each with its 5-95 % interval (a fixed obstacle has no delta-V and no PDOF)."""
    est = estimates(result, units, spread)
    fixed = bool(np.asarray(result.case.vehicle2.fixed))
    cards = []

    def card(label, key, i, extra=""):
        e = est[(key, i)]
        if e.value is None:
            return
        note = f"5-95 %: {e.interval()}" if e.interval() else ""
        cards.append(Card(label, f"{e.text()} {e.unit}".strip() + extra, note))

    for i in (1,) if fixed else (1, 2):
        card(f"delta-V, vehicle {i}", "delta_v", i)
    for i in (1,) if fixed else (1, 2):
        clock = est[("clock", i)].value
        card(f"PDOF, vehicle {i}", "pdof", i,
             "" if clock is None else f" ({format_number(clock)} o'clock)")
    for i in (1,) if fixed else (1, 2):
        card(f"post-impact speed, vehicle {i}", "speed", i)
    card("kinetic energy lost", "energy_loss", 1)
    return Cards(tuple(cards))


def results_table(result: pim.Result, units: str = "si", spread=None) -> Table:
    """What a reconstruction hands on, per vehicle, in the ``units`` system.

    ``spread`` (a :class:`pim.analysis.montecarlo.UncertaintyResult`) adds each vehicle's 5 %
    and 95 % points and sets the digits shown (module notes).
    """
    est = estimates(result, units, spread)
    out = []
    for key, *_ in RESULT_ROWS:
        one, two = est[(key, 1)], est.get((key, 2))
        row = (one.label, one.cell(), "" if two is None else two.cell() or "-", one.unit)
        if spread is not None:
            row += (one.bound(one.low), one.bound(one.high),
                    None if two is None else two.bound(two.low),
                    None if two is None else two.bound(two.high))
        out.append(row)
    columns = ("quantity", "vehicle 1", "vehicle 2", "unit")
    if spread is not None:
        columns += ("vehicle 1, 5 %", "vehicle 1, 95 %", "vehicle 2, 5 %", "vehicle 2, 95 %")
    return Table("results", "Reconstruction results", columns, tuple(out),
                 note="" if spread is None else "5-95 %: Monte Carlo of the case's "
                 "`[uncertainty]` table; digits as its intervals allow")


def _pair(x, kind, units) -> tuple[str, str]:
    (a, b), unit = convert(np.asarray(x, float).reshape(2), kind, units)
    return f"{format_number(float(a))}, {format_number(float(b))}", unit


def _vehicle_inputs(i: int, v, units: str, estimate=None) -> list[tuple]:
    def val(x, kind):
        value, unit = convert(_f(x), kind, units)
        return float(value), unit

    fixed = bool(v.fixed)
    mass, mass_unit = val(v.mass, "mass")
    inertia, inertia_unit = val(v.yaw_inertia, "inertia")
    cg, length_unit = _pair(v.cg, "length", units)
    vel, vel_unit = _pair(v.velocity, "velocity", units)
    yaw, yaw_unit = val(v.yaw_rate, "angular_velocity")
    size = "" if v.length is None else (f"{format_number(val(v.length, 'length')[0])} x "
                                        f"{format_number(val(v.width, 'length')[0])}")
    return [(f"vehicle {i}", "mass", "fixed obstacle" if fixed else mass, mass_unit),
            (f"vehicle {i}", "yaw inertia" + (f" ({estimate.short})" if estimate else ""),
             "" if fixed else inertia, inertia_unit),
            (f"vehicle {i}", "CG x, y", cg, length_unit),
            (f"vehicle {i}", "heading", math.degrees(_f(v.heading)), "deg"),
            (f"vehicle {i}", "velocity x, y", vel, vel_unit),
            (f"vehicle {i}", "yaw rate", yaw, yaw_unit),
            (f"vehicle {i}", "length x width", size, length_unit)]


def inputs_table(case: pim.Case, units: str = "si") -> Table:
    """The case's inputs in the ``units`` system ("si" or "us")."""
    estimated = {e.name: e for e in case.estimates}
    rows = [row for i, v in ((1, case.vehicle1), (2, case.vehicle2))
            for row in _vehicle_inputs(i, v, units, estimated.get(f"vehicle{i}.yaw_inertia"))]
    point, length_unit = _pair(case.impact.point, "length", units)
    rows += [("impact", "point C x, y", point, length_unit),
             ("impact", "normal angle Gamma", math.degrees(_f(case.impact.normal_angle)), "deg"),
             ("impact", "restitution in the case", case.impact.restitution, "-"),
             ("impact", "beta in the case", case.impact.beta, "-")]
    m = case.measured
    if m is not None:
        for i, vel, w in ((1, m.velocity1, m.yaw_rate1), (2, m.velocity2, m.yaw_rate2)):
            if vel is not None:
                text, unit = _pair(vel, "velocity", units)
                rows.append((f"measured {i}", "post-impact velocity x, y", text, unit))
            if w is not None:
                value, unit = convert(w, "angular_velocity", units)
                rows.append((f"measured {i}", "post-impact yaw rate", float(value), unit))
    return Table("inputs", f"Case inputs ({display_units(units)})",
                 ("item", "quantity", "value", "unit"), tuple(rows))


def pre_impact_table(case: pim.Case, units: str = "si") -> Table | None:
    """The speed at the start of each vehicle's pre-impact marks (or driver table) from the
    case's impact velocities (:mod:`pim.analysis.pre_impact_speeds`); None without such
    evidence."""
    rows = pre_impact_rows(case_pre_impact(case), units)
    if not rows:
        return None
    unit = rows[0].unit
    return Table("pre_impact", PRE_IMPACT_TITLE, ("speed", f"value [{unit}]",
                                                  f"impact speed [{unit}]", "where, from what"),
                 tuple((r.name, r.value, r.impact, r.what) for r in rows))


def _cost_rows(fit, f: float, unit: str) -> list[tuple]:
    """The fit's cost: with measured sigmas the chi-square [-] (unit-free), its degrees of
    freedom, p-value and verdict; else the sum of squares in the user's unit squared."""
    g = fit.goodness
    if g is None:
        return [("cost (sum of squared velocity errors)", fit.cost * f * f, f"({unit})^2")]
    return [("chi-square", g.chi_square, "-"), ("degrees of freedom", g.dof, "-"),
            ("p-value", g.p_value, "-"), ("verdict", g.verdict(), "")]


def _law_coefficients(fit) -> tuple[list[tuple], str]:
    """The fitted law parameters and the table's title words."""
    law = getattr(fit, "law", "brach")
    if law == "kudlich-slibar":
        lower = "impact.mu_c" in fit.lower_bounds
        return ([("impact law", law, ""), ("k", fit.eps, "-"),
                 ("mu_c (lower bound: the contact sticks)" if lower else "mu_c",
                  fit.contact_friction, "-"), ("equivalent PIM beta", fit.beta, "-")],
                "(k, mu_c) under the Kudlich-Slibar law")
    coefficients = [("epsilon", fit.eps, "-"), ("beta", fit.beta, "-")]
    if law == "brach-capped":
        return ([("impact law", law, ""), *coefficients, ("cap mu_c", fit.contact_friction,
                                                          "-")],
                "(epsilon, beta) under the friction cap")
    return coefficients, "(epsilon, beta)"


def fit_table(fit, units: str = "si") -> Table:
    """The fitted law parameters ((epsilon, beta), or (k, mu_c) under the Kudlich-Slibar
    law) and the quality of the fit, in the ``units`` system."""
    f, unit = convert(1.0, "velocity", units)
    f = float(f)
    coefficients, title = _law_coefficients(fit)
    rows = [*coefficients,
            *_cost_rows(fit, f, unit),
            ("rms residual", fit.rms * f, unit),
            ("on a bound", ", ".join(f"{k} {v}" for k, v in fit.on_bound.items()) or "no", ""),
            ("local minima found", len(fit.minima), "")]
    rows += [(f"residual {name}", float(r) * f, unit)
             for name, r in zip(fit.residual_names, fit.residuals, strict=True)]
    return Table("fit", f"Least-squares fit of {title} to the measured motion",
                 ("quantity", "value", "unit"), tuple(rows))


def misfit_table(misfit: Misfit, units: str = "si") -> Table:
    """Each measured quantity against the model at the answer: measured, model, their
    difference, its sigma and the difference in sigmas, in the ``units`` system."""
    rows = []
    for r in misfit.rows:
        (measured, model, diff, sigma), unit = convert(
            np.array([r.measured, r.model, r.residual, r.sigma]), r.kind, units)
        d = _misfit_decimals(float(sigma))
        rows.append((r.label, unit, Num(float(measured), d), Num(float(model), d),
                     Num(float(diff), d), Num(float(sigma), sig=3),
                     "case" if r.stated else "tolerance", Num(r.z, sig=2)))
    return Table("misfit", "Each measured quantity against the model at the answer",
                 ("measured quantity", "unit", "measured", "model", "model - measured",
                  "sigma", "sigma from", "(model - measured) / sigma"), tuple(rows),
                 note=_sigma_words(misfit, units))


def _misfit_decimals(sigma: float) -> int | None:
    """The decimals of a measured quantity and its model value: three significant digits of
    its sigma (one more than an interval's, so that a difference within one sigma shows)."""
    return interval_decimals(-sigma, sigma, sig=3)


def _sigma_words(misfit: Misfit, units: str) -> str:
    if misfit.stated:
        return "sigma: the case's `[measured]` standard deviations"
    speed, su = convert(NOMINAL_SIGMAS["velocity"], "velocity", units)
    yaw, yu = convert(NOMINAL_SIGMAS["angular_velocity"], "angular_velocity", units)
    return (f"sigma: the case's `[measured]` standard deviations where it states them, else "
            f"the reproduction tolerances of Brach, Welsh & Brach (SAE 2014-01-0469), "
            f"{format_number(float(speed), sig=3)} {su} per velocity component and "
            f"{format_number(float(yaw), sig=3)} {yu} per yaw rate")


def misfit_sentence(misfit: Misfit, units: str = "si", fit=None,
                    intervals: bool = False) -> str:
    """One sentence when the fit is poor (some measured quantity more than
    :data:`pim.analysis.misfit.POOR` sigmas from the model): how many, each with both
    values, worst first, the rms residual of the best fit (``fit``) and, with ``intervals``,
    that the answer's intervals do not cover the misfit; "" when it is not poor."""
    poor = misfit.poor_rows
    if not poor:
        return ""

    def one(r):
        (model, measured, sigma), unit = convert(np.array([r.model, r.measured, r.sigma]),
                                                 r.kind, units)
        d = _misfit_decimals(float(sigma))
        return (f"{r.label} {format_number(float(model), decimals=d)} {unit} in the model "
                f"against {format_number(float(measured), decimals=d)} measured "
                f"({r.z:+.2g} sigma)")

    rms = ""
    if fit is not None:
        value, unit = convert(fit.rms, "velocity", units)
        rms = (f"; the least-squares fit (`pim fit`) leaves an rms residual of "
               f"{format_number(float(value), sig=3)} {unit}")
    cover = (" The intervals above cover the case's `[uncertainty]` table, not this misfit."
             if intervals else "")
    return (f"The fit is poor: {len(poor)} of {len(misfit.rows)} measured quantities lie "
            f"more than {POOR:g} sigma from the model ({'; '.join(one(r) for r in poor)})"
            f"{rms}: the model does not reproduce these measurements with one set of "
            f"coefficients.{cover}")
