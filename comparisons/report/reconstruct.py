"""The report of ``pim reconstruct``: typed rows of the reconstructed unknowns and the
momentum check, the words the command line and the report share, and the
:class:`~comparisons.report.document.Document` the one pipeline writes.

The report leads with what the reconstruction hands on: the unknowns (the impact speeds
first) with their 5-95 % intervals, then the answer at the solution (each vehicle's delta-V
and PDOF, the energy lost), the warnings, the table of every unknown beside the momentum
check; then the speeds before the impact, what drives each spread, the crush energy, which
evidence drove each unknown, the goodness of fit and the scene with its animation.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from comparisons.report.compare_tables import answer_cards
from comparisons.report.document import (
    Bullets,
    Callout,
    Card,
    Cards,
    Document,
    Paragraph,
    Section,
)
from pim.model.number_format import format_interval, format_number, interval_decimals
from comparisons.report.pre_impact import pre_impact_json, pre_impact_lines, pre_impact_section
from comparisons.report.tables import Num, Table
from pim.analysis.reconstruction import Reconstruction
from pim.io.inertia_data import estimate_notes, estimate_records
from pim.io.units import convert, display_units
from pim.model.evidence import UNKNOWN_KINDS
from pim.model.law import LAW_NAMES, LAW_PARAMETERS
from pim.model.plausibility import secondary_contact
from pim.model.quantities import label_of

__all__ = ["UnknownRow", "MomentumRow", "ReconstructionRows", "reconstruction_rows",
           "law_line", "tyre_models_line", "crush_lines", "evidence_drivers", "driver_lines",
           "spread_driver_lines", "reconstruction_table", "reconstruction_document",
           "spread_text", "table_lines", "reconstruction_lines", "runout_contact",
           "crush_json", "reconstruction_json"]


@dataclass(frozen=True)
class UnknownRow:
    """One reconstructed unknown in the user's units.

    Attributes
    ----------
    name : str
        Its dotted key (``vehicle1.speed``, ``impact.restitution``).
    unit : str
        Display unit ("-" when dimensionless).
    value : float
        The solution.
    p5, p50, p95 : float
        Its Monte Carlo percentiles (NaN without samples).
    driver : str
        The input that drives its spread most ("" without samples).
    driver_index : float
        That input's first-order variance index (NaN without samples).
    lower_bound : bool
        The value is only a lower bound (a contact friction the contact does not reach).
    """

    name: str
    unit: str
    value: float
    p5: float
    p50: float
    p95: float
    driver: str
    driver_index: float
    lower_bound: bool = False

    @property
    def label(self) -> str:
        """Its plain-language name ("impact speed of vehicle 1")."""
        return label_of(self.name)

    @property
    def has_spread(self) -> bool:
        """Whether the percentiles were computed."""
        return not math.isnan(self.p5)

    @property
    def decimals(self) -> int | None:
        """The decimals its interval allows (None without one)."""
        return interval_decimals(self.p5, self.p95)

    def value_text(self) -> str:
        """The value (">= X" where it is a lower bound), with the digits its interval
        allows."""
        return (">= " if self.lower_bound else "") + format_number(self.value,
                                                                   decimals=self.decimals)


@dataclass(frozen=True)
class MomentumRow:
    """The linear-momentum check's impact speed of one vehicle.

    Attributes
    ----------
    vehicle : int
        1 or 2.
    unit : str
        Display unit.
    value : float
        The speed from linear momentum.
    sd : float
        Its standard deviation.
    """

    vehicle: int
    unit: str
    value: float
    sd: float

    @property
    def name(self) -> str:
        """The unknown it checks (``vehicle1.speed``)."""
        return f"vehicle{self.vehicle}.speed"

    @property
    def label(self) -> str:
        """Its plain-language name ("impact speed of vehicle 1")."""
        return label_of(self.name)


@dataclass(frozen=True)
class ReconstructionRows:
    """The reconstruction's table, typed.

    Attributes
    ----------
    unknowns : tuple of UnknownRow
        Every solved unknown.
    momentum : tuple of MomentumRow
        The momentum check (empty without both post-impact velocities).
    """

    unknowns: tuple[UnknownRow, ...]
    momentum: tuple[MomentumRow, ...]


def _kind(name: str) -> str:
    """Unit kind of an unknown (impact speeds in the system's impact-speed unit)."""
    return ("impact_speed" if name.endswith(".speed")
            else UNKNOWN_KINDS.get(name, "dimensionless"))


def reconstruction_rows(rec: Reconstruction, units: str) -> ReconstructionRows:
    """The unknowns and the momentum check of ``rec`` in ``units``."""
    lower = rec.fit.lower_bounds if rec.fit is not None else {}
    unknowns = []
    for r in rec.table():
        values, unit = convert([r["value"], r["p5"], r["p50"], r["p95"]], _kind(r["name"]),
                               units)
        driver = r["drivers"][0] if r["drivers"] else ("", float("nan"))
        unknowns.append(UnknownRow(r["name"], unit, *(float(v) for v in values),
                                   driver=driver[0], driver_index=float(driver[1]),
                                   lower_bound=r["name"] in lower))
    momentum = []
    if rec.momentum is not None:
        m = rec.momentum
        for i, (s, sd) in enumerate(((m.speed1, m.sigma1), (m.speed2, m.sigma2)), start=1):
            values, unit = convert([s, sd], "impact_speed", units)
            momentum.append(MomentumRow(i, unit, float(values[0]), float(values[1])))
    return ReconstructionRows(tuple(unknowns), tuple(momentum))


def law_line(rec: Reconstruction) -> str:
    """The impact law the inverse PIM applied (one line for the report and the CLI)."""
    law = rec.fit.law if rec.fit is not None else (rec.case.impact.law or "brach")
    return f"Impact law: {LAW_NAMES[law]} ({LAW_PARAMETERS[law]}) (docs/impact-laws.md)."


def tyre_models_line(rec: Reconstruction) -> str:
    """Which tyre law each vehicle's run-out used (one line for the report and the CLI)."""
    return "Run-out tyre model: " + ", ".join(
        f"vehicle {i} {fit.tyre_model}" for i, fit in sorted(rec.post.runouts.items())) + "."


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


def _spaced(text: str) -> str:
    """An evidence group's name as a reader writes it: "vehicle1 ..." -> "vehicle 1 ..."."""
    return re.sub(r"\bvehicle(\d)\b", r"vehicle \1", text)


def driver_lines(drivers: dict) -> list[str]:
    """One line per unknown (by its label): its standard error and the evidence shares,
    largest first."""
    return [f"{label_of(key)} (1 sd = {format_number(d['sd'], sig=3)} {d['unit']}): "
            + ", ".join(f"{_spaced(g)} {100 * v:.0f} %" for g, v in d["shares"].items()
                        if v >= 0.005)
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


def spread_driver_lines(rec: Reconstruction) -> list[str]:
    """One line per unknown (by its label): the inputs that drive its spread, with their
    indices."""
    lines = []
    for r in rec.table():
        top = ", ".join(f"{label_of(k)} {v:.2f}" for k, v in r["drivers"][:4] if v > 0.005)
        lines.append(f"{label_of(r['name'])}: {top or 'no single input dominates'}")
    return lines


def _unknown_cells(r: UnknownRow) -> tuple:
    d = r.decimals

    def cell(x):
        return None if math.isnan(x) else Num(x, d)

    value = r.value_text() if r.lower_bound else Num(r.value, d)
    driver = f"{label_of(r.driver)} ({r.driver_index:.2f})" if r.driver else ""
    return (r.label, r.unit, value, cell(r.p5), cell(r.p50), cell(r.p95), driver)


def reconstruction_table(rows: ReconstructionRows) -> Table:
    """Every unknown with its 5/50/95 % and the main driver of its spread, and the
    momentum check's speeds with their standard deviation (``reconstruction.csv``)."""
    body = [_unknown_cells(r) for r in rows.unknowns]
    body += [(f"momentum check: {m.label}", m.unit, Num(m.value, interval_decimals(
        m.value - m.sd, m.value + m.sd)), None, None, None,
        f"1 sd = {format_number(m.sd, sig=2)} {m.unit}") for m in rows.momentum]
    return Table("reconstruction", "Reconstructed unknowns",
                 ("unknown", "unit", "value", "5 %", "50 %", "95 %",
                  "main driver of the spread"), tuple(body))


def _unknown_cards(rows: ReconstructionRows) -> Cards:
    """The unknowns as cards, the impact speeds first."""
    order = sorted(rows.unknowns, key=lambda r: (not r.name.endswith(".speed"), r.name))
    cards = []
    for r in order:
        _, low, high = format_interval(r.value, r.p5, r.p95)
        unit = "" if r.unit in ("-", "") else f" {r.unit}"
        cards.append(Card(r.label, r.value_text() + unit,
                          f"5-95 %: {low} to {high}" if low else ""))
    return Cards(tuple(cards))


def _method(rec: Reconstruction) -> str:
    n = rec.samples.n if rec.samples else 0
    source = ("the run-out inverse of each vehicle's rest evidence" if rec.post else
              "the case's [measured] post-impact motion")
    return (f"Post-impact motion from {source}; unknowns by the inverse PIM (least squares "
            f"over the measured velocities and yaw rates, exact derivatives); "
            + (f"5/50/95 % from a Monte Carlo of {n} samples over the stated uncertainties "
               f"({rec.samples.n_used} used{_through_event(rec.samples)})." if n
               else "no Monte Carlo (--samples 0).")
            + f" {law_line(rec)}")


def _through_event(samples) -> str:
    """How the Monte Carlo's post-impact motions went through the event ("" when they did
    not)."""
    c = samples.through_event
    if not c:
        return ""
    return (f"; each sample's post-impact motion fitted through the event, its further impacts "
            f"included: {c['converged']} of {c['samples']} fits converged, "
            f"{c['unconverged']} left out")


def _results(rec: Reconstruction, rows: ReconstructionRows, units: str) -> Section:
    blocks = [_unknown_cards(rows)]
    if rec.fit is not None:
        blocks += [Paragraph("At the solution (no interval: the Monte Carlo varies the "
                             "unknowns' evidence, not these outputs):"),
                   answer_cards(rec.fit.result, units)]
    if rec.messages:
        blocks.append(Callout("Warnings", tuple(rec.messages)))
    blocks += [Paragraph(_method(rec))]
    if rec.post:
        blocks.append(Paragraph(tyre_models_line(rec)))
    blocks.append(reconstruction_table(rows))
    estimates = estimate_notes(rec.case, units)
    if estimates:
        blocks += [Paragraph("Estimated inputs (drawn with their scatter in the Monte Carlo "
                             "unless the `[uncertainty]` table says otherwise):"),
                   Bullets(tuple(estimates))]
    if not rec.messages:
        blocks.append(Paragraph("No warnings."))
    return Section("results", "Results", tuple(blocks), keep=True)


def _details(rec: Reconstruction, units: str) -> list[Section]:
    sections = []
    if rec.samples:
        sections.append(Section("drivers", "What drives each unknown's spread", (
            Paragraph("First-order variance indices (correlation ratio) of the sampled "
                      "inputs."), Bullets(tuple(spread_driver_lines(rec)))), toc="Drivers"))
    if rec.crush:
        sections.append(Section("crush", "Crush energy", (Bullets(tuple(crush_lines(rec,
                                                                                  units))),)))
    drivers = driver_lines(evidence_drivers(rec, units))
    if drivers:
        sections.append(Section("evidence", "Which evidence drove each unknown", (
            Paragraph("Share of each unknown's variance from each piece of evidence (weighted "
                      "Jacobian at the solution: (J^T J)^-1 split by evidence)."),
            Bullets(tuple(drivers))), toc="Evidence"))
    if rec.goodness is not None:
        sections.append(Section("goodness", "Goodness of fit", (
            Paragraph(f"Goodness of fit: {rec.goodness.summary()}."),), toc="Goodness"))
    return sections


def reconstruction_document(rec: Reconstruction, rows: ReconstructionRows, units: str,
                            pre=(), media: tuple = ()) -> Document:
    """The report of ``pim reconstruct`` (module notes).

    ``pre``: the speeds before the impact (:func:`comparisons.report.pre_impact.pre_impact_rows`);
    ``media``: the scene figure and the animation written beside it
    (:class:`~comparisons.report.document.Figure`, :class:`~comparisons.report.document.Video`).
    """
    sections = [_results(rec, rows, units)]
    pre_section = pre_impact_section(pre)
    if pre_section is not None:
        sections.append(pre_section)
    sections += _details(rec, units)
    if media:
        sections.append(Section("scene", "Scene and animation", tuple(media), toc="Scene"))
    return Document(f"Reconstruction of {rec.case.name}", "pim reconstruct", tuple(sections),
                    subtitle=f"Written by `pim reconstruct` in {display_units(units)} (the "
                             "same as text: `report.md`).")



def spread_text(row: UnknownRow, samples: int, sep: str = ", ") -> str:
    """An unknown's "[p5, p50, p95]", or why there is none (never "[nan, nan, nan]")."""
    if not samples:
        return "(5/50/95 %: not computed, --samples 0)"
    if not row.has_spread:
        return "(5/50/95 %: no usable Monte Carlo sample)"
    return "[" + sep.join(format_number(x) for x in (row.p5, row.p50, row.p95)) + "]"


def table_lines(rows: ReconstructionRows, samples: int) -> list[str]:
    """The table as text lines: each unknown with its 5/50/95 % (``samples``: how many the
    Monte Carlo drew), then the momentum check with its standard deviation."""
    names = [r.label for r in rows.unknowns] + [f"momentum check: {m.label}"
                                                 for m in rows.momentum]
    width = max(map(len, names), default=0)
    lines = [f"{r.label:{width}s} "
             f"{(('>= ' if r.lower_bound else '') + format_number(r.value)):>10s} "
             f"{r.unit}  {spread_text(r, samples)}" for r in rows.unknowns]
    lines += [f"{'momentum check: ' + m.label:{width}s} {format_number(m.value):>10s} "
              f"{m.unit}  (1 sd = {format_number(m.sd, sig=3)} {m.unit})"
              for m in rows.momentum]
    return lines


def reconstruction_lines(rec: Reconstruction, rows: ReconstructionRows, units: str, *,
                         samples: int, pre=()) -> list[str]:
    """``pim reconstruct``'s text, one line each.

    Parameters
    ----------
    rec : Reconstruction
        The reconstruction.
    rows : ReconstructionRows
        Its table in ``units`` (:func:`reconstruction_rows`).
    units : DisplayUnits or str
        The output's units.
    samples : int
        The Monte Carlo samples asked for (0: none).
    pre : sequence
        The speeds before the impact (:func:`comparisons.report.pre_impact.pre_impact_rows`).

    Returns
    -------
    list of str
        The law, the run-outs' tyre model, the warnings (before the table, where a reader
        sees them), the table, the speeds before the impact, the crush energies, the
        evidence behind each unknown and the goodness of fit.
    """
    lines = [law_line(rec)] + ([tyre_models_line(rec)] if rec.post is not None else [])
    lines += [f"warning: {message}" for message in rec.messages]
    lines += table_lines(rows, samples) + pre_impact_lines(pre)
    lines += [f"crush: {line}" for line in crush_lines(rec, units)]
    lines += [f"evidence: {line}" for line in driver_lines(evidence_drivers(rec, units))]
    if rec.goodness is not None:
        lines.append(f"goodness of fit: {rec.goodness.summary()}")
    return lines


def runout_contact(rec: Reconstruction, units: str) -> dict | None:
    """Where the two fitted run-outs (those the animation plays) run into each other again
    after the impact (:func:`pim.model.plausibility.secondary_contact`).

    Parameters
    ----------
    rec : Reconstruction
        The reconstruction, with both vehicles' run-outs.
    units : DisplayUnits or str
        The units of the place.

    Returns
    -------
    dict or None
        Time [s], place (x, y) in ``units`` with its ``length_unit``, and the message; None
        without both run-outs and outlines, or when they do not meet.
    """
    post = rec.post
    if post is None or set(post.runouts) != {1, 2} or post.event_fit is not None:
        return None         # (fitted through the event: its messages name the impacts)
    end = max(float(f.runout.time[-1]) for f in post.runouts.values())
    event = post.event(np.arange(int(np.ceil(end * 100)) + 1) / 100)      # 100 per second
    states = [np.column_stack([t.position, t.heading]) for t in event.tracks]
    hit = secondary_contact(event.time, states[0], states[1], rec.case.vehicle1,
                            rec.case.vehicle2)
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


def crush_json(rec: Reconstruction, units: str) -> dict:
    """The crush outputs per vehicle (``vehicleN``): crush energy with its sd, the
    force-balance factor, EES and the delta-V from crush beside the solution's, each value
    with its unit in ``units``."""
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


def reconstruction_json(rec: Reconstruction, rows: ReconstructionRows, units: str, *,
                        samples: int, pre=(), contact: dict | None = None,
                        findings: dict | None = None) -> dict:
    """``pim reconstruct --json``: every value in ``units`` with its unit.

    Parameters
    ----------
    rec, rows, units, samples, pre
        As :func:`reconstruction_lines`.
    contact : dict, optional
        The run-outs' secondary contact (:func:`runout_contact`).
    findings : dict, optional
        The JSON of what is wrong or doubtful about the answer (placed after the unknowns
        and the momentum check).

    Returns
    -------
    dict
        The case, units, samples, messages, the Monte Carlo's counts (samples used and,
        through the event, how many fits converged), estimated inputs, each unknown by its
        dotted name (value, percentiles, unit, lower bound), the momentum check, the findings, the
        secondary impact, the speeds before the impact, the run-outs' tyre models, the
        goodness of fit, the evidence behind each unknown, the crush outputs and the law.
    """
    return {"case": rec.case.name, "units": display_units(units).to_json(),
            "samples": samples, "messages": rec.messages,
            "monte_carlo": rec.samples.to_dict() if rec.samples else None,
            "estimates": estimate_records(rec.case, units),
            "unknowns": {r.name: {"unit": r.unit, "value": r.value, "p5": r.p5,
                                  "p50": r.p50, "p95": r.p95, "lower_bound": r.lower_bound}
                         for r in rows.unknowns},
            "momentum_check": {m.name: {"unit": m.unit, "value": m.value, "sd": m.sd}
                               for m in rows.momentum},
            **(findings or {}), "secondary_impact": contact, "pre_impact": pre_impact_json(pre),
            "tyre_models": ({f"vehicle{i}": fit.tyre_model for i, fit in
                             rec.post.runouts.items()} if rec.post else {}),
            "goodness_of_fit": rec.goodness.to_dict() if rec.goodness else None,
            "evidence_drivers": evidence_drivers(rec, units), "crush": crush_json(rec, units),
            "law": rec.fit.law}
