"""The input/output layer: units at the edge, case files and bundled cases, Brach's
(theta, phi, d) form, the ``[uncertainty]`` table, atomic file writing.

Uses :mod:`pim.model`; never :mod:`pim.analysis`, :mod:`pim.plotting` or the command line
(:mod:`pim_cli`).
"""
