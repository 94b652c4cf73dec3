"""The ladder of ``pim assumptions`` in words, tables and a plot, as a
:class:`~comparisons.report.document.Document` (``assumptions.md``, ``.html`` and the CSVs)
written with its plot and animation through the one pipeline.

Every effect is said twice: as the project's one error (a share of the impact's largest
velocity change) and in physical terms, how far the delta-V moves and the yaw rate, in the
case's units (:func:`shown_units`: km/h or mph where the case speaks them). Effects that
depend on an unmeasured parameter are stated over its range, never at one chosen value:
the contact time over :data:`comparisons.studies.assumption_configs.CONTACT_RANGE`, the
tangential recovery r over [0, 1]; the tyre rung with the wheels rolling and locked, each
named. "Where C is" stands beside the ladder as the uncertainty of an input.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np

import pim
from comparisons.animation.collision import build_renderer
from comparisons.animation.render import write_animation
from comparisons.report.document import (
    Bullets,
    Callout,
    Document,
    Figure,
    FileList,
    Paragraph,
    Section,
    Video,
)
from pim.model.number_format import format_number
from comparisons.report.tables import Table, fmt_error
from comparisons.report.write import write_document
from comparisons.studies.assumption_configs import (
    HOLDS,
    ROUGHLY,
    RUNGS,
    STIFF_LIMIT,
    TYPICAL,
    RungConfig,
)
from comparisons.studies.assumptions import AssumptionStudy, Change, EffectRange, pim_friction
from pim.io import units as pim_units
from pim.io.files import save_figure
from sim.contact_law import tangential_recovery_default
from sim.error_measure import ERROR_DEFINITION

__all__ = ["ASSUMPTION_GROUPS", "shown_units", "verdicts", "input_shift_words",
           "ladder_intro", "assumption_table", "input_shift_table", "sweep_table",
           "plot_overview", "write_assumptions", "assumptions_document", "study_json"]


def shown_units(case: pim.Case, units=None):
    """The display units of the ladder's output: ``units`` if given, else the case's own
    (with its speed unit, km/h or mph, where :mod:`pim.io.units` knows one)."""
    chooser = getattr(pim_units, "display_units", None)
    if chooser is not None:
        return chooser(units, case=case)
    return units or case.units


def _speed(value: float, units) -> tuple[float, str]:
    v, label = pim_units.convert(value, "velocity", units)
    return float(v), label


def _yaw(value: float, units) -> float:
    return float(pim_units.convert(value, "angular_velocity", units)[0])


# -- words --------------------------------------------------------------------------------

def _pct(x: float) -> str:
    return "n/a" if not math.isfinite(x) else f"{100 * x:.1f} %"


def _size(x: float) -> str:
    if not math.isfinite(x):
        return "not assessed (a simulation failed)"
    if x < HOLDS:
        return "negligible"
    return "moderate" if x < ROUGHLY else "large"


def _sizes(lo: float, hi: float) -> str:
    """The verdict over a range: "negligible", or "negligible to moderate"."""
    a, b = _size(lo), _size(hi)
    return a if a == b else f"{a} to {b}"


def _num(x: float) -> str:
    """A physical change in the reports' number format, two significant digits ("26",
    "100", "0.087"; never "1e+02")."""
    return format_number(x, sig=2)


def _span(lo: float, hi: float, fmt=_num) -> str:
    return fmt(lo) if fmt(lo) == fmt(hi) else f"{fmt(lo)}-{fmt(hi)}"


def _pct_span(lo: float, hi: float) -> str:
    """"5.4-14.9 %" (one value when both round alike; "not assessed" when neither is a
    number)."""
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return "not assessed (a simulation failed)"
    a, b = (f"{100 * x:.1f}" for x in (lo, hi))
    return f"{a} %" if a == b else f"{a}-{b} %"


def _physical(c: Change, units) -> str:
    """"delta-V 1.2 mph, yaw rate 8 deg/s" (the larger vehicle of each)."""
    if not math.isfinite(c.delta_v):
        return "no physical difference measured"
    dv, label = _speed(c.delta_v, units)
    return f"delta-V {_num(dv)} {label}, yaw rate {_num(_yaw(c.yaw_rate, units))} deg/s"


def _range_words(er: EffectRange, units, over: str, against: str = "its baseline") -> str:
    """"negligible to moderate over 50-150 ms: 2.8-15.2 % of the largest velocity change
    of its baseline ..., delta-V ..."."""
    lo, hi = er.extremes("marginal")
    if not math.isfinite(hi):
        return "not assessed (a simulation failed)"
    dv_lo, dv_hi = (_speed(x, units)[0] for x in er.extremes("delta_v"))
    label = _speed(0.0, units)[1]
    w_lo, w_hi = (_yaw(x, units) for x in er.extremes("yaw_rate"))
    if er.missing:
        over += f" (not at {', '.join(er.missing)}: no outline scene there)"
    return (f"{_sizes(lo, hi)} over {over}: {_pct_span(lo, hi)} {_of(against)} "
            f"(largest at {er.setting_of('marginal')}); delta-V moves by "
            f"{_span(dv_lo, dv_hi)} {label}, the yaw rate by {_span(w_lo, w_hi)} deg/s")


