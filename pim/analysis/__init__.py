"""The analysis layer: residuals against measured motion, the least-squares fit,
sensitivities, Monte Carlo.

Uses :mod:`pim.model` and, for the published data's conventions, :mod:`pim.io`
(:mod:`pim.analysis.validation` reads Brach's CG convention through :mod:`pim.io.brach`); never
plots or prints (tests/meta/test_architecture.py ranks the layers).
"""
