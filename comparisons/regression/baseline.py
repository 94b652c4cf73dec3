"""Regression baselines: record a case's outputs with tolerances, and check them later.

``pim baseline CASE... --out baseline.json`` stores, per case, every output the case supports
(:mod:`comparisons.regression.sections`: solve, fit, the rigid cross-check, the Monte Carlo,
reconstruct, and on request the assumptions at their typical values), the SHA-256 of the
case file, the project's and its dependencies' versions, and a tolerance per quantity.
``pim check baseline.json`` reruns them and lists what moved beyond its tolerance.

A baseline may also carry *references*: values from an independent source (a published
sheet, a staged test, a law of physics) with their own tolerance and the source cited beside
them; ``check`` holds today's value to those too. Values are SI; each quantity states its
unit (docs/regression.md has the format).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import platform
import time
import tomllib
from dataclasses import asdict, dataclass, field
from importlib import metadata, resources
from pathlib import Path

import numpy as np

import pim
from comparisons.regression.sections import (
    DEFAULT_SECTIONS,
    DEFAULT_SETTINGS,
    SECTIONS,
    run_section,
)
from pim.io.units import SI_UNITS, DisplayUnits, convert, quantity_text, registry
from pim.model.numbers import InputError
from pim.model.plausibility import Findings, findings
from sim.error_measure import ERROR_DEFINITION, impact_error

__all__ = ["FORMAT", "cases_findings", "make_baseline", "record_case", "load_baseline",
           "check_baseline",
           "CheckReport", "Drift", "format_report", "dumps_baseline", "case_source", "stored_path",
           "shown_case", "versions",
           "load_references", "assert_agrees", "agreement", "DEPENDENCIES", "SAME_VERSIONS_REL"]

#: Format tag of a baseline file.
FORMAT = "pim-baseline/1"
#: Distributions whose versions a baseline records (a change is reported by ``check``).
DEPENDENCIES = ("pim-harness", "numpy", "scipy", "pymunk", "numba", "pint")
#: What "bit for bit" allows for the seeded Monte Carlo on the same versions [-]: the same
#: numpy picks its SIMD sine and cosine by CPU, which may differ in the last bit or two, and
#: a reconstruction's fits amplify that (2.5e-10 relative in a speed on another Xeon).
SAME_VERSIONS_REL = 1e-8
UNITS_NOTE = ("SI: every value is in the SI unit of its 'unit' field (m/s, rad/s, N*s, J, "
              "rad, kg, dimensionless; percent shares in %)")
#: Columns of a drift that are values in its unit (shown in the user's units).
DRIFT_VALUES = ("baseline", "now", "difference", "tolerance")


def versions() -> dict:
    """Python, platform and the :data:`DEPENDENCIES`' installed versions."""
    out = {"python": platform.python_version(), "machine": platform.machine()}
    for name in DEPENDENCIES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = None
    return out


def case_source(case: str, base: Path | None = None) -> tuple[str, bytes]:
    """Where a case comes from and its file's bytes: a bundled name as in
    :func:`pim.load_case`, else a path (relative ones against ``base``, the baseline's
    folder, when given).

    Raises
    ------
    ValueError
        Neither a file nor a bundled case; for an absolute path that is gone (a baseline
        recorded before paths were stored relative to it, then moved) the message says so
        and what to do.
    """
    path = Path(case)
    if base is not None and not path.is_absolute():
        path = base / path
    if path.is_file():
        return str(path), path.read_bytes()
    bundled = resources.files("pim.io") / "cases" / f"{case}.toml"
    if "/" not in case and bundled.is_file():
        return f"bundled:{case}", bundled.read_bytes()
    if Path(case).is_absolute():
        raise InputError(f"case {case!r}: no such file; the baseline stores this absolute path "
                         f"(recorded before pim stored case paths relative to the baseline "
                         f"file): restore the file there, or record the baseline again with "
                         f"pim baseline (it then moves with its cases)")
    where = f" (relative to the baseline's folder {base})" if base is not None else ""
    raise InputError(f"case {case!r}{where}: neither a file nor a bundled case (pim cases "
                     f"lists them)")


