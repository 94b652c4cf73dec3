"""The model layer: case types, the one PIM formula and the paths that evaluate it, the result.

Imports only numpy (numba loads in :mod:`pim.model.kernel` when a batch takes it). Nothing
here reads files, parses units, prints or plots.
"""
