"""Tables, verdicts, plot, JSON and files of the tuned-scene study
(:mod:`comparisons.studies.tuned_scene`).

Consumes :class:`comparisons.studies.tuned_scene.ClassStudy` objects; speaks the user's units
(``units`` "si" or "us" through :func:`pim.io.units.convert`); the report is a
:class:`~comparisons.report.document.Document` (:func:`tuned_document`) written through the
one pipeline (:func:`comparisons.report.write.write_document`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from comparisons.report.document import Bullets, Document, Figure, Paragraph, Section
from comparisons.report.tables import Table
from comparisons.report.write import write_document
from comparisons.studies.crash_records import CLASS_KEYS, UNRUNNABLE
from comparisons.studies.contact_time import (
    LEVEL,
    MECHANISM_TIMES,
    PHYSICAL_TIMES,
    PROFILE_STARTS,
    THRESHOLD_RULE,
)
from comparisons.studies.paired_verdict import (
    ALPHA,
    CONFIDENCE,
    PIM_BETTER,
    RESAMPLES,
    SCENE_BETTER,
    minimum_tests,
)
from comparisons.studies.tuned_scene import (
    AGREEMENT,
    CLASS_STARTS,
    LOO_STARTS,
    MODELS,
    PENALTY_STEP,
    PHYSICAL_RANGES,
    SCENE_MODELS,
    SCENE_PHYSICAL_MODEL,
    SCREEN,
    UNCONSTRAINED_MODELS,
    ClassStudy,
)
from pim.io.datasets import ORIGIN_KINDS, PIM_OUTPUT
from pim.io.files import save_figure
from pim.io.units import convert, display_units

__all__ = ["KINDS", "median_errors", "predictions_table", "summary_table", "verdict_table",
           "origins_table", "verdict_sentence", "plot_tuned_study", "study_json",
           "write_tuned_study", "tuned_document", "FILES", "profile_table", "mechanism_table",
           "plot_profiles", "conclusion", "physical_sentence", "profile_sentence",
           "mechanism_sentence"]

KINDS = ("class fit", "leave-one-out")
#: The files :func:`write_tuned_study` writes, in its order.
FILES = ("tuned-scene.md", "tuned-scene.html", "tuned-scene-profile.csv",
         "tuned-scene-mechanisms.csv", "tuned-scene-verdicts.csv", "tuned-scene-summary.csv",
         "tuned-scene-predictions.csv", "tuned-scene.png", "tuned-scene-profile.png")
_KEY = {name: key for key, name in CLASS_KEYS.items()}


def _speed(x, units) -> float:
    return float(convert(x, "speed", units)[0])


def _unit(units) -> str:
    return convert(1.0, "speed", units)[1]


def _f(digits: int):
    return lambda x: "" if x is None or x != x else f"{x:.{digits}f}"


def median_errors(rows) -> dict:
    """Median score [-], velocity error [m/s], yaw error [rad/s] of prediction rows, the
    failed ones (NaN) counted apart."""
    ok = [r for r in rows if math.isfinite(r.velocity_error)]
    med = (lambda a: float(np.median([getattr(r, a) for r in ok]))) if ok else \
        (lambda a: math.nan)
    return {"n": len(rows), "failed": len(rows) - len(ok), "score": med("score"),
            "v": med("velocity_error"), "yaw": med("yaw_error"),
            "flagged": sum(bool(r.flags) for r in rows)}


def predictions_table(studies, units: str = "si") -> Table:
    """Every prediction: class, variant, test, model, kind, parameters, errors, the scene's
    contact time, crush and friction, and the physical-range flags."""
    su = _unit(units)
    rows = [(st.crash_class, p.variant, p.test, p.model, p.kind,
             " ".join(f"{v:.4g}" for v in p.x), p.score, _speed(p.delta_v_error, units),
             _speed(p.velocity_error, units), math.degrees(p.yaw_error),
             p.contact_time * 1e3, p.peak_crush, p.friction, ", ".join(p.flags))
            for st in studies for v in st.variants for p in v.predictions]
    return Table("tuned-scene-predictions",
                 "Each test predicted by each model with the class parameters and with the "
                 "class parameters refitted without it (leave-one-out)",
                 ("class", "variant", "test", "model", "kind", "parameters", "score [-]",
                  f"delta-V error [{su}]", f"velocity error [{su}]", "yaw error [deg/s]",
                  "contact time [ms]", "peak crush [m]", "friction [-]",
                  "outside the physical ranges"), tuple(rows),
                 {"score [-]": _f(2), f"delta-V error [{su}]": _f(2),
                  f"velocity error [{su}]": _f(2), "yaw error [deg/s]": _f(1),
                  "contact time [ms]": _f(0), "peak crush [m]": _f(2), "friction [-]": _f(2)})


def _fit_text(fit) -> str:
    return (f"{fit.agreeing}/{fit.starts}" if fit is not None else "")


def _loo_agreement(fits) -> str:
    if not fits:
        return ""
    a = [f.agreeing for f in fits]
    return f"{min(a)}-{max(a)} of {fits[0].starts} (median {np.median(a):g})"


def summary_table(studies, units: str = "si") -> Table:
    """Per class, variant and model: the class fit (rms, parameters, starts that reached
    it) and the medians of the leave-one-out errors."""
    su = _unit(units)
    rows = []
    for st in studies:
        for v in st.variants:
            for m in MODELS:
                loo, fit = median_errors(v.rows(m.name, "leave-one-out")), v.class_fits[m.name]
                rows.append((st.crash_class, v.variant.name, m.name, len(st.tests),
                             fit.rms, " ".join(f"{x:.3g}" for x in fit.x), _fit_text(fit),
                             ", ".join(fit.on_bound), _loo_agreement(v.loo_fits[m.name]),
                             loo["score"], _speed(loo["v"], units), math.degrees(loo["yaw"]),
                             loo["failed"], loo["flagged"]))
    return Table("tuned-scene-summary", "Class fits and median leave-one-out errors per class, "
                 "input variant and model",
                 ("class", "variant", "model", "tests", "class-fit rms [-]",
                  "class parameters", "starts at the best", "on a bound",
                  "leave-one-out starts at the best", "median score [-]",
                  f"median velocity error [{su}]", "median yaw error [deg/s]", "failed",
                  "flagged"), tuple(rows),
                 {"class-fit rms [-]": _f(3), "median score [-]": _f(2),
                  f"median velocity error [{su}]": _f(2), "median yaw error [deg/s]": _f(1)})


def _p(p) -> str:
    return "" if p is None else f"{p:.2g}"


def verdict_table(studies) -> Table:
    """Per class, variant and scene model: the verdict, the p-values of the paired
    signed-rank tests and the bootstrap interval of the median score difference."""
    rows = []
    for st in studies:
        for v in st.variants:
            for s in SCENE_MODELS:
                c = v.comparisons[s.name]
                lo, hi = c["score"].interval
                rows.append((st.crash_class, v.variant.name, s.name, c["score"].n,
                             c["score"].verdict, c["score"].p_value, c["velocity"].p_value,
                             c["yaw"].p_value, c["score"].median_difference, lo, hi))
    pct = f"{CONFIDENCE:.0%}"
    return Table("tuned-scene-verdicts", "PIM against the scene on the held-out tests: paired "
                 "Wilcoxon signed-rank tests and the bootstrap interval of the median "
                 "difference of the score (scene minus PIM; negative: the scene errs less)",
                 ("class", "variant", "scene", "tests", "verdict", "p (score)",
                  "p (velocity)", "p (yaw rate)", "median score difference [-]",
                  f"{pct} interval low [-]", f"{pct} interval high [-]"), tuple(rows),
                 {"p (score)": _p, "p (velocity)": _p, "p (yaw rate)": _p,
                  "median score difference [-]": _f(2), f"{pct} interval low [-]": _f(2),
                  f"{pct} interval high [-]": _f(2)})


def origins_table(studies) -> Table:
    """Where each input of each class comes from; an input a variant takes otherwise names
    the variant."""
    rows = []
    for st in studies:
        first, *others = st.variants
        for name, origin in first.variant.origins.items():
            alt = [f"{v.variant.name}: {v.variant.origins[name]}" for v in others
                   if v.variant.origins.get(name, origin) != origin]
            text = f"{first.variant.name}: {origin}; " + "; ".join(alt) if alt else origin
            rows.append((st.crash_class, name, text))
        rows.append((st.crash_class, "outcome (fitted and judged)", st.outcome_origin))
    return Table("tuned-scene-origins", "Where each input comes from",
                 ("class", "input", "origin"), tuple(rows), csv=False)


def verdict_sentence(study: ClassStudy, variant, units: str = "si") -> str:
    """One sentence: the verdict of a class under one variant, with its numbers."""
    su = _unit(units)
    c = variant.comparisons["scene"]
    a = median_errors(variant.rows("pim", "leave-one-out"))
    b = median_errors(variant.rows("scene", "leave-one-out"))
    n = len(study.tests)
    head = f"{study.crash_class} ({n} test{'s' if n != 1 else ''}, {variant.variant.name})"
    if not a["n"]:
        return (f"{head}: {c['score'].verdict} (a class of one: no leave-one-out; fewer than "
                f"{minimum_tests(study.n_parameters)} tests).")
    lo, hi = c["score"].interval
    text = (f"{head}: {c['score'].verdict}. Leave-one-out medians: PIM "
            f"{_speed(a['v'], units):.2f} {su} and {math.degrees(a['yaw']):.1f} deg/s, the "
            f"scene (Coulomb mu_c) {_speed(b['v'], units):.2f} {su} and "
            f"{math.degrees(b['yaw']):.1f} deg/s; score difference "
            f"{c['score'].median_difference:+.2f} [{lo:+.2f}, {hi:+.2f}]")
    if c["score"].p_value is None:
        text += f" (fewer than {minimum_tests(study.n_parameters)} tests: no test run)"
    else:
        mu0 = variant.comparisons["scene-mu0"]["score"]
        text += (f", p = {c['score'].p_value:.2g} (velocity {c['velocity'].p_value:.2g}, "
                 f"yaw rate {c['yaw'].p_value:.2g}); with mu_c = b |mu0|: {mu0.verdict}")
    return text + _flag_note(variant) + "; " + physical_sentence(variant, units) + "."


def physical_sentence(variant, units: str = "si") -> str:
    """The physical scene's verdict against PIM with its p-value, interval and medians."""
    su = _unit(units)
    c = variant.comparisons[SCENE_PHYSICAL_MODEL.name]["score"]
    m = median_errors(variant.rows(SCENE_PHYSICAL_MODEL.name, "leave-one-out"))
    fit = variant.class_fits[SCENE_PHYSICAL_MODEL.name]
    lo, hi = c.interval
    p = "no test run" if c.p_value is None else f"p = {c.p_value:.2g}"
    flagged = m["flagged"]
    return (f"held to the physical ranges the scene (class fit rms {fit.rms:.2f}, "
            f"{_params_text(SCENE_PHYSICAL_MODEL, fit.x)}) gives: {c.verdict} "
            f"({p}; median score difference {c.median_difference:+.2f} [{lo:+.2f}, "
            f"{hi:+.2f}]; leave-one-out medians {_speed(m['v'], units):.2f} {su} and "
            f"{math.degrees(m['yaw']):.1f} deg/s; {flagged} of its {m['n']} held-out "
            f"predictions outside the ranges)")