def stored_path(label: str, base: Path | None) -> str:
    """How a baseline stores a case file: its path relative to the baseline's folder
    ``base`` (``../cases/my-case.toml``), so that a project moved or cloned elsewhere keeps
    finding it; absolute only where no relative path exists (another drive) or without
    ``base``."""
    path = Path(label).resolve()
    if base is None:
        return str(path)
    try:
        return Path(os.path.relpath(path, Path(base).resolve())).as_posix()
    except ValueError:          # another drive: no relative path
        return str(path)


def _load(label: str) -> pim.Case:
    return pim.load_case(label[len("bundled:"):] if label.startswith("bundled:") else label)


def _json_float(x: float):
    return None if x is None or not math.isfinite(x) else float(x)


def record_case(case: str, sections=DEFAULT_SECTIONS, settings: dict | None = None,
                base: Path | None = None) -> dict:
    """One case's entry of a baseline: hash, sections run or skipped (why), quantities.

    ``case`` is stored as given when bundled, else as its path relative to ``base`` (the
    baseline's folder; :func:`stored_path`), so that a committed baseline moves with its
    cases.
    """
    settings = {**DEFAULT_SETTINGS, **(settings or {})}
    label, data = case_source(case)
    loaded = _load(label)
    stored = case if label.startswith("bundled:") else stored_path(label, base)
    entry = {"case": stored, "name": loaded.name, "sha256": hashlib.sha256(data).hexdigest(),
             "units_of_case": loaded.units, "settings": settings, "sections": [],
             "skipped": {}, "seconds": {}, "quantities": {}, "references": {}}
    for section in SECTIONS:
        if section not in sections:
            continue
        start = time.perf_counter()
        try:
            rows = run_section(section, loaded, settings)
        except LookupError as exc:
            entry["skipped"][section] = str(exc)
            continue
        entry["sections"].append(section)
        entry["seconds"][section] = round(time.perf_counter() - start, 3)
        for r in rows:
            entry["quantities"][r.name] = {
                "value": _json_float(r.value), "unit": r.unit, "kind": r.kind,
                "tolerance": {"absolute": r.absolute, "relative": r.relative},
                "tolerance_basis": r.basis, "exact_same_versions": r.exact_same_versions}
    return entry


def make_baseline(cases, sections=DEFAULT_SECTIONS, settings: dict | None = None,
                  base: Path | None = None, references: dict | None = None,
                  progress=None) -> dict:
    """A baseline document for several cases (see the module notes).

    Parameters
    ----------
    cases : iterable of str
        Bundled names or case file paths.
    sections : iterable of str
        Sections to record (:data:`comparisons.regression.sections.SECTIONS`).
    settings : dict, optional
        Monte Carlo sample counts and seed (default
        :data:`comparisons.regression.sections.DEFAULT_SETTINGS`).
    base : Path, optional
        The folder the baseline will be written to: case files are stored by their path
        relative to it (:func:`stored_path`; without ``base``, absolute).
    references : dict, optional
        Case name -> {quantity -> reference} (:func:`load_references`).
    progress : callable, optional
        Called with each case name before it is recorded.
    """
    sections = tuple(sections)
    for s in sections:
        if s not in SECTIONS:
            raise InputError(f"unknown section {s!r} (allowed: {', '.join(SECTIONS)})")
    out = {"format": FORMAT, "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
           "units": UNITS_NOTE, "versions": versions(), "sections": list(sections),
           "cases": []}
    for case in cases:
        if progress is not None:
            progress(case)
        entry = record_case(case, sections, settings, base)
        refs = (references or {}).get(entry["name"], {})
        entry["references"] = {k: v for k, v in refs.items()
                               if k.split(".")[0] in entry["sections"]}
        out["cases"].append(entry)
    return out


