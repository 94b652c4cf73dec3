"""Brach's Planar Impact Mechanics (PIM) for two-vehicle collisions.

The model works in SI units in a global x-y frame (angles counter-clockwise from +x);
see the README for the sign conventions and the glossary.

>>> import pim
>>> case = pim.load_case("ricsac9")
>>> result = pim.solve(case, eps=0.355, beta=1.0)
>>> result.velocity1            # m/s, shape (2,)          # doctest: +SKIP
"""

from .case import Case, Impact, Measured, Vehicle
from .casefile import list_cases, load_case
from .solver import Result, solve

__all__ = ["Case", "Impact", "Measured", "Vehicle", "Result", "solve", "load_case",
           "list_cases"]
__version__ = "0.1.0"