def _params_text(model, x) -> str:
    return ", ".join(f"{n.split(' ')[0]} {v * 1e3:.0f} ms" if n.startswith("T")
                     else f"{n} {v:.2f}" for n, v in zip(model.parameters, x, strict=True))


def _flag_note(variant) -> str:
    """'; ... outside the physical ranges' for the unconstrained scenes' held-out
    predictions, or ''."""
    rows = [r for m in UNCONSTRAINED_MODELS for r in variant.rows(m.name, "leave-one-out")]
    flagged = [r for r in rows if r.flags]
    if not flagged:
        return ""
    names = sorted({f for r in flagged for f in r.flags})
    return (f"; {len(flagged)} of the scenes' {len(rows)} held-out predictions lie outside "
            f"the physical ranges ({', '.join(names)})")


def plot_tuned_study(studies, units: str = "si"):
    """Leave-one-out errors, the Coulomb scene against PIM, per class (first variant):
    velocity (top) and yaw rate (bottom); points below the diagonal are tests the scene
    predicts better. A Figure."""
    from matplotlib.figure import Figure

    su = _unit(units)
    shown = [st for st in studies if st.variants[0].rows("pim", "leave-one-out")]
    fig = Figure(figsize=(3.6 * max(len(shown), 1), 7.0), layout="constrained")
    axes = np.atleast_2d(fig.subplots(2, max(len(shown), 1), squeeze=False))
    for j, st in enumerate(shown):
        v = st.variants[0]
        pairs = list(zip(v.rows("pim", "leave-one-out"), v.rows("scene", "leave-one-out"),
                         strict=True))
        for i, (attr, scale, label) in enumerate(
                (("velocity_error", lambda x: _speed(x, units), f"velocity error [{su}]"),
                 ("yaw_error", math.degrees, "yaw-rate error [deg/s]"))):
            _scatter(axes[i, j], [scale(getattr(a, attr)) for a, _ in pairs],
                     [scale(getattr(b, attr)) for _, b in pairs], label)
            if i == 0:
                axes[i, j].set_title(f"{st.crash_class}\n{v.variant.name}, {len(pairs)} tests",
                                     fontsize=8)
    return fig