def _parse_value(text, kind: str, where: str) -> float:
    if isinstance(text, int | float) and not isinstance(text, bool):
        return float(text)
    try:
        q = registry().Quantity(str(text))
        return float(q.to(SI_UNITS[kind]).magnitude) if kind != "dimensionless" else \
            float(q.to("dimensionless").magnitude)
    except Exception as exc:   # pint raises several unrelated types for a bad unit
        raise InputError(f"{where}: cannot read {text!r} as {kind} ({exc})") from None


def dumps_baseline(doc: dict) -> str:
    """A baseline as JSON text: indented, one line per quantity and reference (so that a
    re-recorded baseline's diff shows one line per value that changed)."""
    lines = {}

    def one_line(table: dict) -> dict:
        out = {}
        for name, q in table.items():
            key = f"@@{len(lines)}@@"
            lines[key] = json.dumps(q, allow_nan=False)
            out[name] = key
        return out

    cases = [{**c, "quantities": one_line(c["quantities"]),
              "references": one_line(c.get("references", {}))} for c in doc["cases"]]
    text = json.dumps({**doc, "cases": cases}, indent=1, allow_nan=False)
    for key, value in lines.items():
        text = text.replace(f'"{key}"', value, 1)
    return text + "\n"


def _reference(ref: dict, where: str) -> dict:
    missing = {"case", "quantity", "kind", "source"} - set(ref)
    bounds = [k for k in ("value", "at_least", "at_most") if k in ref]
    if missing or ref.get("kind") not in SI_UNITS or len(bounds) != 1:
        raise InputError(f"{where}: needs case, quantity, kind (one of {', '.join(SI_UNITS)}), "
                         f"source and one of value, at_least, at_most")
    absolute = _parse_value(ref.get("absolute", 0.0), ref["kind"], where)
    return {"value": _parse_value(ref[bounds[0]], ref["kind"], where), "bound": bounds[0],
            "kind": ref["kind"], "unit": SI_UNITS[ref["kind"]],
            "printed": str(ref[bounds[0]]),
            "tolerance": {"absolute": absolute, "relative": float(ref.get("relative", 0.0))},
            "source": ref["source"]}


def load_references(path) -> dict:
    """Independent reference values from a TOML file (docs/regression.md)::

        [[reference]]
        case = "ricsac9"              # the case's name
        quantity = "solve.velocity1_x"
        kind = "velocity"             # unit kind of the value
        value = "-6.126 ft/s"         # as published, with its unit (or at_least / at_most)
        relative = 2e-3               # and/or absolute = "0.01 ft/s"
        source = "Brach design sheet, RICSAC 9 validation table"

    Returns case name -> {quantity -> {value [SI], bound, kind, unit, printed, tolerance,
    source}}; ``bound`` is "value" (within the tolerance), "at_least" or "at_most".
    """
    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InputError(f"{path}: cannot read references ({exc})") from None
    out: dict = {}
    for i, ref in enumerate(data.get("reference", [])):
        out.setdefault(ref.get("case"), {})[ref.get("quantity")] = _reference(
            ref, f"{path}: reference {i + 1}")
    return out


def _fail(path, why: str) -> InputError:
    return InputError(f"{path}: not a pim baseline ({why}); make one with pim baseline")


def _check_entry(path, i: int, entry) -> None:
    if not isinstance(entry, dict) or not {"case", "sha256", "quantities"} <= set(entry):
        raise _fail(path, f"case {i + 1} lacks case, sha256 or quantities")
    for name, q in entry["quantities"].items():
        if (isinstance(q, dict) and q.get("kind") == "dimensionless"
                and any(part.endswith("_percent") for part in name.split("."))):
            q.update(kind="percent", unit=SI_UNITS["percent"])   # recorded before kind percent
        ok = (isinstance(q, dict) and isinstance(q.get("tolerance"), dict)
              and q.get("kind") in SI_UNITS
              and (q.get("value") is None or isinstance(q.get("value"), int | float)))
        if not ok:
            raise _fail(path, f"quantity {name!r} of case {entry['case']!r} is malformed")