def _contact_words(study: AssumptionStudy) -> str:
    lo, hi = study.contact_range
    return f"{1e3 * lo:g}-{1e3 * hi:g} ms of contact"


def _tangential(study: AssumptionStudy) -> str:
    """PIM's tangential law at the case's own beta, as the "law" rung's contact law."""
    beta = study.beta_pim
    if beta <= 0:
        return "no friction between the vehicles (PIM's beta = 0, the case's)"
    if beta >= 1:
        return f"a sticking, plastic friction spring (PIM's beta = {beta:.3g}, the case's)"
    mu = pim_friction(study.case, study.eps, beta)
    return (f"a plastic friction spring sliding at |mu| = beta |mu0| = {mu:.3g} (PIM's "
            f"beta = {beta:.3g}, the case's)")


def _of(whose: str) -> str:
    """What an effect in % is a share of (:data:`sim.error_measure.ERROR_DEFINITION`)."""
    return f"of the largest velocity change of {whose}"


def _rung_subjects(study: AssumptionStudy) -> dict:
    """Rung key -> the sentence's subject: the assumption and what replaced it."""
    tyre = TYPICAL["tyre_friction"]
    r0 = float(tangential_recovery_default(study.eps))
    return {
        "law": f"Newton's restitution with mu = beta mu0, replaced by the crush hysteresis "
               f"(epsilon = {study.eps:.3g}) with {_tangential(study)} at a nearly "
               f"instantaneous {1e3 * STIFF_LIMIT:g} ms contact",
        "duration": "The instantaneous impulse, replaced by a finite contact (same contact "
                    "law at C)",
        "outline": "One contact point, replaced by the outlines crushing into each other "
                   "(a distributed contact on the same line of impulse)",
        "tyres": f"No external forces, replaced by tyre friction {tyre:g} during the contact "
                 f"with the wheels rolling (tyres resist sideways slip only)",
        "tyres_locked": f"No external forces, replaced by tyre friction {tyre:g} during the "
                        f"contact with the wheels locked (tyres resist the whole slip)",
        "friction": f"PIM's tangential law, replaced by Coulomb friction "
                    f"{TYPICAL['friction']:g} between the vehicles with the tangential "
                    f"recovery r unmeasured (0 plastic to 1 elastic; default eps^2 = "
                    f"{r0:.3g})",
    }


def _typical_words(study: AssumptionStudy, key: str, units) -> str:
    rung = study.typical.rung(key)
    ms = f"{1e3 * study.typical.duration:g} ms"
    at = f"at {ms}" + (" and r = eps^2" if key == "friction" else "")
    return (f"{at}: {_pct(rung.marginal)} {_of('its baseline')} "
            f"({_physical(rung.change, units)}); PIM misses this scene by "
            f"{_pct(rung.cumulative)} {_of('the scene')} (cumulative, "
            f"{_physical(rung.pim_change, units)})")


def _friction_map_words(study: AssumptionStudy) -> str:
    d = TYPICAL["duration"]
    pts = [p for p in study.friction_points if p.duration == d]
    mus = sorted({p.mu_c for p in pts})
    if len(mus) < 2:
        return ""
    values = [p.marginal for p in pts if math.isfinite(p.marginal)]
    span = _pct_span(min(values), max(values)) if values else _pct_span(math.nan, math.nan)
    return (f"; over mu_c {mus[0]:g}-{mus[-1]:g} and every r at {1e3 * d:g} ms: {span}"
            + (f" {_of('its baseline')}" if values else ""))