def _scatter(ax, xs, ys, label) -> None:
    ax.scatter(xs, ys, s=24, color="C0", edgecolors="k", linewidths=0.3)
    top = max([v for v in xs + ys if v == v] + [1e-3]) * 1.1
    ax.plot([0, top], [0, top], color="0.5", ls="--", lw=1)
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_xlabel(f"PIM, {label}", fontsize=8)
    ax.set_ylabel(f"scene, {label}", fontsize=8)
    ax.grid(alpha=0.3)


def _model_json(variant, model, units) -> dict:
    loo = median_errors(variant.rows(model.name, "leave-one-out"))
    fit, folds = variant.class_fits[model.name], variant.loo_fits[model.name]
    return {"label": model.label, "law": model.law, "parameters": list(model.parameters),
            "loo_velocity_median": _nan_none(loo["v"]),
            "loo_yaw_median": _nan_none(math.degrees(loo["yaw"])),
            "loo_velocity_median_user_units": _nan_none(_speed(loo["v"], units)),
            "loo_score_median": _nan_none(loo["score"]), "loo_failed": loo["failed"],
            "loo_flagged": loo["flagged"],
            "class_fit": {"x": dict(zip(model.parameters, fit.x, strict=True)),
                          "rms": fit.rms, "starts": fit.starts, "agreeing": fit.agreeing,
                          "converged": fit.converged, "on_bound": list(fit.on_bound)},
            "loo_starts": {"starts": folds[0].starts if folds else 0,
                           "agreeing": [f.agreeing for f in folds],
                           "converged": [f.converged for f in folds]}}


