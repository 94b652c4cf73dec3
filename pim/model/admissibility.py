"""Admissibility flags of a PIM result, and the reasons in plain language.

A mixin of :class:`pim.Result`. Inadmissible results are flagged, never hidden: no approach
at C, a pulling normal impulse, energy gained, |mu| > |mu0|, a tangential impulse along the
remaining slip, singular q. The last two (|mu| > |mu0| and a tangential impulse along the
remaining slip) are tangential restitution: outside Brach's law, but the standard behaviour
of the Kudlich-Slibar law of PC-Crash and Virtual CRASH (:mod:`pim.model.impact_laws`),
whose results do not count them.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

__all__ = ["Admissibility"]


class Admissibility:
    """Flags that say whether each element of a result is physically admissible."""

    @cached_property
    def normal_impulse_positive(self) -> np.ndarray:
        """Pn > 0: the contact pushes (a negative Pn would pull the vehicles together)."""
        return self.impulse_n > 0

    @cached_property
    def energy_not_gained(self) -> np.ndarray:
        """Kinetic energy does not rise (loss >= 0 within round-off)."""
        tol = 1e-9 * self.kinetic_energy_before
        return self.energy_loss >= -tol

    @cached_property
    def within_critical(self) -> np.ndarray:
        """|mu| <= |mu0| (0 <= beta <= 1): no reversal of tangential sliding at C."""
        return (self.beta >= 0) & (self.beta <= 1)

    @cached_property
    def friction_opposes_sliding(self) -> np.ndarray:
        """Pt U_t <= 0: the tangential impulse does not point along the slip left at C.

        With strong n-t coupling PIM's mu = beta mu0 can push along the post-impact
        sliding, which a Coulomb contact that slides throughout cannot do. A contact that
        sticks and then restitutes tangentially (the Kudlich-Slibar law of PC-Crash and
        Virtual CRASH, slip -k u_t after impact) does it as standard.
        """
        scale = np.abs(self.impulse_t) * (np.abs(self.approach_n) + np.abs(self.approach_t))
        return self.impulse_t * self.separation_t <= 1e-9 * scale

    @cached_property
    def admissible(self) -> np.ndarray:
        """All flags hold: approach, Pn > 0, no energy gain, |mu| <= |mu0|, friction opposing
        the remaining slip, finite q."""
        return (self.approaching & self.normal_impulse_positive & self.energy_not_gained
                & self.within_critical & self.friction_opposes_sliding & ~self.q_singular)

    def admissibility_checks(self) -> list[tuple]:
        """(ok, reason, key) for each check :meth:`problems` reports, in order."""
        return [
            (self.approaching, "the vehicles do not approach at C (u_n >= 0): no impact",
             "approach"),
            (~self.q_singular, "q is singular (A - mu B = 0): the impulse is unbounded",
             "singular"),
            (self.normal_impulse_positive | ~self.approaching,
             "the normal impulse is not positive (the contact would pull)", "pull"),
            (self.energy_not_gained, "kinetic energy is gained", "energy"),
            (self.friction_opposes_sliding | ~self.approaching,
             "the tangential impulse points along the remaining slip at C (tangential "
             "restitution: outside Brach's mu <= mu0, though standard in the Kudlich-Slibar "
             "law of PC-Crash and Virtual CRASH, where sticking ends at slip -k u_t)", "along"),
            # Sliding reverses only where beta > 1 and there is sliding to reverse (Pt0 != 0);
            # beta < 0 makes the tangential impulse drive the sliding instead.
            (np.broadcast_to((self.beta <= 1) | (self.critical_impulse_t == 0),
                             np.shape(self.impulse_n)),
             "|mu| > |mu0| (beta > 1): tangential slip at C reverses (outside Brach's "
             "bounds; the Kudlich-Slibar law of PC-Crash and Virtual CRASH does this as "
             "standard: law = \"kudlich-slibar\")", "reverses"),
            (np.broadcast_to((self.beta >= 0) | (self.critical_impulse_t == 0),
                             np.shape(self.impulse_n)),
             "beta < 0: the tangential impulse drives the sliding at C instead of opposing it",
             "drives"),
        ]

    def problems(self) -> list[str]:
        """Plain-language reasons why any element is inadmissible (empty when all are fine)."""
        return [text if size == 1 else f"{text} ({bad} of {size} cases)"
                for text, bad, size in self.problem_counts()]

    def unsolvable(self) -> str | None:
        """Why there is no answer to give: where q is singular anywhere, the first reason of
        :meth:`problems` (a generic one if none); else None."""
        if not np.any(self.q_singular):
            return None
        problems = self.problems()
        return problems[0] if problems else "q is singular"

    def problem_counts(self) -> list[tuple[str, int, int]]:
        """(reason, elements failing it, elements) of each failed check of :meth:`problems`
        (counts that add up over the chunks of a Monte Carlo)."""
        out = []
        for ok, text, _ in self.admissibility_checks():
            ok = np.asarray(ok)
            bad = int(np.size(ok) - np.count_nonzero(ok))
            if bad:
                out.append((text, bad, int(ok.size)))
        return out