def _rung_sentence(study: AssumptionStudy, key: str, subject: str, units) -> str:
    rung = study.typical.rung(key)
    if key == "law":
        if rung.run.failure:
            return f"{subject}: not assessed ({rung.run.failure})."
        return (f"{subject}: {_size(rung.marginal)}, {_pct(rung.marginal)} "
                f"{_of('PIM')} ({_physical(rung.change, units)}), whatever the "
                f"contact time.")
    if key == "friction":
        er, over = study.friction_over(), f"every r and {_contact_words(study)}"
    else:
        er, over = study.over_range(key), _contact_words(study)
    text = _range_words(er, units, over) if er is not None else "no range simulated"
    if rung.run.failure:
        typical = (f"at {1e3 * study.typical.duration:g} ms not assessed "
                   f"({rung.run.failure.rstrip('.')})")
    else:
        typical = _typical_words(study, key, units)
    extra = _friction_map_words(study) if key == "friction" else ""
    return f"{subject}: {text}; {typical}{extra}."


def verdicts(study: AssumptionStudy, units=None) -> list[str]:
    """One sentence per rung above PIM: the assumption, what replaced it (the wheels'
    state named), the effect over the unmeasured range in % and in the case's units."""
    units = shown_units(study.case, units)
    subjects = _rung_subjects(study)
    out = [_rung_sentence(study, rung.key, subjects[rung.key], units)
           for rung in study.typical.rungs[1:]]
    if study.typical.rung("outline") is None:
        out.insert(2, f"One contact point: not assessed ({study.outline_note}).")
    elif study.outline_note:
        out.append(f"The outline rung is missing at some contact times: "
                   f"{study.outline_note}.")
    return out


def input_shift_words(study: AssumptionStudy, units=None) -> str:
    """"Where C is": the input uncertainty beside the ladder, in one sentence ("" without
    outlines)."""
    shift, er = study.input_shift, study.shift_over_range()
    if shift is None:
        return ""
    units = shown_units(study.case, units)
    length, label = pim_units.convert(shift.distance, "length", units)
    scene = ("" if er is None else
             f"; the crush scene moves "
             f"{_range_words(er, units, _contact_words(study), 'the scene at C')}")
    return (f"Where C is (input uncertainty, not an assumption of PIM): the case's outlines "
            f"put the impulse {float(length):.2f} {label} from the sheet's C on vehicle 1 and "
            f"{round(shift.turn) + 0:+d} deg from Gamma; moving C and Gamma there (the bodies "
            f"where "
            f"the outlines first touch) moves PIM's own answer by {_pct(shift.pim_error)} "
            f"{_of('its answer at C')} "
            f"({_physical(shift.pim_change, units)}){scene}. The outlines are illustrative: "
            f"settle C from the crush profile before reading the ladder's outline rung.")


def ladder_intro(command: str) -> str:
    """The sentence a report puts before the verdicts: what the ladder is, over which
    ranges, and the command of the whole study."""
    return (f"A ladder of crush scenes relaxes PIM's assumptions one at a time, each scene "
            f"differing from its baseline in one assumption; the marginal effect is against "
            f"the baseline at the same contact time, the cumulative one is PIM's error "
            f"against the scene, both also as the delta-V and yaw rate they move. The "
            f"unmeasured parameters are ranges: contact times 50-150 ms, the tangential "
            f"recovery 0-1; tyre friction {TYPICAL['tyre_friction']:g} with the wheels "
            f"rolling and locked, friction {TYPICAL['friction']:g} between the vehicles; "
            f"docs/contact-model.md has the model. The study over contact times, its plots "
            f"and an animation are `{command}`.")


# -- tables and plots -----------------------------------------------------------------------