def _nan_none(x):
    return None if x is None or (isinstance(x, float) and math.isnan(x)) else x


def _comparison_json(c: dict) -> dict:
    s = c["score"]
    return {"verdict": s.verdict, "p_value": s.p_value, "p_value_velocity": c["velocity"].p_value,
            "p_value_yaw": c["yaw"].p_value, "tests": s.n,
            "median_score_difference": s.median_difference,
            "interval": list(s.interval), "scene_better": s.scene_better}


def _variant_json(variant, units) -> dict:
    primary = _comparison_json(variant.comparisons["scene"])
    return {"description": variant.variant.description, "origins": dict(variant.variant.origins),
            "verdict": primary["verdict"], "p_value": primary["p_value"],
            "physical": _physical_json(variant),
            "compared": "pim against scene (Coulomb mu_c), on the score",
            "comparisons": {k: _comparison_json(c) for k, c in variant.comparisons.items()},
            "models": {m.name: _model_json(variant, m, units) for m in MODELS}}


def _held_json(model_parameters, fit) -> dict:
    return {"x": dict(zip(model_parameters, fit.x, strict=True)), "rms": fit.rms,
            "starts": fit.starts, "agreeing": fit.agreeing, "converged": fit.converged,
            "on_bound": list(fit.on_bound)}


def _profile_json(p) -> dict | None:
    """The profile: T [s], score (class-fit rms), refitted parameters, the threshold."""
    if p is None:
        return None
    names = SCENE_PHYSICAL_MODEL.parameters
    return {"T": list(p.times), "score": [f.rms for f in p.fits],
            "parameters": [dict(zip(names, f.x, strict=True)) for f in p.fits],
            "agreeing": [f.agreeing for f in p.fits], "starts": PROFILE_STARTS,
            "threshold": p.threshold, "threshold_rule": THRESHOLD_RULE, "level": LEVEL,
            "n_residuals": p.n_residuals, "best_score": p.best_rms,
            "free_fit": _held_json(names, p.free), "kept_T": list(p.kept),
            "physical_T": list(PHYSICAL_TIMES),
            "physical_T_excluded": p.physical_excluded()}


