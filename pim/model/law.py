"""The impact law of a case: its resolution, the one solve entry point, and which command
applies which law.

A case names its law in ``impact.law`` (docs/impact-laws.md); an option may override it.
:func:`resolve_law` turns the case and the options into a :class:`LawChoice` (the law, its
restitution, beta and contact friction), checking the options against each other, once for
the library and the command line; :func:`solve` (``pim.solve``) solves the case under it,
with the per-law solvers as its parts: :func:`pim.model.solver.solve` (Brach's PIM),
:func:`pim.model.friction_cap.solve_capped` ("brach-capped") and
:func:`pim.model.impact_laws.solve_kudlich_slibar` ("kudlich-slibar").
:data:`COMMAND_LAWS` says which laws each command applies; :func:`check_command_law` is the
one place a command refuses a law, with the reason.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .case import LAWS, Case
from .friction_cap import solve_capped
from .impact_laws import check_contact_friction, check_restitution, law_of, solve_kudlich_slibar
from .numbers import InputError
from .result import Result
from .solver import APPROACH_TOLERANCE, SINGULAR_TOLERANCE, unknown_hint
from .solver import solve as solve_brach

__all__ = ["LAWS", "LAW_NAMES", "LAW_PARAMETERS", "API_NAMES", "LawChoice", "resolve_law",
           "solve", "COMMAND_LAWS", "REFUSAL_REASONS", "command_law_refusal",
           "check_command_law", "brach_equivalent", "fit_restitution"]

KS = "kudlich-slibar"

#: How each impact law is named in words (messages, reports, animations; JSON names the
#: law by its code, the key).
LAW_NAMES = {"brach": "Brach's PIM", "brach-capped": "friction-capped Brach (PIM)",
             KS: "Kudlich-Slibar law (PC-Crash, Virtual CRASH)"}
#: The parameters each law takes, in words.
LAW_PARAMETERS = {"brach": "eps, beta", "brach-capped": "eps, beta, cap mu_c", KS: "k, mu_c"}

#: How the library's callers name the inputs of :func:`resolve_law` in its messages (the
#: command line passes its option names).
API_NAMES = {"eps": "eps", "beta": "beta", "law": "law =", "k": "k", "mu_c": "mu_c",
             "cap_friction": "cap_friction", "friction_limit": "friction_limit"}


@dataclass(frozen=True)
class LawChoice:
    """An impact law and its parameters, resolved from a case and the options.

    Attributes
    ----------
    law : {"brach", "brach-capped", "kudlich-slibar"}
    restitution : array_like or None
        eps (Brach's laws) or k (Kudlich-Slibar) [-]; None: the case's ``impact.restitution``
        (its solver says when that is missing too).
    beta : array_like or None
        Fraction of mu0 [-] (Brach's laws; None: the case's ``impact.beta``, else 1).
    contact_friction : array_like or None
        mu_c [-]: the cap of "brach-capped", the contact friction of "kudlich-slibar";
        None for "brach".
    """

    law: str
    restitution: object = None
    beta: object = None
    contact_friction: object = None

    @property
    def name(self) -> str:
        """The law in words (:data:`LAW_NAMES`)."""
        return LAW_NAMES[self.law]


def _capped_law(law, mu_c, friction_limit, names):
    """(law, mu_c) of the command line's --cap-friction: law "brach-capped" at the limit."""
    if law not in (None, "brach-capped"):
        raise InputError(f"{names['cap_friction']} is law brach-capped; it contradicts "
                         f"{names['law']} {law}")
    if friction_limit is None and mu_c is None:
        raise InputError(f"{names['cap_friction']} needs {names['friction_limit']}")
    return "brach-capped", friction_limit if mu_c is None else mu_c


def _friction(case: Case, law: str, mu_c, names):
    """The law's contact friction: given, else the case's; checked; None for "brach"."""
    if mu_c is not None:
        if law == "brach":
            raise InputError(f"{names['mu_c']} needs {names['law']} kudlich-slibar or "
                             "brach-capped (it does not apply to law 'brach')")
        return check_contact_friction(mu_c, f"{names['mu_c']} (contact friction)")
    if law == "brach":
        return None
    mu_c = case.impact.contact_friction
    if mu_c is None:
        what = "the cap" if law == "brach-capped" else "the contact friction"
        raise InputError(f"{names['mu_c']} ({what}) is required for law {law!r}: give it or "
                         f"set impact.contact_friction in the case{unknown_hint(case)}")
    return check_contact_friction(mu_c, "impact.contact_friction")


def resolve_law(case: Case, eps=None, beta=None, *, law: str | None = None, k=None, mu_c=None,
                cap_friction: bool = False, friction_limit=None,
                names: dict = API_NAMES) -> LawChoice:
    """The impact law and its parameters from the case and the options, checked.

    Parameters
    ----------
    case : Case
        Supplies ``impact.law`` (default "brach") and ``impact.contact_friction``.
    eps : array_like, optional
        Restitution [-] in [0, 1]: eps of Brach's laws, k of "kudlich-slibar".
    beta : array_like, optional
        Fraction of mu0 [-] (Brach's laws only).
    law : {"brach", "brach-capped", "kudlich-slibar"}, optional
        Overrides the case's law.
    k : array_like, optional
        Restitution k [-] in [0, 1] of "kudlich-slibar" (instead of ``eps``).
    mu_c : array_like, optional
        Contact friction [-] >= 0: the cap of "brach-capped", the contact friction of
        "kudlich-slibar" (default: the case's ``impact.contact_friction``).
    cap_friction : bool
        Law "brach-capped" capped at ``friction_limit`` (the command line's --cap-friction).
    friction_limit : float, optional
        The cap under ``cap_friction`` (``mu_c`` wins when both are given).
    names : dict
        How the caller names these inputs in the messages (:data:`API_NAMES`).

    Returns
    -------
    LawChoice
        The law and its parameters; restitution and beta stay None where not given (the
        law's solver takes the case's defaults).

    Raises
    ------
    ValueError
        An unknown law, a parameter the law does not take (k, mu_c, beta), k with eps,
        a missing contact friction, a value out of range.
    """
    if cap_friction:
        law, mu_c = _capped_law(law, mu_c, friction_limit, names)
    law = law_of(case, law)
    if k is not None:
        if law != KS:
            raise InputError(f"{names['k']} is the restitution of law kudlich-slibar (law is "
                             f"{law}; use {names['eps']})")
        if eps is not None:
            raise InputError(f"give {names['k']} or {names['eps']}, not both")
        eps = check_restitution(k, f"{names['k']} (restitution)")
    if law == KS and beta is not None:
        raise InputError(f"{names['beta']} does not apply to law 'kudlich-slibar' (use "
                         f"{names['k']} and {names['mu_c']})")
    return LawChoice(law, eps, beta, _friction(case, law, mu_c, names))


def fit_restitution(case: Case, eps=None, k=None, *, names: dict = API_NAMES):
    """The restitution a fit of ``case`` holds fixed, given as the parameter of its law.

    A fit applies the case's own law (:func:`pim.model.impact_laws.law_of`): Brach's laws
    hold eps, the Kudlich-Slibar law holds k (``pim.fit`` takes either as ``eps``).

    Parameters
    ----------
    case : Case
        Supplies ``impact.law``.
    eps : float, optional
        Brach's restitution epsilon [-] to hold.
    k : float, optional
        Kudlich-Slibar's restitution k [-] to hold.
    names : dict
        How the caller names these inputs in the messages (:data:`API_NAMES`).

    Returns
    -------
    float or None
        The restitution to hold (None: fitted).

    Raises
    ------
    InputError
        ``k`` under a law other than Kudlich-Slibar's, or ``eps`` under it.
    """
    ks = law_of(case) == KS
    if k is not None and not ks:
        raise InputError(f"{names['k']} is the restitution of law kudlich-slibar (use "
                         f"{names['eps']})")
    if ks and eps is not None:
        raise InputError(f"{names['eps']}: the case's law is kudlich-slibar; hold k with "
                         f"{names['k']}")
    return k if ks else eps


def solve(case: Case, eps=None, beta=None, backend: str = "auto", fast_trig: bool = True,
          approach_tol: float = APPROACH_TOLERANCE, singular_tol: float = SINGULAR_TOLERANCE,
          *, law: str | None = None, k=None, mu_c=None) -> Result:
    """Post-impact motion of a planar two-body impact under the case's impact law.

    Parameters
    ----------
    case : Case
        Vehicles, impact point C and normal angle Gamma (every field may be an array); its
        ``impact.law`` names the law (default Brach's PIM).
    eps : array_like, optional
        Restitution [-] in [0, 1]: Brach's epsilon, or k under "kudlich-slibar"; defaults to
        ``case.impact.restitution``.
    beta : array_like, optional
        Fraction of the critical impulse ratio, mu = beta mu0 [-] (Brach's laws); defaults to
        ``case.impact.beta``, else 1.
    backend, fast_trig, approach_tol, singular_tol
        As for :func:`pim.model.solver.solve` (backend and fast_trig apply to Brach's law;
        the tolerances to Brach's and Kudlich-Slibar's).
    law : {"brach", "brach-capped", "kudlich-slibar"}, optional
        Overrides the case's law.
    k : array_like, optional
        Restitution k [-] of "kudlich-slibar" (instead of ``eps``).
    mu_c : array_like, optional
        Contact friction [-] >= 0: the cap of "brach-capped", the contact friction of
        "kudlich-slibar"; defaults to ``case.impact.contact_friction``.

    Returns
    -------
    Result
        :func:`pim.model.solver.solve`'s (Brach's PIM, bitwise the same),
        :func:`pim.model.friction_cap.solve_capped`'s or
        :func:`pim.model.impact_laws.solve_kudlich_slibar`'s answer.

    Raises
    ------
    ValueError
        As :func:`resolve_law`, and the law's solver (a missing or bad value).

    Notes
    -----
    Brach & Brach (2011) eqs. 6.45-6.62 in vector form; the laws and their mapping in
    :mod:`pim.model.impact_laws` and docs/impact-laws.md.

    Examples
    --------
    >>> import pim
    >>> case = pim.load_case("ricsac9")
    >>> round(float(pim.solve(case, eps=0.355, beta=1.0).mu0), 3)
    0.512
    >>> float(pim.solve(case, law="kudlich-slibar", k=0.1, mu_c=0.6).eps)
    0.1
    """
    if not isinstance(case, Case):
        raise InputError(f"case must be a pim.Case (e.g. pim.load_case(...)), got "
                         f"{type(case).__name__}")
    choice = resolve_law(case, eps, beta, law=law, k=k, mu_c=mu_c)
    if choice.law == "brach":
        return solve_brach(case, choice.restitution, choice.beta, backend, fast_trig,
                           approach_tol, singular_tol)
    if choice.law == "brach-capped":
        return solve_capped(case, choice.restitution, choice.beta, choice.contact_friction)
    return solve_kudlich_slibar(case, choice.restitution, choice.contact_friction,
                                approach_tol, singular_tol)


_ALL = LAWS
_BRACH = ("brach",)

#: The impact laws each command applies, in the order the refusal lists them. A command
#: not listed takes no case (its inputs name no impact law).
COMMAND_LAWS = {
    "solve": _ALL, "draw": _ALL, "sim": _ALL, "fit": _ALL, "compare": _ALL, "animate": _ALL,
    "baseline": _ALL, "reconstruct": _ALL, "event": _ALL,
    "uncertainty": _BRACH, "sensitivity": _BRACH, "plot": _BRACH, "speed-error": _BRACH,
    "assumptions": _BRACH,
}
#: Why a command applies Brach's law only.
REFUSAL_REASONS = {
    "uncertainty": "its Monte Carlo samples Brach's (eps, beta)",
    "sensitivity": "its derivatives are taken with respect to Brach's (eps, beta)",
    "plot": "it maps the fit over Brach's (eps, beta) plane",
    "speed-error": "its pymunk scene plays Brach's rigid impact at (eps, beta)",
    "assumptions": "it varies the assumptions of Brach's rigid scene one at a time",
}


def brach_equivalent(case: Case, law: str) -> str:
    """Brach's (eps, beta) with the same answer as ``case`` under ``law``, in words."""
    try:
        result = solve(case, law=law)
        eps, beta = float(result.eps), float(result.beta)
    except ValueError as exc:
        return f"fix the case first ({exc})"
    if not (math.isfinite(eps) and math.isfinite(beta)):
        return "this case has no Brach equivalent (no impact at C)"
    return (f"the same answer is Brach's at eps = {eps:.6g}, beta = {beta:.6g}: set "
            f"impact.law = \"brach\", restitution = {eps:.6g}, beta = {beta:.6g} to run it")


def command_law_refusal(command: str, case: Case, law: str | None = None) -> str | None:
    """Why ``pim command`` cannot apply the case's law (or ``law``); None when it can.

    Parameters
    ----------
    command : str
        The command's name (a key of :data:`COMMAND_LAWS`; any other takes no law).
    case : Case
        The case the command runs on.
    law : str, optional
        The law an option asks for (default: the case's, else "brach").

    Returns
    -------
    str or None
        One line: the command, the law, the reason, Brach's equivalent for this case and
        the commands that apply the law.
    """
    law = law_of(case, law)
    if law in COMMAND_LAWS.get(command, LAWS):
        return None
    applying = [f"`pim {c}`" for c, laws in COMMAND_LAWS.items() if law in laws]
    listed = ", ".join(applying[:-1]) + " and " + applying[-1]
    return (f"pim {command} cannot use impact law {law!r} yet ({LAW_NAMES[law]}; only "
            f"Brach's): {REFUSAL_REASONS[command]}; {brach_equivalent(case, law)}; {listed} "
            "apply the law itself")


def check_command_law(command: str, case: Case, law: str | None = None) -> None:
    """Raise :class:`pim.InputError` with :func:`command_law_refusal`'s reason when
    ``pim command`` cannot apply the case's law (or ``law``): the one place a command
    refuses a law, never silently Brach's answer instead."""
    refusal = command_law_refusal(command, case, law)
    if refusal is not None:
        raise InputError(refusal)