#: The assumptions table's columns in groups that fit a screen: (caption, columns). A
#: column matches by its header, or by its header without the unit (``"fit rms"`` matches
#: ``"fit rms [ft/s]"``); columns no group names are shown in a last group.
ASSUMPTION_GROUPS = (
    ("Effect of each assumption (marginal: against its baseline; cumulative: PIM against "
     "the scene; changes: the larger vehicle's)",
     ("against", "marginal effect [-]", "cumulative (PIM's error) [-]", "delta-V change",
      "yaw-rate change")),
    ("Over the contact-time range (and the tangential recovery r for friction)",
     ("least marginal over the range [-]", "most marginal over the range [-]",
      "most delta-V change over the range", "most yaw-rate change over the range")),
    ("The scene of each rung", ("scene", "contact [ms]", "failure")),
    ("What PIM would need to reproduce the scene (effective coefficients and impact point)",
     ("eps_eff [-]", "beta_eff [-]", "C_eff x", "C_eff y")),
    ("Contact and energy", ("energy loss [-]", "stick fraction [-]", "slip reversed")),
)



def _config_words(config: RungConfig) -> str:
    if config.law == "pim":
        return "PIM"
    parts = ["crush", "instant" if config.duration is None else f"{1e3 * config.duration:g} ms",
             "outline" if config.distributed else f"point at {config.point}"]
    if config.tyre_friction:
        parts.append(f"tyres {config.tyre_friction:g} {config.tyre_mode}")
    parts.append("PIM's tangential law" if config.friction == "pim" else
                 f"mu_c {config.mu_c:g}, r "
                 f"{'eps^2' if config.recovery is None else f'{config.recovery:.3g}'}")
    return ", ".join(parts)


def _f(x) -> float:
    return float(x)


def _range_cells(er: EffectRange | None, units) -> tuple:
    if er is None:
        return (math.nan,) * 4
    lo, hi = er.extremes("marginal")
    return (lo, hi, _speed(er.extremes("delta_v")[1], units)[0],
            _yaw(er.extremes("yaw_rate")[1], units))


def assumption_table(study: AssumptionStudy, name: str = "assumptions",
                     units=None) -> Table:
    """The ladder: each rung at the typical contact time, and its marginal effect over the
    verdicts' range (the friction rung: over r too), in % and in the case's units."""
    units = shown_units(study.case, units)
    length, lab = pim_units.convert(1.0, "length", units)
    v = _speed(0.0, units)[1]
    lo, hi = (1e3 * t for t in study.contact_range)
    rows = []
    for rung in study.typical.rungs[1:]:
        r, c = rung.run, rung.change
        er = study.friction_over() if rung.key == "friction" else study.over_range(rung.key)
        rows.append((RUNGS[rung.key].title, rung.baseline, _config_words(rung.config),
                     rung.marginal, rung.cumulative, _speed(c.delta_v, units)[0],
                     _yaw(c.yaw_rate, units), *_range_cells(er, units),
                     1e3 * r.contact_duration, _f(length * r.impact_point[0]),
                     _f(length * r.impact_point[1]), rung.eps_eff, rung.beta_eff,
                     r.energy_loss, r.stick_fraction, r.slip_reversed, r.failure or ""))
    span = f"{lo:g}-{hi:g} ms"
    columns = ("assumption relaxed", "against", "scene", "marginal effect [-]",
               "cumulative (PIM's error) [-]", f"delta-V change [{v}]",
               "yaw-rate change [deg/s]", "least marginal over the range [-]",
               "most marginal over the range [-]",
               f"most delta-V change over the range [{v}]",
               "most yaw-rate change over the range [deg/s]", "contact [ms]",
               f"C_eff x [{lab}]", f"C_eff y [{lab}]", "eps_eff [-]", "beta_eff [-]",
               "energy loss [-]", "stick fraction [-]", "slip reversed", "failure")
    return Table(name, f"PIM's assumptions one at a time at {1e3 * study.typical.duration:g} "
                 f"ms and over the range {span} (friction: and r in [0, 1]) "
                 f"({ERROR_DEFINITION}; changes: the larger vehicle's)",
                 columns, tuple(rows),
                 {c: fmt_error for c in columns if "marginal" in c or "cumulative" in c})