def load_baseline(path) -> dict:
    """Read and validate a baseline file.

    Raises
    ------
    ValueError
        Missing, unreadable or malformed file (one line naming what is wrong).
    """
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"{path}: no such baseline file") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise _fail(path, f"unreadable JSON: {exc}") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise _fail(path, f"format is not {FORMAT!r}")
    if not isinstance(data.get("cases"), list) or not data["cases"]:
        raise _fail(path, "no cases")
    for i, entry in enumerate(data["cases"]):
        _check_entry(path, i, entry)
    return data


@dataclass
class Drift:
    """One quantity outside its tolerance (values SI; ``unit`` names the unit).

    Attributes
    ----------
    case : str
        The case as shown (:func:`shown_case`: a bundled name, or the file's path).
    quantity : str
        ``section.quantity`` that drifted.
    baseline : float or None
        Recorded (or reference) value [SI ``unit``] (None where undefined).
    now : float or None
        Value now [SI ``unit``] (None where undefined or it no longer runs).
    difference : float or None
        ``now - baseline`` [SI ``unit``] (None where either is undefined).
    tolerance : float
        Allowed difference [SI ``unit``].
    unit : str
        SI unit of the values.
    kind : str
        Unit kind (a key of :data:`pim.io.units.SI_UNITS`), for display.
    against : str
        ``"baseline"`` or the source of the reference value compared with.
    """

    case: str
    quantity: str
    baseline: float | None
    now: float | None
    difference: float | None
    tolerance: float
    unit: str
    kind: str
    against: str = "baseline"       # or the source of a reference value


@dataclass
class CheckReport:
    """Outcome of :func:`check_baseline`.

    Attributes
    ----------
    path : str
        The baseline file checked.
    drifts : list of Drift
        Quantities outside their tolerance.
    checked : int
        Number of quantities compared.
    input_changes : list of str
        Cases whose case file changed since the baseline.
    version_changes : dict
        Dependency name -> [baseline version, version now] where they differ.
    notes : list of str
        Sections that no longer run or now run, and quantities new since the baseline.
    units : dict
        Case name -> (unit system, speed unit or None) its case file presents results in
        (``Case.units``, ``Case.speed_unit``), for display.
    """

    path: str
    drifts: list = field(default_factory=list)
    checked: int = 0
    input_changes: list = field(default_factory=list)
    version_changes: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)
    units: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return not self.drifts

    def units_of(self, case: str, units: str | None = None,
                 speed: str | None = None) -> DisplayUnits:
        """The display units of ``case``'s drifts: the unit system ``units`` and the speed
        unit ``speed`` asked for (``--units``, ``--speed-unit``), each by default the case
        file's (:func:`pim.io.units.display_units`)."""
        system, own_speed = self.units.get(case, ("si", None))
        return DisplayUnits(units or system, speed or own_speed)

    def to_json(self, units: str | None = None, speed: str | None = None) -> dict:
        """Plain data for ``--json``: each drift's values in its case's display units
        (:meth:`units_of`; its ``unit`` and ``si_unit`` fields name them), and ``units``
        naming each case's units (the baseline file itself stores SI)."""
        return {"baseline": self.path, "ok": self.ok, "checked": self.checked,
                "drifts": [_drift_json(d, self.units_of(d.case, units, speed))
                           for d in self.drifts],
                "input_changes": self.input_changes, "version_changes": self.version_changes,
                "notes": self.notes,
                "units": {case: self.units_of(case, units, speed).to_json()
                          for case in self.units}}


def _drift_json(d: Drift, units: DisplayUnits) -> dict:
    """A drift for ``--json``: its values in ``units``, with the unit they are in."""
    out = asdict(d)
    for key in DRIFT_VALUES:
        if out[key] is not None:
            out[key] = float(convert(out[key], d.kind, units)[0])
    out["si_unit"], out["unit"] = d.unit, convert(1.0, d.kind, units)[1]
    return out


