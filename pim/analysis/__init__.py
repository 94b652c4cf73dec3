"""The analysis layer: residuals against measured motion, the least-squares fit,
sensitivities, Monte Carlo.

Uses :mod:`pim.model` only; never reads files, plots or prints.
"""