def input_shift_table(study: AssumptionStudy, name: str = "where_c", units=None) -> Table:
    """Where C is: PIM and the crush scene at each contact time of the range moved from the
    sheet's C to where the outlines' impulse acts (empty without outlines; every contact
    time: :func:`sweep_table`)."""
    units = shown_units(study.case, units)
    v = _speed(0.0, units)[1]
    rows = []
    if study.input_shift is not None:
        s = study.input_shift
        rows.append(("PIM", math.nan, s.pim_error, _speed(s.pim_change.delta_v, units)[0],
                     _yaw(s.pim_change.yaw_rate, units)))
    for lad in study.in_range("outline"):
        c = lad.shift.change
        rows.append(("crush scene", 1e3 * lad.duration, lad.shift.error,
                     _speed(c.delta_v, units)[0], _yaw(c.yaw_rate, units)))
    columns = ("model", "contact time [ms]", "effect [-]", f"delta-V change [{v}]",
               "yaw-rate change [deg/s]")
    return Table(name, "Where C is: the sheet's C against where the outlines' impulse acts "
                 "(input uncertainty, not a rung)", columns, tuple(rows),
                 {"effect [-]": fmt_error})


def _ladder_rows(study: AssumptionStudy, units) -> list:
    rows = []
    for lad in study.ladders:
        for rung in lad.rungs[1:]:
            rows.append(("ladder", rung.key, 1e3 * lad.duration, _config_words(rung.config),
                         rung.marginal, rung.cumulative,
                         _speed(rung.change.delta_v, units)[0],
                         _yaw(rung.change.yaw_rate, units), rung.run.failure or ""))
    return rows


def sweep_table(study: AssumptionStudy, name: str = "assumption_sweeps", units=None) -> Table:
    """Every rung at every contact time, the tyre curves (rolling and locked), the friction
    rung over (contact time, mu_c, r) and where C is at each contact time."""
    units = shown_units(study.case, units)
    rows = _ladder_rows(study, units)
    for (mode, mu), values in study.tyre_curves.items():
        for d, x in zip(study.durations, values, strict=True):
            rows.append(("tyre effect", f"tyre friction {mu:g}, wheels {mode}", _f(1e3 * d),
                         "", _f(x), math.nan, math.nan, math.nan, ""))
    for p in study.friction_points:
        rows.append(("friction effect", f"mu_c {p.mu_c:g}, r {p.recovery:.3g}",
                     1e3 * p.duration, "", p.marginal, p.cumulative,
                     _speed(p.change.delta_v, units)[0], _yaw(p.change.yaw_rate, units), ""))
    for lad in study.ladders:
        if lad.shift is not None:
            rows.append(("where C is", "centroid against C", 1e3 * lad.duration, "",
                         lad.shift.error, math.nan, _speed(lad.shift.change.delta_v, units)[0],
                         _yaw(lad.shift.change.yaw_rate, units), ""))
    v = _speed(0.0, units)[1]
    columns = ("part", "rung", "contact time [ms]", "scene", "marginal effect [-]",
               "cumulative (PIM's error) [-]", f"delta-V change [{v}]",
               "yaw-rate change [deg/s]", "failure")
    return Table(name, "Every scene of the study", columns, tuple(rows),
                 {c: fmt_error for c in columns[4:6]})


def _plot_ladder(ax, study: AssumptionStudy) -> None:
    rungs = study.typical.rungs[1:]
    x = np.arange(len(rungs))
    ax.bar(x - 0.2, [100 * r.marginal for r in rungs], 0.4,
           label=f"marginal at {1e3 * study.typical.duration:g} ms")
    ax.bar(x + 0.2, [100 * r.cumulative for r in rungs], 0.4, label="cumulative (PIM's error)")
    for i, rung in enumerate(rungs):
        er = study.friction_over() if rung.key == "friction" else study.over_range(rung.key)
        if er is not None and rung.key != "law":
            lo, hi = er.extremes("marginal")
            ax.plot([i - 0.2] * 2, [100 * lo, 100 * hi], color="k", lw=1.5)
    ax.plot([], [], color="k", lw=1.5, label="marginal over the range")
    ax.set_xticks(x, [r.key.replace("_", "\n") for r in rungs], fontsize=8)
    ax.set_title("the ladder (bars: typical; lines: over 50-150 ms and r)", fontsize=10)


def _plot_durations(ax, study: AssumptionStudy) -> None:
    ms = 1e3 * study.durations
    for r in study.typical.rungs[1:]:
        if r.key != "law":
            ax.plot(ms, 100 * study.effect(r.key), "o-", ms=3, label=r.key)
    lo, hi = study.contact_range
    ax.axvspan(1e3 * lo, 1e3 * hi, color="0.9", zorder=0, label="contact-time range")
    ax.set_xlabel("contact time [ms]")
    ax.set_title("marginal effect of each assumption over the contact time", fontsize=10)