def _allowed(tol: dict, reference: float) -> float:
    return max(float(tol.get("absolute", 0.0)), float(tol.get("relative", 0.0)) * abs(reference))


def _compare(case: str, name: str, q: dict, now: float | None, exact: bool,
             against: str = "baseline") -> Drift | None:
    old = q["value"]
    if old is None and (now is None or not math.isfinite(now)):
        return None
    ref = old if old is not None else 0.0
    tol = SAME_VERSIONS_REL * abs(ref) if exact else _allowed(q["tolerance"], ref)
    if old is None or now is None or not math.isfinite(now):
        diff = None
    else:
        diff = now - old
        if abs(diff) <= tol:
            return None
    return Drift(case=case, quantity=name, baseline=old, now=now, difference=diff,
                 tolerance=tol, unit=q.get("unit", SI_UNITS[q["kind"]]), kind=q["kind"],
                 against=against)


def _compare_reference(case: str, name: str, ref: dict, now: float | None) -> Drift | None:
    bound = ref.get("bound", "value")
    if bound == "value":
        return _compare(case, name, ref, now, False, ref["source"])
    limit = ref["value"]
    ok = now is not None and (now >= limit if bound == "at_least" else now <= limit)
    if ok:
        return None
    return Drift(case=case, quantity=name, baseline=limit, now=now,
                 difference=None if now is None else now - limit, tolerance=0.0,
                 unit=ref["unit"], kind=ref["kind"],
                 against=f"{bound.replace('_', ' ')}: {ref['source']}")


def _rerun(entry: dict, loaded: pim.Case, report: CheckReport, shown: str) -> dict:
    now = {}
    for section in entry.get("sections", []):
        try:
            rows = run_section(section, loaded, entry.get("settings", DEFAULT_SETTINGS))
        except LookupError as exc:
            report.notes.append(f"{shown}: {section} no longer runs ({exc})")
            continue
        now.update({r.name: r.value for r in rows})
    for section in entry.get("skipped", {}):
        try:
            run_section(section, loaded, entry.get("settings", DEFAULT_SETTINGS))
            report.notes.append(f"{shown}: {section} runs now (skipped in the baseline)")
        except LookupError:
            pass
    return now


def _case_path(stored: str, base: Path) -> Path | None:
    """The file a stored case names (relative paths from the baseline's folder ``base``),
    resolved; None for a bundled name."""
    path = Path(stored)
    path = path if path.is_absolute() else base / path
    if path.is_file() or "/" in stored or stored.endswith(".toml"):
        return path.resolve()
    return None


def shown_case(stored: str, base: Path) -> str:
    """A stored case as the report shows it: a bundled name as it is, a file by its path
    from the current folder when it lies below it (``cases/my-case.toml``, as typed), else
    its absolute path."""
    path = _case_path(stored, base)
    if path is None:
        return stored
    try:
        return path.relative_to(Path.cwd().resolve()).as_posix()
    except ValueError:
        return str(path)


def _check_case(entry: dict, base: Path, same_versions: bool, report: CheckReport) -> None:
    label, data = case_source(entry["case"], base)
    shown = shown_case(entry["case"], base)
    if hashlib.sha256(data).hexdigest() != entry["sha256"]:
        report.input_changes.append(f"{shown}: the case file changed since the baseline (its "
                                    f"SHA-256 differs)")
    loaded = _load(label)
    report.units[shown] = (loaded.units, loaded.speed_unit)
    now = _rerun(entry, loaded, report, shown)
    for name, q in entry["quantities"].items():
        report.checked += 1
        exact = same_versions and bool(q.get("exact_same_versions"))
        d = _compare(shown, name, q, now.get(name), exact)
        if d is not None:
            report.drifts.append(d)
    new = sorted(set(now) - set(entry["quantities"]))
    if new:
        report.notes.append(f"{shown}: {len(new)} quantities are new since the "
                            f"baseline and not checked ({', '.join(new[:5])}"
                            f"{', ...' if len(new) > 5 else ''})")
    for name, ref in entry.get("references", {}).items():
        report.checked += 1
        d = _compare_reference(shown, name, ref, now.get(name))
        if d is not None:
            report.drifts.append(d)


