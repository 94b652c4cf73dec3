"""The impact laws other than Brach's in the comparisons: the analytic answer, the
simulation that cross-checks it, and how the report and the animation name them.

``law = "kudlich-slibar"`` (docs/impact-laws.md): the analytic answer is
:func:`pim.solve`'s; the simulation is the two-phase pymunk run
(:func:`sim.kudlich_slibar.simulate_kudlich_slibar`: compression by the engine at restitution
0 and Coulomb coefficient mu_c, then k times the engine's impulse), which takes only the case,
k and mu_c and, with ``record`` and ``duration``, continues after separation like the Brach
scene. ``law = "brach-capped"``: the answer is PIM at the effective beta_eff = min(beta,
mu_c / |mu0|), which the Brach scene plays (as ``pim sim`` does). ``law = "brach"`` is the
Brach scene at (eps, beta).
"""

from __future__ import annotations

from dataclasses import dataclass

import pim
import sim
from pim.model.impact_laws import law_of
from pim.model.law import LAW_NAMES
from sim.kudlich_slibar import engine_friction, simulate_kudlich_slibar

__all__ = ["LawSetup", "law_setup", "simulate_law"]



@dataclass(frozen=True, eq=False)
class LawSetup:
    """An impact law with its parameters and its analytic answer for one case.

    Attributes
    ----------
    law : {"brach", "brach-capped", "kudlich-slibar"}
    result : pim.Result
        :func:`pim.solve`'s answer.
    restitution : float
        eps (Brach's laws) or k (Kudlich-Slibar) [-].
    beta : float
        Brach's beta; for "brach-capped" the effective beta, for "kudlich-slibar" the PIM
        beta giving the same answer [-].
    contact_friction : float or None
        mu_c [-]: the contact friction of Kudlich-Slibar, the cap of "brach-capped".
    """

    law: str
    result: pim.Result
    restitution: float
    beta: float
    contact_friction: float | None = None

    @property
    def name(self) -> str:
        """The law's name in words."""
        return LAW_NAMES[self.law]

    def parameters(self) -> str:
        """The law's parameters in words, e.g. "k = 0.1, mu_c = 0.6"."""
        if self.law == "kudlich-slibar":
            return f"k = {self.restitution:.6g}, mu_c = {self.contact_friction:.6g}"
        text = f"epsilon = {self.restitution:.6g}, beta = {self.beta:.6g}"
        if self.law == "brach-capped":
            text = (f"epsilon = {self.restitution:.6g}, effective beta = {self.beta:.6g} "
                    f"(cap mu_c = {self.contact_friction:.6g})")
        return text

    def describe(self) -> str:
        """Law and parameters, e.g. "Kudlich-Slibar law (...), k = 0.1, mu_c = 0.6"."""
        return f"{self.name}, {self.parameters()}"


def law_setup(case: pim.Case, law: str | None = None, restitution=None, beta=None,
              contact_friction=None) -> LawSetup:
    """Solve ``case`` under its law (or ``law``) and keep the law's parameters.

    The parameters default to the case's ``impact`` table as in :func:`pim.solve`;
    raises ValueError (an InputError naming the field) on a bad or missing one.
    """
    law = law_of(case, law)
    result = pim.solve(case, restitution, beta, law=law, mu_c=contact_friction)
    mu_c = None
    if law == "kudlich-slibar":
        mu_c = float(result.contact_friction)
    elif law == "brach-capped":
        mu_c = float(contact_friction if contact_friction is not None
                     else case.impact.contact_friction)
    return LawSetup(law, result, float(result.eps), float(result.beta), mu_c)


def simulate_law(case: pim.Case, setup: LawSetup, settings: sim.Settings | None = None):
    """The pymunk run that cross-checks ``setup``'s law on ``case``.

    Returns a :class:`sim.SimResult` (Brach's laws) or a
    :class:`sim.kudlich_slibar.KudlichSlibarRun`; both carry the post-impact velocities, yaw
    rates, the impulse on vehicle 1, and (with ``settings.record``) the trajectory.
    Raises :class:`sim.SimulationError` when the run fails.
    """
    settings = settings or sim.Settings()
    if setup.law == "kudlich-slibar":
        return simulate_kudlich_slibar(case, setup.restitution,
                                       engine_friction(setup.contact_friction), settings)
    return sim.simulate(case, setup.restitution, setup.beta, settings)
