"""Brach's Planar Impact Mechanics (PIM) for two-vehicle collisions.

The model works in SI units in a global x-y frame (angles counter-clockwise from +x);
see the README for the sign conventions and the glossary, and docs/architecture.md for the
layers (pim.model, pim.io, pim.analysis, pim.plotting; the command line is pim_cli). The public
functions are
named after what they do; the modules that hold them after what they compute
(``pim.fit`` is :func:`pim.analysis.fitting.fit`), so no public name hides a module.

>>> import pim
>>> case = pim.load_case("ricsac9")
>>> result = pim.solve(case, eps=0.355, beta=1.0)
>>> result.velocity1.round(3)           # m/s, shape (2,)
array([-1.867,  3.898])
"""

# Everything here needs only numpy; scipy, numba and matplotlib load on first use.
from .analysis.event import event
from .analysis.fitting import FitResult, fit
from .analysis.montecarlo import UncertaintyResult, uncertainty
from .analysis.reconstruction import post_impact_motion
from .analysis.sensitivity import sensitivity
from .io.casefile import list_cases, load_case
from .io.datasets import load_dataset
from .model.case import Case, Impact, Measured, Vehicle
from .model.friction_cap import solve_capped
from .model.impact_laws import solve_kudlich_slibar
from .model.law import LAW_NAMES, resolve_law, solve
from .model.numbers import InputError
from .model.result import Result

__all__ = ["Case", "Impact", "Measured", "Vehicle", "Result", "solve", "load_case",
           "list_cases", "fit", "FitResult", "sensitivity", "uncertainty",
           "UncertaintyResult", "solve_capped", "post_impact_motion", "load_dataset",
           "solve_kudlich_slibar", "resolve_law", "LAW_NAMES", "InputError", "event"]
__version__ = "0.1.0"