def _matches(entry: dict, wanted: str, base: Path) -> str | None:
    """How ``wanted`` names ``entry``: "exact" (as stored, by the case's name, or the same
    file from the current folder), "suffix" (a relative path the file's path ends with, as
    ``cases/my-case.toml`` from another folder), or None."""
    if wanted in (entry["case"], entry.get("name")):
        return "exact"
    path = _case_path(entry["case"], base)
    if path is None:
        return None
    given = Path(wanted)
    if given.resolve() == path:
        return "exact"
    parts = given.parts
    if not given.is_absolute() and ".." not in parts and path.parts[-len(parts):] == parts:
        return "suffix"
    return None


def _select(path, entries: list, cases, base: Path) -> list:
    """The entries ``cases`` name (each as stored, by name, or by its file's path: see
    :func:`_matches`), in the baseline's order."""
    chosen = set()
    for wanted in cases:
        how = {i: _matches(e, str(wanted), base) for i, e in enumerate(entries)}
        exact = {i for i, h in how.items() if h == "exact"}
        suffix = {i for i, h in how.items() if h == "suffix"}
        if not exact and len(suffix) > 1:
            raise InputError(f"{path}: case {wanted!r} names several of its cases "
                             f"({', '.join(entries[i]['case'] for i in sorted(suffix))}); "
                             f"give more of the path")
        if not (exact or suffix):
            raise InputError(f"{path}: holds no case {wanted} (it holds "
                             f"{', '.join(shown_case(e['case'], base) for e in entries)})")
        chosen |= exact or suffix
    return [e for i, e in enumerate(entries) if i in chosen]


def check_baseline(path, cases=None, progress=None) -> CheckReport:
    """Rerun a baseline's cases and compare every quantity with its tolerance.

    Parameters
    ----------
    path : str or Path
        The baseline file.
    cases : iterable of str, optional
        Only these of its cases: as stored, by case name, or by the case file's path (from
        the current folder, or any trailing part of it such as ``cases/my-case.toml``).
    progress : callable, optional
        Called with each case before it runs.

    Raises
    ------
    ValueError
        Missing or malformed baseline, a case that is no longer found, or a case in
        ``cases`` that the baseline does not hold.
    """
    data = load_baseline(path)
    report = CheckReport(str(path))
    now_versions = versions()
    report.version_changes = {k: [v, now_versions.get(k)] for k, v in data.get(
        "versions", {}).items() if now_versions.get(k) != v}
    base = Path(path).resolve().parent
    entries = data["cases"] if cases is None else _select(path, data["cases"], cases, base)
    for entry in entries:
        if progress is not None:
            progress(shown_case(entry["case"], base))
        _check_case(entry, base, not report.version_changes, report)
    return report


def _show(value, kind: str, system) -> str:
    if value is None:
        return "missing"
    if not math.isfinite(value):
        return "undefined"
    x, _ = convert(value, kind, system)
    return f"{float(x):.10g}"


def _short(value: float, kind: str, system) -> str:
    return f"{float(convert(value, kind, system)[0]):.3g}"


def _row(d: Drift, system: DisplayUnits) -> list[str]:
    _, unit = convert(1.0, d.kind, system)
    diff = "-" if d.difference is None else _short(d.difference, d.kind, system)
    return [d.case, d.quantity, _show(d.baseline, d.kind, system),
            _show(d.now, d.kind, system), diff, _short(d.tolerance, d.kind, system), unit,
            d.against]


def _by_section(report: CheckReport) -> str:
    counts: dict = {}
    for d in report.drifts:
        key = d.quantity.split(".")[0] + (" (references)" if d.against != "baseline" else "")
        counts[key] = counts.get(key, 0) + 1
    return ", ".join(f"{k} {n}" for k, n in counts.items())