def _physical_json(variant) -> dict:
    c = _comparison_json(variant.comparisons[SCENE_PHYSICAL_MODEL.name])
    fit = variant.class_fits[SCENE_PHYSICAL_MODEL.name]
    return c | {"class_fit": _held_json(SCENE_PHYSICAL_MODEL.parameters, fit),
                "box": dict(zip(SCENE_PHYSICAL_MODEL.parameters,
                                zip(SCENE_PHYSICAL_MODEL.lower, SCENE_PHYSICAL_MODEL.upper,
                                    strict=True), strict=True)),
                "outputs_held": [name for _, name in SCENE_PHYSICAL_MODEL.outputs],
                "penalty_step": dict(PENALTY_STEP)}


def _mechanisms_json(st) -> list:
    return [{"mechanism": m.mechanism.name, "switched_off": m.mechanism.label,
             "profile": _profile_json(m.profile), "rise_to_100ms": m.rise}
            for m in st.mechanisms]


def _class_json(st, units) -> dict:
    first = st.variants[0]
    return {"name": st.crash_class, "tests": list(st.tests), "observable": st.observable,
            "outcome_origin": st.outcome_origin, "n_parameters": st.n_parameters,
            "coarse_check": {"speed": st.coarse_check[0],
                             "yaw_rate_deg": math.degrees(st.coarse_check[1])},
            "physical": _physical_json(first) | {"variant": first.variant.name},
            "profile": _profile_json(st.profile), "mechanisms": _mechanisms_json(st),
            "conclusion": next(iter(conclusion([st], units)), None),
            "variants": {v.variant.name: _variant_json(v, units) for v in st.variants}}


def study_json(studies, units: str = "si", wall_time: float | None = None) -> dict:
    """The study as JSON-ready data: per class (keyed by :data:`CLASS_KEYS`) and input
    variant the verdict and p-value,
    per model the leave-one-out medians (velocity [m/s], yaw rate [deg/s]) and the
    multi-start agreement counts."""
    return {"units": display_units(units).to_json(), "speed_unit": _unit(units),
            "wall_time": wall_time,
            "alpha": ALPHA, "agreement": AGREEMENT, "screen": SCREEN,
            "class_starts": CLASS_STARTS, "loo_starts": LOO_STARTS,
            "physical_ranges": {k: list(v[:3]) for k, v in PHYSICAL_RANGES.items()},
            "unrunnable": dict(UNRUNNABLE),
            "classes": {_KEY.get(st.crash_class, st.crash_class): _class_json(st, units)
                        for st in studies}}


def profile_table(studies) -> Table:
    """Per class and held contact time: the class-fit rms, the threshold, whether the
    threshold keeps it and the refitted parameters."""
    rows = []
    for st in studies:
        p = st.profile
        if p is None:
            continue
        for t, f in zip(p.times, p.fits, strict=True):
            rows.append((st.crash_class, st.variants[0].variant.name, t * 1e3, f.rms,
                         p.threshold, f.rms <= p.threshold, *f.x[:2], f.x[3],
                         f"{f.agreeing}/{f.starts}"))
    return Table("tuned-scene-profile", "The class fit of the scene (Coulomb mu_c) with the "
                 "contact time T held, epsilon, mu_c and mu_tyre refitted at each T",
                 ("class", "variant", "T [ms]", "class-fit rms [-]", "threshold [-]",
                  "kept", "epsilon [-]", "mu_c [-]", "mu_tyre [-]", "starts at the best"),
                 tuple(rows), {"T [ms]": _f(0), "class-fit rms [-]": _f(3),
                               "threshold [-]": _f(3), "epsilon [-]": _f(3),
                               "mu_c [-]": _f(3), "mu_tyre [-]": _f(3)},
                 note=f"Threshold: {THRESHOLD_RULE}.")


