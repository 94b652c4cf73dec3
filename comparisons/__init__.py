"""Analytic PIM against the pymunk simulation: reports, animations, speed-error, hard cases.

The harness's main job. ``pim compare CASE --out DIR`` writes a report (report.html, one
self-contained page, and report.md) that leads with the answer (delta-V, PDOF, speeds,
energy with their intervals), then the fit, the fitted (epsilon, beta), the sheet's plots,
the analytic-vs-simulated table, an animation (simulated vehicles solid, the analytic motion as
a ghost outline) and a summary
of how the simulator's accuracy buys speed; ``pim animate``, ``pim speed-error`` and
``pim hard-cases`` run the parts on their own. See docs/comparisons.md.

comparisons/ uses both pim/ (the analytic model) and sim/ (the pymunk scene); neither of
them imports it. This file imports nothing: the pytest plugin (comparisons.regression.plugin),
which every pytest run in an environment with the project installed loads, stays light.
The error measure is :mod:`sim.error_measure`'s.
"""
