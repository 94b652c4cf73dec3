"""pymunk (Chipmunk2D) recreation of a PIM case, to cross-check :func:`pim.solve`.

>>> import pim, sim
>>> case = pim.load_case("ricsac9")
>>> result = sim.simulate(case, eps=0.355, beta=1.0)
>>> result.velocity1.round(2)           # m/s, shape (2,): PIM's (-1.867, 3.898)
array([-1.87,  3.9 ])

``sim.simulate_event`` runs the whole event (approach, every impact, run-out to rest) and
returns the project's timeline, :class:`pim.model.event.Event`.

``sim.simulate_compliant`` relaxes PIM's assumptions instead: a finite-duration crush
contact (docs/contact-model.md), checked by ``sim.reference_compliant`` (solve_ivp).

See docs/sim.md for how the scene reproduces PIM's assumptions, the switches that relax
them one at a time, and the measured accuracy and speed.
"""

from .batch import case_element, simulate_many
from .compliant import simulate_compliant
from .compliant_batch import CompliantBatch
from .compliant_setup import DEFAULT_STIFFNESS, CompliantResult, CompliantSettings, ContactHistory
from .crosscheck import CrossCheck, crosscheck
from .event import simulate_event
from .event_scene import SecondaryLaw
from .failures import FAILURE_KINDS, SimulationError
from .limits import limitations
from .reference import reference_compliant
from .result import BatchResult, SimResult, Trajectory
from .run import simulate
from .scene import Scene, build_scene
from .secondary import SecondaryImpact, find_secondary_impact, watch_after_impact
from .settings import Settings

__all__ = ["Settings", "simulate", "simulate_many", "SimResult", "Trajectory", "BatchResult",
           "SimulationError", "FAILURE_KINDS", "limitations", "crosscheck", "CrossCheck",
           "Scene", "build_scene", "case_element", "simulate_compliant", "reference_compliant",
           "CompliantSettings", "CompliantResult", "CompliantBatch", "ContactHistory",
           "DEFAULT_STIFFNESS", "find_secondary_impact", "SecondaryImpact", "watch_after_impact",
           "simulate_event", "SecondaryLaw"]
