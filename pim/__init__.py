"""Brach's Planar Impact Mechanics (PIM) for two-vehicle collisions.

The model works in SI units in a global x-y frame (angles counter-clockwise from +x);
see the README for the sign conventions and the glossary.

>>> import pim
>>> case = pim.load_case("ricsac9")
>>> result = pim.solve(case, eps=0.355, beta=1.0)
>>> result.velocity1            # m/s, shape (2,)          # doctest: +SKIP
"""

# fit, sensitivity and uncertainty share their modules' names. They are imported eagerly
# (they need only numpy; scipy, numba and matplotlib load inside them on first use) so that
# the function, bound after its submodule, is what pim.fit means even after a later
# `import pim.fit`; a lazy __getattr__ export would be overwritten by the module.
from .analysis.fitting import FitResult, fit
from .analysis.montecarlo import UncertaintyResult, uncertainty
from .analysis.sensitivity import sensitivity
from .io.casefile import list_cases, load_case
from .model.case import Case, Impact, Measured, Vehicle
from .model.friction_cap import solve_capped
from .model.result import Result
from .model.solver import solve

__all__ = ["Case", "Impact", "Measured", "Vehicle", "Result", "solve", "load_case",
           "list_cases", "fit", "FitResult", "sensitivity", "uncertainty",
           "UncertaintyResult"]
__all__ += ["solve_capped"]    # issue 12: the friction-capped model
__version__ = "0.1.0"