def _plot_tyres(ax, study: AssumptionStudy) -> None:
    mus = sorted({mu for _, mu in study.tyre_curves})
    for (mode, mu), values in study.tyre_curves.items():
        ax.plot(1e3 * study.durations, 100 * values, "o-" if mode == "rolling" else "s--",
                ms=3, color=f"C{mus.index(mu)}", label=f"tyre friction {mu:g}, wheels {mode}")
    ax.set_xlabel("contact time [ms]")
    ax.set_title("tyre effect (tyres vs none, same contact time)", fontsize=10)


def _plot_friction(ax, study: AssumptionStudy) -> None:
    d = TYPICAL["duration"]
    pts = [p for p in study.friction_points if p.duration == d]
    for r in sorted({p.recovery for p in pts}):
        sel = [p for p in pts if p.recovery == r]
        ax.plot([p.mu_c for p in sel], [100 * p.marginal for p in sel], "o-", ms=3,
                label=f"tangential recovery r = {r:.3g}")
    ax.set_xlabel("friction between the vehicles mu_c [-]")
    ax.set_title(f"friction effect at {1e3 * d:g} ms (Coulomb vs PIM's law)", fontsize=10)


def plot_overview(study: AssumptionStudy):
    """The ladder with its ranges, effects over the contact time, tyres rolling and locked,
    friction over mu_c and r (a Figure)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12, 8), layout="constrained")
    (a, b), (c, d) = fig.subplots(2, 2)
    _plot_ladder(a, study)
    _plot_durations(b, study)
    _plot_tyres(c, study)
    _plot_friction(d, study)
    for ax in (a, b, c, d):
        ax.axhline(100 * HOLDS, color="0.6", lw=0.8, ls=":")
        ax.set_ylabel("impact error [%]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{study.case.name or 'case'}: PIM's assumptions one at a time "
                 f"(epsilon = {study.eps:.3g}, PIM at beta = {study.beta_pim:g})", fontsize=11)
    return fig


# -- documents ------------------------------------------------------------------------------

def write_assumptions(study: AssumptionStudy, out_dir, *, animation: bool = True,
                      progress: bool | None = None, command: str = "",
                      units=None) -> list[Path]:
    """Write the plot (PNG), the MP4 (with ``animation``) and the report
    (:func:`assumptions_document`: the tables as CSV, assumptions.html, assumptions.md) to
    ``out_dir``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = [save_figure(plot_overview(study), out / "assumptions.png")]
    info = _write_animation(study, out, progress) if animation else None
    if info is not None:
        files.append(info.path)
    doc = assumptions_document(study, info, command, units)
    return [*write_document(doc, out), *files]


def _write_animation(study: AssumptionStudy, out: Path, progress):
    r = study.animation_result
    if r is None:
        return None
    ghost = pim.solve(study.case, study.eps, study.beta_pim)
    renderer = build_renderer(
        study.case, study.eps, study.beta_pim, result=ghost, simulated=r, tyre=0.0,
        after=max(0.1, float(r.trajectory.time[-1]) - 0.05),
        title=f"{study.case.name or 'case'}: finite-duration crush ({r.geometry}, "
              f"{1e3 * r.contact_duration:.0f} ms), PIM ghost eps = {study.eps:.3g}, "
              f"beta = {study.beta_pim:g}")
    return write_animation(renderer, out / "assumptions.mp4", progress=progress)


def _about(study: AssumptionStudy) -> str:
    return (f"A ladder of finite-duration crush scenes (docs/contact-model.md), each "
            f"differing from its baseline in one assumption of PIM; epsilon = "
            f"{study.eps:.4g}, PIM at beta = {study.beta_pim:g}. The *marginal* effect of "
            f"an assumption is the impact error between its scene and its baseline at the "
            f"same contact time; the *cumulative* one is PIM's error against the scene (PIM "
            f"at the scene's impact configuration). Each is also said as the delta-V and the "
            f"yaw rate it moves (the larger of the two vehicles). Impact error: "
            f"{ERROR_DEFINITION} (sim.error_measure.impact_error). Every verdict spans the "
            f"unmeasured parameters: {_contact_words(study)} (McHenry's range; "
            f"docs/contact-model.md) and, for friction, the tangential recovery r from 0 to "
            f"1.")


