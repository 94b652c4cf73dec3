"""Named coefficient priors from the bundled crash tests (Brach et al., SAE 2014-01-0469).

A prior is the empirical distribution of epsilon (``impact.restitution``) or beta = mu/mu0
(``impact.beta``) over the tests of one crash class, sampled by inverse CDF
(:class:`pim.model.distributions.Distribution` kind ``prior``)::

    [uncertainty]
    impact.restitution = {prior = "iihs-small-overlap-barrier"}
    impact.beta = {prior = "iihs-small-overlap-barrier"}

Priors (the authors' outlier CF11006 is left out of all of them):

* ``iihs-small-overlap-barrier``: the 16 non-sideswipe vehicle-to-barrier tests (NS);
* ``iihs-small-overlap-sideswipe``: the 24 sideswipe vehicle-to-barrier tests (SS);
* ``iihs-small-overlap-car-to-car``: the 9 vehicle-to-vehicle tests (one value per test;
  both vehicles of a test share e and mu).
"""

from __future__ import annotations

from ..model.distributions import Distribution
from ..model.numbers import InputError, did_you_mean
from .datasets import load_barrier, load_car_to_car

__all__ = ["PRIORS", "PRIOR_INPUTS", "prior_values", "prior_distribution"]

#: Prior name -> (crash class description).
PRIORS = {
    "iihs-small-overlap-barrier":
        "IIHS small-overlap barrier tests, non-sideswipe (Brach et al. 2014)",
    "iihs-small-overlap-sideswipe":
        "IIHS small-overlap barrier tests, sideswipe (Brach et al. 2014)",
    "iihs-small-overlap-car-to-car": "IIHS small-overlap car-to-car tests (Brach et al. 2014)",
}
#: Inputs a prior can describe -> record attribute.
PRIOR_INPUTS = {"impact.restitution": "restitution", "impact.beta": "beta"}


def _records(name: str):
    if name == "iihs-small-overlap-barrier":
        return [t for t in load_barrier() if t.group == "NS"]
    if name == "iihs-small-overlap-sideswipe":
        return [t for t in load_barrier() if t.group == "SS"]
    if name == "iihs-small-overlap-car-to-car":
        return [v for v in load_car_to_car() if v.test_id.endswith("a")]
    raise _unknown_prior(name, "prior")


def _unknown_prior(name, where: str) -> InputError:
    """The error of a prior name that is not one of :data:`PRIORS`: it names the field and
    the name given, the closest known prior when one is close, and the known ones."""
    return InputError(f"{where} = {name!r} is not a known prior{did_you_mean(name, PRIORS)} "
                      f"(known: {', '.join(PRIORS)})")


def prior_values(name: str, input_name: str) -> tuple:
    """The observed values of ``input_name`` (``impact.restitution`` or ``impact.beta``) [-].

    Raises
    ------
    InputError
        An input no prior describes, or a prior name not in :data:`PRIORS` (the message
        names the field, the name given and the known priors).
    """
    if input_name not in PRIOR_INPUTS:
        raise InputError(f"uncertainty.{input_name}: a prior exists only for "
                         f"{', '.join(PRIOR_INPUTS)}")
    if name not in PRIORS:
        raise _unknown_prior(name, f"uncertainty.{input_name}.prior")
    return tuple(getattr(r, PRIOR_INPUTS[input_name]) for r in _records(name))


def prior_distribution(name: str, input_name: str) -> Distribution:
    """The named prior of ``input_name`` as a :class:`Distribution` of kind ``prior``."""
    if not isinstance(name, str):
        raise InputError(f"uncertainty.{input_name}.prior must be a prior's name "
                         f"(known: {', '.join(PRIORS)})")
    return Distribution("prior", values=prior_values(name, input_name), label=name)