def mechanism_table(studies) -> Table:
    """Per mechanism switched off: the free fit's T and rms, the threshold and the profile's
    rms at each of :data:`MECHANISM_TIMES`."""
    rows = []
    for st in studies:
        for m in st.mechanisms:
            p = m.profile
            rows.append((st.crash_class, m.mechanism.name, m.mechanism.label,
                         p.free.x[2] * 1e3, p.free.rms, p.threshold, *p.rms, m.rise))
    times = [f"rms at {t * 1e3:.0f} ms [-]" for t in MECHANISM_TIMES]
    return Table("tuned-scene-mechanisms", "The scene with one mechanism switched off at a "
                 "time: its free class fit and its profile over the contact time",
                 ("class", "mechanism", "switched off", "fitted T [ms]", "class-fit rms [-]",
                  "threshold [-]", *times, "rise to 100 ms [-]"), tuple(rows),
                 {"fitted T [ms]": _f(0), "class-fit rms [-]": _f(3), "threshold [-]": _f(3),
                  "rise to 100 ms [-]": _f(3)} | {c: _f(3) for c in times})


def plot_profiles(studies):
    """The class-fit rms against the held contact time per class, its threshold (dashed) and
    the physical contact times (shaded); the mechanisms' profiles in the last panel."""
    from matplotlib.figure import Figure

    shown = [st for st in studies if st.profile is not None]
    mech = [st for st in shown if st.mechanisms]
    n = max(len(shown) + len(mech), 1)
    fig = Figure(figsize=(3.4 * n, 3.4), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, n, squeeze=False)[0])
    for ax, st in zip(axes, shown, strict=False):
        _profile_axes(ax, st.crash_class, [("scene", st.profile)])
    for ax, st in zip(axes[len(shown):], mech, strict=False):
        _profile_axes(ax, f"{st.crash_class}:\none mechanism off",
                      [(m.mechanism.name, m.profile) for m in st.mechanisms])
    return fig


def _profile_axes(ax, title, profiles) -> None:
    ax.axvspan(*(t * 1e3 for t in PHYSICAL_TIMES), color="0.9", label="full-scale pulses")
    for i, (label, p) in enumerate(profiles):
        ax.plot(np.array(p.times) * 1e3, p.rms, "o-", color=f"C{i}", ms=3, label=label)
        ax.axhline(p.threshold, color=f"C{i}", ls="--", lw=0.8)
    ax.set_xlabel("contact time T held [ms]", fontsize=8)
    ax.set_ylabel("class-fit rms score [-]", fontsize=8)
    ax.set_title(title, fontsize=8)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6)


def profile_sentence(st) -> str:
    """What the profile says about T: the least rms, the threshold, the times it keeps and
    whether the physical contact times are excluded."""
    p = st.profile
    kept = p.kept
    span = (f"keeps {kept[0] * 1e3:.0f}-{kept[-1] * 1e3:.0f} ms" if kept else
            "keeps none of the grid")
    verdict = _profile_verdict(p)
    return (f"The profile over T (epsilon, mu_c, mu_tyre refitted at each of "
            f"{len(p.times)} times, {p.times[0] * 1e3:.0f}-{p.times[-1] * 1e3:.0f} ms): "
            f"class-fit rms {p.best_rms:.3f} at best (T free: {p.free.x[2] * 1e3:.0f} ms), "
            f"{p.at(0.1):.3f} at 100 ms; the {LEVEL:.0%} likelihood-ratio threshold "
            f"{p.threshold:.3f} ({p.n_residuals} residuals) {span}: {verdict}.")


def _profile_verdict(p) -> str:
    """What the times the threshold keeps say about instantaneous against finite contact."""
    phys = f"{PHYSICAL_TIMES[0] * 1e3:.0f}-{PHYSICAL_TIMES[1] * 1e3:.0f} ms"
    kept = p.kept
    if not kept:
        return (f"no held time comes within the threshold of the free fit's "
                f"(T {p.free.x[2] * 1e3:.0f} ms): the grid is too coarse to say more")
    if p.physical_excluded():
        return (f"the tests exclude the full-scale contact time {phys}: at the times a real "
                "crash pulse lasts this scene fits them worse than the threshold allows, so "
                "in it they favour a near-instant contact, as PIM assumes")
    if len(kept) == len(p.times):
        return ("the tests do not constrain the contact time: an instant and a "
                f"{phys} contact fit them alike, so they neither contradict nor support "
                "PIM's instantaneous impact")
    if p.times[0] not in kept:
        return (f"the tests exclude a near-instant contact (T up to "
                f"{max(t for t in p.times if t < kept[0]) * 1e3:.0f} ms) and keep the "
                f"full-scale {phys}: in this scene they favour a finite contact over PIM's "
                "instant")
    return f"the tests constrain the contact time to a span that overlaps the full-scale {phys}"


