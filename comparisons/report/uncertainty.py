"""What ``pim uncertainty`` shows of a :class:`pim.analysis.montecarlo.UncertaintyResult`:
typed rows of each output's nominal value and 5/50/95 % in the user's units with the inputs
that drive its spread, their JSON and text, and the words about inadmissible samples.
"""

from __future__ import annotations

from dataclasses import dataclass

from pim.analysis.montecarlo import OUTPUTS, UncertaintyResult
from pim.io.inertia_data import estimate_records
from pim.io.units import convert
from pim.model.case import Case
from pim.model.quantities import OUTPUTS as QUANTITIES
from pim.model.quantities import label_of

__all__ = ["UncertaintyRow", "uncertainty_rows", "uncertainty_json", "uncertainty_lines",
           "inadmissible_note", "no_admissible_error", "BARRIER_OUTPUTS"]

#: Outputs a fixed obstacle (vehicle 2 ``fixed``) does not have: it does not move and has
#: no PDOF.
BARRIER_OUTPUTS = ("pdof2", "delta_v2_magnitude", "speed2", "yaw_rate2")


@dataclass(frozen=True)
class UncertaintyRow:
    """One output of the Monte Carlo in the user's units.

    Attributes
    ----------
    output : str
        Its name (:data:`pim.model.quantities.OUTPUTS`).
    label : str
        Its label in words.
    unit : str
        Display unit.
    nominal, p5, p50, p95 : float
        The nominal answer and the percentiles of the admissible samples.
    sensitivity : tuple of (str, float)
        (input, first-order variance index) pairs, largest first.
    """

    output: str
    label: str
    unit: str
    nominal: float
    p5: float
    p50: float
    p95: float
    sensitivity: tuple = ()

    def to_json(self) -> dict:
        """The row as JSON (each first-order index rounded to 4 decimals)."""
        return {"output": self.output, "label": self.label, "unit": self.unit,
                "nominal": self.nominal, "p5": self.p5, "p50": self.p50, "p95": self.p95,
                "sensitivity": [{"input": k, "first_order": round(v, 4)}
                                for k, v in self.sensitivity]}


def uncertainty_rows(case: Case, result: UncertaintyResult,
                     units: str) -> tuple[UncertaintyRow, ...]:
    """Every output of ``result`` in ``units`` (a fixed obstacle's are left out:
    :data:`BARRIER_OUTPUTS`)."""
    rows = []
    for name in OUTPUTS:
        if case.vehicle2.fixed and name in BARRIER_OUTPUTS:
            continue
        s = result.stats[name]
        values, unit = convert([s.nominal, s.p5, s.p50, s.p95], QUANTITIES[name].kind, units)
        rows.append(UncertaintyRow(name, QUANTITIES[name].label, unit,
                                   *(float(v) for v in values),
                                   sensitivity=tuple(result.sensitivity[name])))
    return tuple(rows)


def uncertainty_json(case: Case, result: UncertaintyResult, rows, units, *, seed: int,
                     findings: dict | None = None) -> dict:
    """``pim uncertainty --json``: the case, the samples and seed, the units, the estimated
    inputs, ``findings`` (the nominal answer's), the counts of admissible and inadmissible
    samples with the reasons, and every output's row (:class:`UncertaintyRow`)."""
    return {"case": case.name, "samples": result.n, "seed": seed,
            "units": units.to_json(), "estimates": estimate_records(case, units),
            **(findings or {}), "samples_admissible": result.n_admissible,
            "samples_inadmissible": result.n - result.n_admissible,
            "inadmissible_samples": "left out of the percentiles and indices",
            "sample_problems": result.problems, "outputs": [r.to_json() for r in rows]}


def uncertainty_lines(name: str, result: UncertaintyResult, rows, *, seed: int,
                      top: int = 3) -> list[str]:
    """``pim uncertainty``'s table: a heading (samples, seed, admissible), then per output
    its unit, nominal value, 5/50/95 % and the ``top`` inputs that drive its spread (by
    their labels, separated by semicolons: a label may hold a comma)."""
    lines = [f"{name}: {result.n:,} samples (seed {seed}), {result.n_admissible:,} admissible"]
    width = max(len(r.label) for r in rows)
    lines.append(f"{'output':<{width}}  {'unit':>6}  {'nominal':>10}  {'5 %':>10}  "
                 f"{'50 %':>10}  {'95 %':>10}  main contributions (first-order index)")
    for r in rows:
        contrib = "; ".join(f"{label_of(k)} {round(v, 4):.2f}" for k, v in r.sensitivity[:top])
        lines.append(f"{r.label:<{width}}  {r.unit:>6}  {r.nominal:>10.4g}  {r.p5:>10.4g}  "
                     f"{r.p50:>10.4g}  {r.p95:>10.4g}  {contrib}")
    return lines


def inadmissible_note(result: UncertaintyResult) -> list[str]:
    """The share of inadmissible samples and how they were treated, then one line per
    reason with its count; empty when every sample is admissible."""
    bad = result.n - result.n_admissible
    if not bad:
        return []
    return [f"note: {bad:,} of {result.n:,} samples ({100 * bad / result.n:.3g} %) are "
            f"inadmissible impacts, left out of the percentiles and the indices (those "
            f"describe the admissible impacts); why:",
            *(f"warning: samples: {text}" for text in result.problems)]


def no_admissible_error(result: UncertaintyResult) -> str | None:
    """The error when no sample is an admissible impact (no statistics), else None."""
    if result.n_admissible:
        return None
    return f"no sample of {result.n:,} is an admissible impact: no statistics"
