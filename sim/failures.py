"""The one exception of the simulator: a run that does not reproduce an impact."""

from __future__ import annotations

__all__ = ["SimulationError", "FAILURE_KINDS"]

#: Every value :attr:`SimulationError.kind` can take.
FAILURE_KINDS = ("no_contact", "never_separated", "multiple_contacts", "energy_gained",
                 "not_converged", "tunnelled")


class SimulationError(RuntimeError):
    """A simulation that failed to reproduce the impact; never returned silently.

    Attributes
    ----------
    kind : str
        One of :data:`FAILURE_KINDS`: "no_contact" (the engine never processed a contact:
        tunnelling at large dt, or the bodies do not approach at C), "never_separated" (the
        contact still pushed after ``settings.max_contact_time``), "multiple_contacts"
        (more contact points than the scene allows), "energy_gained" (kinetic energy rose
        beyond ``settings.energy_tolerance``), "not_converged" (the contact law was not met
        after a contact step: too few solver iterations, or a sliding contact on which
        Chipmunk's sequential impulses diverge, see :mod:`sim.convergence`), "tunnelled"
        (the finite-duration contact of :mod:`sim.compliant`: a step too coarse to resolve
        the contact, or outlines that passed through each other).
    step : int or None
        Step at which the failure was found.
    """

    def __init__(self, kind: str, message: str, step: int | None = None) -> None:
        if kind not in FAILURE_KINDS:
            raise ValueError(f"kind must be one of {FAILURE_KINDS}, got {kind!r}")
        super().__init__(message)
        self.kind = kind
        self.step = step