def mechanism_sentence(st) -> str:
    """Which mechanism pushes T down: the one whose removal flattens the profile most."""
    if not st.mechanisms:
        return ""
    full, *off = st.mechanisms
    flat = min(off, key=lambda m: m.rise)
    parts = "; ".join(f"{m.mechanism.name}: fitted T {m.profile.free.x[2] * 1e3:.0f} ms, "
                      f"rms {m.profile.free.rms:.3f}, rise {m.rise:+.3f}" for m in off)
    name = flat.mechanism.label.split(":")[0]
    if len(flat.profile.kept) == len(flat.profile.times):
        why = (f"with {name} switched off the profile stays within its threshold from "
               f"{flat.profile.times[0] * 1e3:.0f} to {flat.profile.times[-1] * 1e3:.0f} ms "
               f"(rms {flat.profile.at(0.1):.3f} at 100 ms against {flat.profile.threshold:.3f})"
               f": that mechanism is what pushes T to its bound, and the tests' preference "
               f"for a short contact is a preference for a contact without it, not for an "
               f"instant as such")
    else:
        why = (f"the profile is flattest with {name} switched off, but T stays constrained "
               "without any one of them")
    return (f"Switching off one mechanism at a time (the full scene: fitted T "
            f"{full.profile.free.x[2] * 1e3:.0f} ms, class-fit rms {full.profile.free.rms:.3f},"
            f" rising {full.rise:+.3f} from its least to 100 ms; {parts}): {why}.")


def _physical_reading(variant) -> str:
    """What the physical scene's verdict means, where it has one."""
    c = variant.comparisons[SCENE_PHYSICAL_MODEL.name]["score"]
    if c.verdict == PIM_BETTER:
        return (": with physical contact time and friction the finite contact does not "
                "reproduce these tests as well as PIM does; the freely fitted scene matches "
                "PIM only outside the physical ranges")
    if c.verdict == SCENE_BETTER:
        return ": a finite contact with physical values predicts these tests better than PIM"
    return ""


def conclusion(studies, units: str = "si") -> tuple[str, ...]:
    """One paragraph per class: what the tests support (instantaneous or finite contact:
    the profile's numbers), the physical scene's verdict and, where studied, the mechanism
    that pushes T down."""
    out = []
    for st in studies:
        if st.profile is None:
            continue
        v = st.variants[0]
        n = len(st.tests)
        head = f"**{st.crash_class}** ({n} test{'s' if n != 1 else ''}, {v.variant.name})."
        verdict = (f" PIM against the scene fitted freely: {v.verdict.verdict}; "
                   f"{physical_sentence(v, units)}{_physical_reading(v)}."
                   if v.rows("pim", "leave-one-out") else " A class of one: no held-out "
                   "verdict.")
        caveat = (f"Caveat: this class's outcome is {st.outcome_origin}, not a measurement, "
                  "so PIM fits it by construction and its preference says nothing about "
                  "real contact." if st.outcome_origin == PIM_OUTPUT else "")
        out.append(" ".join(filter(None, [head + verdict, profile_sentence(st),
                                          mechanism_sentence(st), caveat])))
    return tuple(out)