def _where_c(study: AssumptionStudy, units) -> Section:
    """Where C is: the sentence and its table (the table only as CSV without outlines)."""
    words = input_shift_words(study, units)
    table = input_shift_table(study, units=units)
    if not words:
        return Section("where-c", "Where C is (input uncertainty, not a rung)", (
            Paragraph("The case gives no outlines."), replace(table, show=False)))
    return Section("where-c", "Where C is (input uncertainty, not a rung)",
                   (Paragraph(words), table), toc="Where C is")


def _animation(info) -> Section:
    """The finite-duration scene with PIM's ghost, and a warning of a second impact."""
    video = Video("assumptions.mp4", "The finite-duration scene (filled) with PIM's answer "
                  "as a dashed ghost.", frames=info.frames, fps=info.fps, size=info.size)
    warning = () if info.secondary_impact is None else (
        Callout("Warning", (f"{info.secondary_impact.message()}.",)),)
    return Section("animation", "Animation", (video, *warning))


def assumptions_document(study: AssumptionStudy, info=None, command: str = "",
                         units=None) -> Document:
    """The study as a report: the verdicts first, where C is, the ladder's table (in
    column groups one screen wide, :data:`ASSUMPTION_GROUPS`), the plots, every scene (CSV),
    the animation (``info``: what :func:`comparisons.animation.render.write_animation`
    returned, or None) and the method. No wall times: a document regenerated by
    ``comparisons.docs_numbers`` holds only what the code gives."""
    ms = f"{1e3 * study.typical.duration:g} ms"
    ladder = replace(assumption_table(study, units=units), groups=ASSUMPTION_GROUPS)
    sections = [
        Section("verdicts", "Verdicts", (Bullets(tuple(verdicts(study, units))),), keep=True),
        _where_c(study, units),
        Section("typical", f"The ladder at {ms} and over the range", (ladder, Paragraph(
            "eps_eff, beta_eff: what `pim fit` (velocities and yaw rates) needs to reproduce "
            "the simulated motion; C_eff: the impulse centroid.")), toc="The ladder"),
        Section("sweeps", "Over contact times, tyre friction and the tangential recovery", (
            Figure("assumptions.png", alt="the ladder's effects"),
            Paragraph("Every scene of the study:"), FileList(("assumption_sweeps.csv",)),
            replace(sweep_table(study, units=units), show=False)), toc="Plots")]
    if info is not None:
        sections.append(_animation(info))
    sections.append(Section("method", "Method", (Paragraph(_about(study)),)))
    return Document(f"{study.case.name or 'case'}: PIM's assumptions one at a time",
                    "pim assumptions", tuple(sections),
                    subtitle=f"Regenerate with `{command}`." if command else "",
                    name="assumptions")


def _change_json(c: Change, units) -> dict:
    return {"delta_v": _speed(c.delta_v, units)[0], "yaw_rate": _yaw(c.yaw_rate, units)}


def study_json(study: AssumptionStudy, units=None) -> dict:
    """The study for ``--json``: verdicts, every ladder's rungs with their effects in % and
    in the case's units (named under ``units``), where C is."""
    units = shown_units(study.case, units)
    shift = study.input_shift
    return {
        "case": study.case.name, "eps": study.eps, "beta": study.beta,
        "beta_pim": study.beta_pim, "engine": study.engine,
        "units": {"delta_v": _speed(0.0, units)[1], "yaw_rate": "deg/s"},
        "contact_range_ms": [1e3 * t for t in study.contact_range],
        "verdicts": verdicts(study, units), "where_c": input_shift_words(study, units),
        "input_shift": None if shift is None else {
            "distance_m": shift.distance, "turn_deg": shift.turn,
            "pim_error": shift.pim_error, **_change_json(shift.pim_change, units)},
        "ladders": [{"contact_time_ms": 1e3 * lad.duration, "rungs": [
            {"key": r.key, "against": r.baseline, "marginal": r.marginal,
             "cumulative": r.cumulative, **_change_json(r.change, units),
             "failure": r.run.failure} for r in lad.rungs[1:]]} for lad in study.ladders]}