def format_report(report: CheckReport, units: str | None = None,
                  speed: str | None = None) -> str:
    """The check as text: input and version changes, then one row per drifted quantity
    (case, quantity, baseline, now, difference, tolerance, unit, against what) in the unit
    system ``units`` ("si" or "us") with speeds in ``speed`` (default each case's own:
    :meth:`CheckReport.units_of`)."""
    lines = [f"input changed: {c}" for c in report.input_changes]
    lines += [f"version differs: {k} {old} -> {new} (Monte Carlo statistics are held to "
              f"their statistical tolerance, not bit for bit)"
              for k, (old, new) in report.version_changes.items()]
    lines += [f"note: {n}" for n in report.notes]
    if report.ok:
        lines.append(f"{report.path}: all {report.checked} quantities within tolerance")
        return "\n".join(lines)
    lines.append(f"{report.path}: {len(report.drifts)} of {report.checked} quantities moved "
                 f"beyond tolerance ({_by_section(report)})")
    rows = [["case", "quantity", "baseline", "now", "difference", "tolerance", "unit",
             "against"]]
    rows += [_row(d, report.units_of(d.case, units, speed)) for d in report.drifts]
    widths = [max(len(r[i]) for r in rows) for i in range(7)]
    for r in rows:
        cells = [c.ljust(w) if i in (0, 1, 6) else c.rjust(w)
                 for i, (c, w) in enumerate(zip(r, widths, strict=False))]
        lines.append("  ".join(cells + [r[7]]))
    return "\n".join(lines)


def _motion(x):
    """(velocity1, velocity2, yaw_rate1, yaw_rate2) of a pim.Result, sim.SimResult or
    anything with those attributes."""
    return tuple(np.asarray(getattr(x, k), float) for k in
                 ("velocity1", "velocity2", "yaw_rate1", "yaw_rate2"))


def agreement(result_a, result_b) -> float:
    """The project's one error measure between two answers to the same case
    (:func:`sim.error_measure.impact_error`: the largest error in the velocity changes,
    yaw rates times the radius of gyration, relative to the largest change) [-].

    One of the two must be a :class:`pim.Result` (it gives the case and the scale of the
    changes); the other may be a :class:`pim.Result`, a :class:`sim.SimResult` or anything
    with ``velocity1``, ``velocity2``, ``yaw_rate1``, ``yaw_rate2``.
    """
    if isinstance(result_a, pim.Result):
        ref, other = result_a, result_b
    elif isinstance(result_b, pim.Result):
        ref, other = result_b, result_a
    else:
        raise TypeError("agreement: one of the two results must be a pim.Result")
    return float(np.max(impact_error(ref.case, ref, *_motion(other))))


def assert_agrees(result_a, result_b, tol: float) -> float:
    """Assert that two answers agree within ``tol`` by :func:`agreement`; returns the error.

    Raises
    ------
    AssertionError
        The error exceeds ``tol`` (the message gives it and what it measures).
    """
    error = agreement(result_a, result_b)
    if not error <= tol:
        raise AssertionError(f"results differ by {error:.3g} > tolerance {tol:.3g} "
                             f"({ERROR_DEFINITION})")
    return error


def cases_findings(cases: dict) -> Findings:
    """What is wrong or doubtful about each case a baseline would record and its answer
    under its own law (:func:`pim.solve`; the case alone where it has no coefficients, a
    reconstruction case), numbers in the case's units, each prefixed with the case's name.

    Parameters
    ----------
    cases : dict
        Name (as given) -> :class:`pim.Case`.

    Returns
    -------
    Findings
        Every case's errors and warnings, in the order of ``cases``.
    """
    errors, warnings = [], []
    for name, case in cases.items():
        try:
            result = pim.solve(case)
        except InputError:          # no coefficients (a reconstruction case): the case alone
            result = None
        found = findings(case, result, show=quantity_text(case.units))
        errors += [f"{name}: {text}" for text in found.errors]
        warnings += [f"{name}: {text}" for text in found.warnings]
    return Findings(errors, warnings)