def _method_lines() -> list[str]:
    ranges = "; ".join(f"{k} {lo:g}-{hi:g} {u}: {why}"
                       for k, (lo, hi, u, why) in PHYSICAL_RANGES.items())
    return [
        "Models: PIM (epsilon, beta; mu = beta mu0); the scene with Coulomb friction (epsilon, "
        "mu_c, T, mu_tyre); the scene with mu_c = b |mu0| (epsilon, b, T, mu_tyre), mu0 "
        "PIM's critical impulse ratio of the test's own inputs. Score: root-mean-square of a "
        "test's residuals scaled by 1 mph and 10 deg/s (the fits' objective).",
        f"Fits: a {SCREEN}-point Sobol screen, the best {CLASS_STARTS['scene']} (scene) or "
        f"{CLASS_STARTS['pim']} (PIM) points refined by the batched Levenberg-Marquardt "
        f"engine for the class fit, the best {LOO_STARTS['scene']} for each leave-one-out "
        f"refit; a start 'reached the best' when its rms is within {AGREEMENT:.0%} of the "
        "best's.",
        f"Verdicts: paired Wilcoxon signed-rank test of the leave-one-out scores, level "
        f"{ALPHA:g}; the median difference with a {CONFIDENCE:.0%} percentile-bootstrap "
        f"interval ({RESAMPLES} resamples); no verdict below the larger model's parameters "
        "+ 2 tests.",
        f"Physical ranges of the fitted scene, flagged outside them: {ranges}.",
        f"The scene in physical ranges ({SCENE_PHYSICAL_MODEL.name}): the Coulomb scene with "
        "T, mu_c and mu_tyre boxed to those ranges and its contact's duration and peak crush "
        f"held inside them while fitting (every {PENALTY_STEP['contact_time'] * 1e3:g} ms or "
        f"{PENALTY_STEP['peak_crush'] * 1e3:g} mm outside adds one to the test's residuals; "
        "its class-fit rms includes that), on the same multi-start and leave-one-out "
        "machinery, with its own paired test and interval against PIM.",
        f"Profile over the contact time: the Coulomb scene's class fit (first input variant) "
        f"with T held, epsilon, mu_c and mu_tyre refitted at each T ({PROFILE_STARTS} starts "
        f"from a Sobol screen); threshold: {THRESHOLD_RULE}. The rule estimates the "
        "residual variance from the fit (the 1 mph / 10 deg/s scale is a tolerance, not a "
        "measured error); it is asymptotic and treats a test's residuals as independent.",
        "Mechanisms: on the non-sideswipe class, the scene with one of its ways of "
        "depending on T switched off at a time (the geometry change during contact frozen "
        "at the start; no tyre forces; plastic tangential recovery), each with its free fit "
        "and a coarse profile (comparisons/studies/contact_time.py)."]


def _verdict_lines(studies, units) -> tuple[str, ...]:
    return tuple([verdict_sentence(st, v, units) for st in studies for v in st.variants]
                 + [f"{name}: not run ({why})." for name, why in UNRUNNABLE.items()])


def tuned_document(studies, units: str = "si", command: str = "") -> Document:
    """tuned-scene.md and .html: the conclusion first, the verdicts, then the method, the
    plot, the contact time's profile and mechanisms, the verdict statistics, the class fits, the inputs' origins, the coarse scene's check and every
    prediction."""
    su = _unit(units)
    head = (Paragraph(f"Written by `{command}`; every number below comes from that run."),) \
        if command else ()
    coarse = tuple(f"{st.crash_class}: {_speed(st.coarse_check[0], units):.3f} {su}, "
                   f"{math.degrees(st.coarse_check[1]):.2f} deg/s" for st in studies)
    origins = "Origins: " + "; ".join(f"{k}: {v}" for k, v in ORIGIN_KINDS.items()) + "."
    sections = (
        Section("conclusion", "Conclusion: instantaneous or finite contact?",
                (*head, *(Paragraph(p) for p in conclusion(studies, units))), keep=True),
        Section("verdicts", "Verdicts", (Bullets(_verdict_lines(studies, units)),),
                keep=True),
        Section("method", "Method", (Bullets(tuple(_method_lines())), Figure(
            "tuned-scene.png", alt="leave-one-out errors, scene against PIM"))),
        Section("profile", "The contact time: profile and mechanisms",
                (Figure("tuned-scene-profile.png", alt="class-fit score over the contact "
                        "time"), profile_table(studies), mechanism_table(studies))),
        Section("statistics", "Verdict statistics", (verdict_table(studies),)),
        Section("fits", "Class fits and medians", (summary_table(studies, units),)),
        Section("origins", "Where each input comes from",
                (origins_table(studies), Paragraph(origins))),
        Section("coarse", "Coarse scene against a 10x finer one (class parameters)",
                (Bullets(coarse),)),
        Section("predictions", "Every prediction", (predictions_table(studies, units),)))
    return Document("The finite-duration scene tuned to crash tests, against PIM",
                    "pim validate-models", sections, name="tuned-scene")


def write_tuned_study(studies, out_dir, units: str = "si", command: str = "") -> list[Path]:
    """Write :data:`FILES` into ``out_dir``: tuned-scene.md and .html, the summary, verdict,
    profile, mechanism and prediction tables as CSV, the plots."""
    out = Path(out_dir)
    png = save_figure(plot_tuned_study(studies, units), out / "tuned-scene.png")
    profile = save_figure(plot_profiles(studies), out / "tuned-scene-profile.png")
    written = write_document(tuned_document(studies, units, command), out)
    return [written[-1], written[-2], *written[:-2], png, profile]
