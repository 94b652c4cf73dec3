"""Analytic PIM against the pymunk simulation: reports, animations, speed-error, hard cases.

The harness's main job. ``pim compare CASE --out DIR`` writes a report (report.html, one
self-contained page, and report.md) that leads with the answer (delta-V, PDOF, speeds,
energy with their intervals), then the fit, the fitted (epsilon, beta), the sheet's plots,
the analytic-vs-simulated table, an animation (simulated vehicles solid, the analytic motion as
a ghost outline) and a summary
of how the simulator's accuracy buys speed; ``pim animate``, ``pim speed-error`` and
``pim hard-cases`` run the parts on their own. See docs/comparisons.md.

comparisons/ uses both pim/ (the analytic model) and sim/ (the pymunk scene); neither of
them imports it.
"""

from sim.error_measure import QuantityError, compare_results, impact_error

__all__ = ["QuantityError", "compare_results", "impact_error"]
