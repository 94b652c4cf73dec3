"""Reconstruction chain: evidence at rest -> post-impact motion -> impact speeds.

Step 1 (this module, :func:`post_impact_motion`): for each vehicle with ``[evidence]``,
the run-out inverse (:func:`pim.analysis.runout_fit.fit_runout`) from its separation state
to its measured rest state gives the post-impact CG velocity and yaw rate, with standard
deviations from the fit's Jacobian and the evidence's sigmas. PIM's impact is
instantaneous, so each vehicle separates from its impact position and heading (the case's
``cg`` and ``heading``).

Step 2: the post-impact motion becomes the case's ``measured`` data (with standard
deviations from step 1); the unknowns of ``[unknown]`` (pre-impact speeds, restitution,
beta ...) are solved by the inverse PIM (:func:`pim.analysis.inverse_pim.inverse_pim`).
Beside it, the linear-momentum two-equation solve
(:func:`pim.analysis.momentum.momentum_speeds`) is reported as a check. A case without
``[evidence]`` but with ``[measured]`` post-impact motion starts at step 2.

Step 3 (:func:`reconstruct` with ``samples``): a Monte Carlo over the stated uncertainties
(:mod:`pim.analysis.reconstruction_mc`) gives each unknown's 5/50/95 % values and the inputs
that drive its spread.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, fields, replace

import numpy as np

from ..model.case import Case, Measured, checked_case
from ..model.crush import crush_delta_v, effective_mass, equivalent_energy_speed, moment_arm
from ..model.display import convert, display_units
from ..model.event import Event, Track, phase_labels
from ..model.evidence_terms import result_quantities
from ..model.geometry import vehicle_outline
from ..model.motion import Term
from ..model.notebook import Notebook, Table, short
from ..model.numbers import (
    ArgumentTypeError,
    InputError,
    check_counts,
    checked_count,
    message_units,
    speed_text,
    unit_text,
    units_in,
)
from ..model.tyres import STANDARD_GRAVITY
from .fitting import FitResult
from .free_inputs import approach_direction, check_free, free_kind, free_label
from .inverse_pim import check_evidence, inverse_pim, under_determined
from .event import event_after, event_rest_many, sliding_flags
from .event_fit import EventFit, fit_through_event
from .event_samples import event_sampler
from .momentum import MomentumSpeeds, momentum_speeds
from .reconstruction_mc import (
    ReconstructionSamples,
    reconstruction_samples,
    residual_standard_error,
    rest_draws,
    solve_samples,
    summarise,
)
from .residuals import GoodnessOfFit, contradiction, crush_terms, measured_terms
from .runout_fit import RunoutFit, fit_runout

__all__ = ["PostImpact", "post_impact_motion", "check_reachable", "approach_direction",
           "Reconstruction", "CrushOutput", "crush_outputs",
           "reconstruct", "evidence_sampler", "evidence_nominal", "sample_block",
           "monte_carlo_seconds", "PILOT_SAMPLES", "TIMED_SAMPLES", "BLOCKS_PER_WORKER",
           "worker_blocks", "progress_stages", "MonteCarloBudget"]


@dataclass(frozen=True)
class PostImpact:
    """Post-impact motion reconstructed from the evidence (SI).

    Attributes
    ----------
    case : Case, the input case with ``measured`` replaced by the run-out fits' motion
    runouts : dict vehicle number (1, 2) -> RunoutFit (only vehicles with evidence)
    velocity_covariance : dict vehicle number -> (2, 2) covariance of the post-impact
        velocity [m^2/s^2] (``velocity_sigma``, its former name, still reads it)
    yaw_rate_sigma : dict vehicle number -> standard deviation of the yaw rate [rad/s]
    momentum : MomentumSpeeds or None (needs both vehicles' evidence)
    messages : list of plain-language warnings (unreachable rest, no stop, several minima)
    event_fit : EventFit or None
        The fit through the event (:func:`pim.analysis.event_fit.fit_through_event`), made
        when the single-impact run-outs' event has further impacts; its motion is then the
        case's ``measured`` motion
    single_event_impacts : int
        Further impacts of the event of the single-impact run-outs' motion (0: none, or not
        checked without both outlines)
    """

    case: Case
    runouts: dict
    velocity_covariance: dict
    yaw_rate_sigma: dict
    momentum: MomentumSpeeds | None
    messages: list
    event_fit: EventFit | None = None
    single_event_impacts: int = 0

    @property
    def velocity_sigma(self) -> dict:
        """Former name of :attr:`velocity_covariance` (it always held covariances)."""
        return self.velocity_covariance

    def event(self, times=None, first=None) -> Event:
        """The fitted run-outs as an :class:`pim.model.event.Event` from the impact (t = 0)
        to the later vehicle's rest, at ``times`` [s] (default: every time either run-out
        stored), each run-out's track with its wheels (the evidence's axles) and which of
        them slide (:func:`pim.analysis.event.sliding_flags`: the tyre marks). A vehicle
        without a run-out stays at its impact pose (a note says so).

        When the motion was fitted through the event (``event_fit``), the event that fit
        assumed instead: its post-impact motion carried through every further impact to
        rest (:func:`pim.analysis.event.event_after`; ``first`` the first impact's
        :class:`pim.model.event.ImpactRecord`), at its own times by default.
        """
        if not self.runouts:
            raise InputError("the reconstruction has no run-out (no [evidence])")
        if self.event_fit is not None:
            fit = self.event_fit
            full = event_after(self.case, fit.velocity, fit.yaw_rate, first=first)
            return full if times is None else full.at(np.asarray(times, float))
        if times is None:
            times = np.unique(np.concatenate([f.runout.time for f in self.runouts.values()]))
        times = np.asarray(times, float)
        tracks, notes = [], []
        for i in (1, 2):
            vehicle = getattr(self.case, f"vehicle{i}")
            outline = vehicle_outline(vehicle)
            if i in self.runouts:
                tracks.append(self._runout_track(i, times, outline))
                continue
            n = len(times)
            tracks.append(Track(np.broadcast_to(np.asarray(vehicle.cg, float), (n, 2)).copy(),
                                np.full(n, float(vehicle.heading)), np.zeros((n, 2)),
                                np.zeros(n), outline=outline, fixed=bool(vehicle.fixed)))
            notes.append(f"vehicle {i} has no run-out evidence: held at its impact pose")
        stopped = tuple(bool(self.runouts[i].stopped) if i in self.runouts else True
                        for i in (1, 2))
        rest = max(float(f.runout.stop_time) for f in self.runouts.values())
        return Event(times, tracks[0], tracks[1],
                     phase_labels(times, [0.0], rest if all(stopped) else None),
                     source="reconstruction", stopped=stopped, notes=tuple(notes))

    def _runout_track(self, i: int, times: np.ndarray, outline) -> Track:
        """Vehicle ``i``'s fitted run-out at ``times`` with its wheels and sliding flags
        (none where the case keeps no ``[evidence]`` of its tyres)."""
        vehicle = getattr(self.case, f"vehicle{i}")
        track = self.runouts[i].runout.track(times, outline)
        evidence = getattr(self.case.evidence, f"vehicle{i}", None)
        if evidence is None:
            return track
        tyres = evidence.runout_vehicle(float(vehicle.mass), float(vehicle.yaw_inertia))
        states = np.column_stack([track.position, track.heading, track.velocity,
                                  track.yaw_rate])
        return replace(track, sliding=sliding_flags(states, tyres), wheels=tyres.positions)


def _velocity_covariance(fit: RunoutFit) -> tuple[np.ndarray, float]:
    """Covariance of (v_x, v_y) and sigma of omega from the polar (V, theta, omega) one."""
    c, s = np.cos(fit.direction), np.sin(fit.direction)
    jac = np.array([[c, -fit.speed * s, 0.0], [s, fit.speed * c, 0.0], [0.0, 0.0, 1.0]])
    cov = jac @ fit.covariance @ jac.T
    return cov[:2, :2], float(np.sqrt(max(cov[2, 2], 0.0)))


#: Slack [m] on the reach of :func:`check_reachable`: the regularised tyre law's extra
#: sliding (about 1 mm, :func:`pim.model.tyres.regularised_slide_distance`) and more.
REACH_SLACK = 1.0


def check_reachable(ev, vehicle, speed_bounds, yaw_rate_bounds, where: str) -> None:
    """InputError at once (instead of minutes of run-out fits) when no post-impact motion
    within the bounds can end at the rest evidence.

    All four wheels free-rolling never stop a car rolling straight (the tyre model has no
    rolling resistance). Otherwise, with ``f`` the smallest braking fraction, every wheel
    dissipates at least ``f mu N_i |v_i|``, and ``sum N_i |v_i| >= |sum N_i v_i| = m g |v|``
    (the static loads have their centroid at the CG), so the kinetic energy falls by at least
    ``f mu m g`` per metre of CG path: from at most ``(v_max^2 + k^2 w_max^2) / 2`` per unit
    mass the CG travels at most ``(v_max^2 + k^2 w_max^2) / (2 f mu g)``. A rest position
    farther from the CG at impact is unreachable. (With a free-rolling wheel, ``f = 0``, no
    such bound holds and the fit decides.)
    """
    braking = np.asarray(ev.braking, dtype=float)
    if not braking.any():
        raise InputError(f"{where}.wheels: with all four wheels free-rolling nothing stops a "
                         f"car rolling straight (the tyre model has no rolling resistance), "
                         f"so no run-out ends at rest; give the braked or locked wheels")
    f = float(braking.min())
    if f == 0:
        return
    k2 = float(vehicle.yaw_inertia) / float(vehicle.mass)
    w_max = max(abs(float(w)) for w in yaw_rate_bounds)
    reach = (float(speed_bounds[1]) ** 2 + k2 * w_max ** 2) / (2 * f * ev.friction
                                                                * STANDARD_GRAVITY)
    distance = float(np.hypot(*(np.asarray(ev.rest_position) - np.asarray(vehicle.cg))))
    if distance > reach + REACH_SLACK + 3 * ev.position_sigma:
        raise InputError(f"{where}.rest_position is {unit_text(distance, 'length')} from the CG "
                         f"at impact, beyond any run-out within the speed bound "
                         f"{speed_text(speed_bounds[1], '.4g')} and yaw-rate bound "
                         f"{unit_text(w_max, 'angular_velocity', '.4g')} (at most "
                         f"{unit_text(reach, 'length')} with friction {ev.friction:g} and "
                         f"braking {f:g} on every wheel)")


def post_impact_motion(case: Case, *, speed_bounds=(0.0, 60.0),
                       yaw_rate_bounds=(-15.0, 15.0), through_event: bool = True,
                       **fit_options) -> PostImpact:
    """Fit each vehicle's post-impact motion to its rest evidence (step 1 of the chain).

    Parameters
    ----------
    case : Case
        With ``evidence`` (the ``[evidence]`` table) for one or both vehicles.
    speed_bounds, yaw_rate_bounds : (float, float)
        [m/s], [rad/s] bounds of the post-impact motion searched.
    through_event : bool
        When the fitted single-impact run-outs run the outlines into each other again
        (their event, :func:`pim.analysis.event.event_rest_many`, has further impacts), fit
        the post-impact motion through the event instead
        (:func:`pim.analysis.event_fit.fit_through_event`; reconstruction through the event).
    **fit_options
        Passed to :func:`pim.analysis.runout_fit.fit_runout`.

    Raises
    ------
    ValueError
        The case has no evidence.
    """
    evidence = case.evidence
    if evidence is None or (evidence.vehicle1 is None and evidence.vehicle2 is None):
        raise InputError("evidence: the case has no [evidence] table (rest positions, "
                         "friction, wheelbase and track of at least one vehicle)")
    runouts, vel_cov, yaw_sigma, measured, messages = {}, {}, {}, {}, []
    for i in (1, 2):
        ev = getattr(evidence, f"vehicle{i}")
        if ev is None:
            continue
        vehicle = getattr(case, f"vehicle{i}")
        check_reachable(ev, vehicle, speed_bounds, yaw_rate_bounds, f"evidence.vehicle{i}")
        fit = fit_runout(ev.runout_vehicle(float(vehicle.mass), float(vehicle.yaw_inertia)),
                         vehicle.cg, float(vehicle.heading), ev.rest_position,
                         ev.rest_heading, path_points=ev.path_points if len(ev.path_points)
                         else None, position_sigma=ev.position_sigma,
                         heading_sigma=ev.heading_sigma, speed_bounds=speed_bounds,
                         yaw_rate_bounds=yaw_rate_bounds, **fit_options)
        runouts[i] = fit
        vel_cov[i], yaw_sigma[i] = _velocity_covariance(fit)
        measured[f"velocity{i}"] = fit.velocity
        measured[f"yaw_rate{i}"] = fit.yaw_rate
        measured[f"velocity{i}_sigma"] = np.sqrt(np.maximum(np.diag(vel_cov[i]), 1e-12))
        measured[f"yaw_rate{i}_sigma"] = max(yaw_sigma[i], 1e-9)
        if fit.message:
            messages.append(f"vehicle{i}: {fit.message}")
    momentum = None
    if len(runouts) == 2:
        momentum = momentum_speeds(float(case.vehicle1.mass), float(case.vehicle2.mass),
                                   approach_direction(case.vehicle1),
                                   approach_direction(case.vehicle2), runouts[1].velocity,
                                   runouts[2].velocity, vel_cov[1], vel_cov[2])
        if momentum.message:
            messages.append(f"linear momentum: {momentum.message}")
    post = PostImpact(replace(case, measured=_with_motion(case.measured, measured)), runouts,
                      vel_cov, yaw_sigma, momentum, messages)
    return _through_event(post) if through_event else post


def _through_event(post: PostImpact) -> PostImpact:
    """``post`` refitted through the event when the single-impact run-outs' motion runs the
    outlines into each other again (module notes of :mod:`pim.analysis.event_fit`); the
    messages name the impacts and how far the speeds move."""
    case = post.case
    if 1 not in post.runouts or (2 not in post.runouts and not bool(case.vehicle2.fixed)):
        return post
    if any(getattr(case, f"vehicle{i}").length is None or getattr(
            case, f"vehicle{i}").width is None for i in (1, 2)):
        return post
    velocity = np.stack([post.runouts[i].velocity if i in post.runouts else np.zeros(2)
                         for i in (1, 2)])
    yaw = np.array([post.runouts[i].yaw_rate if i in post.runouts else 0.0 for i in (1, 2)])
    single = event_rest_many(case, velocity[None], yaw[None])
    if int(single.impacts[0]) == 0:
        return post
    fit = fit_through_event(case, velocity, yaw)
    moved = [abs(float(np.hypot(*fit.velocity[i - 1])) - float(np.hypot(*velocity[i - 1])))
             for i in post.runouts]
    text = (f"the single-impact run-outs re-contact at t = {float(single.first_time[0]):.3g} s "
            f"after the impact ({int(single.impacts[0])} further impact(s)): the post-impact "
            f"motion is fitted through the event ({fit.impacts} further impact(s), "
            f"{fit.starts_agreeing} of {fit.starts} starts agree); the post-impact speeds "
            "move by " + ", ".join(f"{speed_text(m, '.3g')} (vehicle {i})"
                                  for i, m in zip(post.runouts, moved, strict=True)))
    measured = {f"velocity{i}": fit.velocity[i - 1] for i in post.runouts}
    measured.update({f"yaw_rate{i}": float(fit.yaw_rate[i - 1]) for i in post.runouts})
    kept = {k: getattr(case.measured, k) for k in ("velocity1_sigma", "velocity2_sigma",
                                                   "yaw_rate1_sigma", "yaw_rate2_sigma")}
    new_case = replace(case, measured=_with_motion(case.measured, {**measured, **{
        k: v for k, v in kept.items() if v is not None}}))
    return replace(post, case=new_case, messages=post.messages + [text], event_fit=fit,
                   single_event_impacts=int(single.impacts[0]))


def _with_motion(measured: Measured | None, motion: dict) -> Measured:
    """``measured`` with the run-out fits' post-impact ``motion`` in place of its own (the
    recorder's delta-V and pre-crash speed and the energy loss are kept)."""
    kept = {} if measured is None else {
        f.name: getattr(measured, f.name) for f in fields(Measured)
        if not f.name.startswith(("velocity", "yaw_rate"))}
    return Measured(**kept, **motion)


@dataclass(frozen=True)
class CrushOutput:
    """One vehicle's crush evidence at the reconstructed impact (SI).

    Attributes
    ----------
    vehicle : int
    energy, energy_sigma : float
        Crush energy of its profile before the force-balance factor and its sd [J].
    factor : float
        Force-balance factor 1 + tan^2(alpha) at the solution's impulse [-] (1 with the
        "normal" partition).
    ees : float
        Equivalent energy speed sqrt(2 E factor / m) [m/s].
    delta_v_crush : float
        Crush-energy delta-V |dV| of its CG from both vehicles' corrected energies, the
        solution's restitution and effective masses (:func:`pim.model.crush.crush_delta_v`)
        [m/s].
    delta_v_model : float
        |V' - V| of the PIM solution (momentum) [m/s], beside it.
    """

    vehicle: int
    energy: float
    energy_sigma: float
    factor: float
    ees: float
    delta_v_crush: float
    delta_v_model: float

    def to_dict(self) -> dict:
        return dict(vars(self))


def crush_outputs(case: Case, fitted: FitResult) -> tuple[CrushOutput, ...]:
    """EES, crush energy and crush-energy delta-V of each vehicle with a crush profile, at
    the inverse PIM's solution (its impulse sets the force-balance factors and, through the
    line of action at C, the effective masses gamma m = m I / (I + m h^2))."""
    terms = crush_terms(case)
    if not terms:
        return ()
    res = fitted.result
    q = result_quantities(res)
    factors = [float(np.asarray(f)) for f in terms[0].factors(q)]
    profiles = case.evidence.crush
    total = sum(p.energy * factors[i - 1] for i, p in profiles.items())
    p_vec = np.asarray(res.impulse, dtype=float)
    gammas, masses = [], []
    for i in (1, 2):
        v = getattr(res.case, f"vehicle{i}")
        arm = np.asarray(res.case.impact.point, float) - np.asarray(v.cg, float)
        h = moment_arm(arm[0], arm[1], p_vec[0], p_vec[1])
        masses.append(float(v.mass))
        gammas.append(float(effective_mass(v.mass, v.yaw_inertia, h)) / float(v.mass))
    # the corrected crush energies equal T_L, the energy dissipated (not the energy at
    # maximum engagement): CRASH3's delta-V with restitution in its "dissipated" reading
    dv = crush_delta_v(total, masses[0], masses[1], fitted.eps, energy_is="dissipated",
                       gamma1=gammas[0], gamma2=gammas[1])
    out = []
    for i, p in profiles.items():
        v = getattr(res.case, f"vehicle{i}")
        model = np.asarray(getattr(res, f"velocity{i}"), float) - np.asarray(v.velocity, float)
        out.append(CrushOutput(i, p.energy, p.energy_sigma, factors[i - 1],
                               float(equivalent_energy_speed(p.energy * factors[i - 1],
                                                             masses[i - 1])),
                               float(dv[i - 1]), float(np.hypot(*model))))
    return tuple(out)


@dataclass(frozen=True, kw_only=True)
class Reconstruction(Notebook):
    """Outcome of :func:`reconstruct` (SI); built by keyword.

    In a notebook it shows as a table in the case's units (:meth:`display_table`: each unknown's
    value and its 5-50-95 % percentiles); :meth:`to_dict` and ``to_frame()`` (pandas) give
    its numbers.

    Attributes
    ----------
    case : Case
        The case solved: the input case with ``measured`` = the post-impact motion used.
    unknown : dict
        The unknowns' bounds [SI] (the ``[unknown]`` table).
    post : PostImpact or None
        Step 1 (run-out inverse of the evidence); None when the case's ``[measured]`` motion
        was used directly.
    fit : FitResult or None
        The inverse PIM (None when under-determined).
    values : dict
        Unknown key -> solved value [SI] (empty when under-determined).
    momentum : MomentumSpeeds or None
        The linear-momentum check (both vehicles' post-impact velocities needed).
    samples : ReconstructionSamples or None
        The Monte Carlo (None without ``samples``).
    determined : bool
        False when the data cannot decide the unknowns (``messages`` says why).
    messages : list of str
    crush : tuple of CrushOutput
        Per vehicle with a crush profile: EES, crush energy, crush-energy delta-V beside the
        solution's delta-V (empty without crush evidence or a solution).
    """

    case: Case
    unknown: dict
    post: PostImpact | None
    fit: FitResult | None
    values: dict
    momentum: MomentumSpeeds | None
    samples: ReconstructionSamples | None = None
    determined: bool
    messages: list
    crush: tuple = ()

    @property
    def goodness(self) -> GoodnessOfFit | None:
        """Chi-square test of the inverse PIM (None without standard deviations or a fit)."""
        return None if self.fit is None else self.fit.goodness

    @property
    def contradiction(self) -> str | None:
        """Why the answer is refused when the evidence contradicts itself beyond
        :data:`pim.analysis.residuals.P_CONTRADICTED` (:meth:`GoodnessOfFit.refusal`), else
        None."""
        return contradiction(self.goodness)

    def table(self) -> list[dict]:
        """Per unknown: name, value, p5, p50, p95 [SI] (percentiles NaN without samples)."""
        rows = []
        for key, value in self.values.items():
            st = self.samples.stats.get(key) if self.samples else None
            rows.append({"name": key, "value": float(value),
                         "p5": st.p5 if st else float("nan"),
                         "p50": st.p50 if st else float("nan"),
                         "p95": st.p95 if st else float("nan"),
                         "drivers": st.drivers if st else []})
        return rows

    def __repr__(self) -> str:
        if not self.determined:
            return f"Reconstruction({self.case.name or '(unnamed)'!r}: under-determined)"
        shown = display_units(case=self.case)
        values = []
        for key, value in self.values.items():
            v, unit = convert(value, free_kind(key), shown)
            values.append(f"{key}={short(v, '' if unit == '-' else unit)}")
        samples = f", {self.samples.n} Monte Carlo samples" if self.samples else ""
        return f"Reconstruction({self.case.name or '(unnamed)'!r}: {', '.join(values)}{samples})"

    def display_table(self, units=None) -> Table:
        """Each unknown's solved value and, with a Monte Carlo, its 5th, 50th and 95th
        percentiles, in ``units`` (default the case's); the messages in the notes."""
        shown = display_units(units, case=self.case)
        rows = []
        for row in self.table():
            values, unit = convert([row["value"], row["p5"], row["p50"], row["p95"]],
                                   free_kind(row["name"]), shown)
            rows.append((free_label(row["name"]), *map(float, values), unit))
        notes = [f"{shown}; angles in deg, yaw rates in deg/s", *self.messages]
        if not self.determined:
            notes.insert(0, f"under-determined: {self.undetermined_reason}")
        return Table(f"reconstruction of {self.case.name or 'case'}",
                     ("unknown", "value", "5 %", "50 %", "95 %", "unit"), tuple(rows),
                     tuple(notes))

    def to_dict(self, units=None) -> dict:
        """JSON-ready: each unknown's value and percentiles in ``units`` (default the
        case's), whether the data decide them, the messages, the chi-square test, the Monte
        Carlo's counts (:meth:`ReconstructionSamples.to_dict`)."""
        shown = display_units(units, case=self.case)
        unknowns = {}
        for row in self.table():
            values, unit = convert([row["value"], row["p5"], row["p50"], row["p95"]],
                                   free_kind(row["name"]), shown)
            unknowns[row["name"]] = dict(zip(("value", "p5", "p50", "p95"),
                                             map(float, values), strict=True)) | {"unit": unit}
        return {"case": self.case.name,
                "units": {"system": shown.system, "speed": shown.speed},
                "determined": self.determined, "unknowns": unknowns,
                "messages": list(self.messages),
                "goodness_of_fit": None if self.goodness is None else self.goodness.to_dict(),
                "crush": [c.to_dict() for c in self.crush],
                "monte_carlo": None if self.samples is None else self.samples.to_dict()}

    @property
    def undetermined_reason(self) -> str:
        """Why the data cannot decide the unknowns: the message that says so (an
        under-determined fit, a family of equally good fits), else all messages."""
        return next((m for m in self.messages if "under-determined" in m or "family" in m
                     or "equally well" in m), "; ".join(self.messages))


def reconstruct(case: Case, *, unknown: dict | None = None, samples: int = 0, seed: int = 0,
                include_yaw: bool = True, post_impact_samples=None, executor=None,
                blocks: int | None = None, progress=None, estimate=None) -> Reconstruction:
    """Evidence (or measured post-impact motion) -> impact speeds, eps, beta, with intervals.

    Parameters
    ----------
    case : Case
        With ``[evidence]`` for one or both vehicles, or with ``[measured]`` post-impact motion;
        and the unknowns (``[unknown]`` or ``unknown``).
    unknown : dict, optional
        Dotted key -> (low, high) [SI]; default ``case.unknown``.
    samples : int
        Monte Carlo samples (0: none).
    seed : int
        Seed of the Monte Carlo.
    include_yaw : bool
        Fit the post-impact yaw rates too (default).
    post_impact_samples : callable, optional
        Per-sample post-impact motion from the evidence, for the Monte Carlo (see
        :func:`pim.analysis.reconstruction_mc.reconstruction_samples`); in-process only.
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Spread the Monte Carlo over it in ``blocks`` blocks of samples (each block seeded
        from ``seed`` by ``numpy.random.SeedSequence.spawn``, so a run repeats for a given
        block count); None: one block in this process (numpy and numba's threads).
    blocks : int, optional
        Number of blocks with an executor (default 4).
    progress : callable, optional
        Called with the name of each stage as it starts ("run-out fits", "inverse PIM",
        "Monte Carlo") and once per finished Monte Carlo block ("Monte Carlo block i/k"),
        e.g. to move a progress bar; the results do not depend on it.
    estimate : callable, optional
        Called with the Monte Carlo's estimated time [s] before it starts (run-out evidence,
        :func:`monte_carlo_seconds`); it may raise to refuse the work.

    Returns
    -------
    Reconstruction
        With ``determined = False`` and a message naming what is missing when the data cannot
        decide the unknowns; never a number then.
    """
    _check_arguments(case, executor)
    samples = checked_count(samples, "samples", low=0)
    seed = checked_count(seed, "seed", low=0)
    check_counts(blocks=blocks)
    unknown = check_free(case.unknown if unknown is None else unknown)
    if not unknown:
        raise InputError("unknown: nothing to solve for; name the unknowns in an [unknown] "
                         "table (e.g. vehicle1.speed = {bounds = [\"0 mph\", \"80 mph\"]})")
    check_evidence(case, unknown)
    say = progress or (lambda stage: None)
    post, solved = _post_impact(case, say)
    messages = list(post.messages) if post else []
    momentum = post.momentum if post else _momentum_of(solved)
    if momentum is not None and momentum.message and not post:
        messages.append(f"linear momentum: {momentum.message}")
    why = under_determined(solved, unknown, include_yaw)
    if why:
        return Reconstruction(case=solved, unknown=unknown, post=post, fit=None, values={},
                              momentum=momentum, determined=False, messages=messages + [why])
    say("inverse PIM")
    fitted = inverse_pim(solved, unknown, include_yaw=include_yaw)
    determined, said = _judge(fitted)
    messages += said
    values = {k: v for k, v in fitted.values.items()} if determined else {}
    if momentum is not None and not post and solved.measured.velocity1_sigma is None:
        s_hat = residual_standard_error(fitted)          # no sigma stated: the fit's
        if np.isfinite(s_hat):
            momentum = _momentum_of(solved, s_hat)
    rec = Reconstruction(case=solved, unknown=unknown, post=post, fit=fitted, values=values,
                         momentum=momentum, determined=determined, messages=messages,
                         crush=crush_outputs(solved, fitted) if determined else ())
    if determined and samples:
        _time_monte_carlo(estimate, case, post, fitted, unknown, samples, include_yaw,
                          post_impact_samples)
        say("Monte Carlo")
        mc = _monte_carlo(case, rec, samples=samples, seed=seed, include_yaw=include_yaw,
                          sampler=post_impact_samples, executor=executor, blocks=blocks, say=say)
        rec = replace(rec, samples=mc, messages=messages + mc.messages)
    return rec


#: Samples of the pilot that times a Monte Carlo with run-out evidence, after a warm-up of
#: 10 (which compiles the run-out kernels); its random stream is its own (PILOT_SEED), so
#: the run's samples are those of a run without it.
PILOT_SAMPLES = 50
PILOT_SEED = 20_260_228
#: Fewest Monte Carlo samples whose time is estimated (below, the pilot would cost a
#: sizeable share of the run).
TIMED_SAMPLES = 1000


def monte_carlo_seconds(case: Case, post: PostImpact, solved: Case, fitted: FitResult,
                        unknown: dict, samples: int, include_yaw: bool = True) -> float:
    """Estimated wall time [s] of :func:`reconstruct`'s Monte Carlo of ``samples`` samples
    in this process with run-out evidence (every sample refits the run-outs): a pilot of
    :data:`PILOT_SAMPLES` samples timed and scaled (its fixed costs included: an upper
    estimate)."""
    sampler, extra = evidence_sampler(case, post, include_yaw), evidence_nominal(case, post)
    rng = np.random.default_rng(PILOT_SEED)

    def run(n: int) -> float:
        start = time.perf_counter()
        solve_samples(solved, fitted, unknown, n, rng, include_yaw=include_yaw,
                      post_impact=sampler, extra_nominal=extra)
        return time.perf_counter() - start

    run(10)
    return run(PILOT_SAMPLES) * samples / PILOT_SAMPLES


def _time_monte_carlo(estimate, case, post, fitted, unknown, samples, include_yaw,
                      post_impact_samples) -> None:
    """``estimate(seconds)`` of a Monte Carlo of ``samples`` that refits the run-outs (from
    :data:`TIMED_SAMPLES` samples up; nothing to time otherwise)."""
    if estimate is not None and post is not None and post_impact_samples is None \
            and samples >= TIMED_SAMPLES:
        estimate(monte_carlo_seconds(case, post, post.case, fitted, unknown, samples,
                                     include_yaw))


def _check_arguments(case, executor) -> None:
    """``case`` is a Case (:func:`checked_case`); ``executor`` None, an Executor (anything
    with ``map``) or a Dask client (``get_executor``)."""
    checked_case(case)
    if executor is None or hasattr(executor, "map") or hasattr(executor, "get_executor"):
        return
    got = repr(executor) if isinstance(executor, str) else f"a {type(executor).__name__}"
    raise ArgumentTypeError(f"executor must be None (this process), a "
                            f"concurrent.futures.Executor or a dask.distributed.Client, got {got}")


def _post_impact(case: Case, say) -> tuple[PostImpact | None, Case]:
    """Step 1 when the case has run-out evidence (else None), and the case to solve:
    refused when it has no data at all."""
    has_runout = case.evidence is not None and case.evidence.has_runout
    if has_runout:
        say("run-out fits")
    post = post_impact_motion(case) if has_runout else None
    solved = post.case if post else case
    if solved.measured is None and not crush_terms(solved):
        raise InputError("reconstruct: the case has neither [evidence] nor [measured] data "
                         "(a run-out's rest position, post-impact motion, a recorded delta_v or "
                         "pre_crash_speed, an energy_loss)")
    return post, solved


def _judge(fitted: FitResult) -> tuple[bool, list[str]]:
    """Whether the inverse PIM determines the unknowns, and what to tell the user: the
    identifiability warnings, parameters on a bound, a chi-square that says the data do not
    fit, several equally good solutions."""
    ident = fitted.identifiability
    determined = ident is None or ident.identifiable
    messages = list(ident.warnings) if ident else []
    messages += [f"{key} sits on its {side} bound" for key, side in fitted.on_bound.items()]
    if fitted.goodness is not None and fitted.goodness.consistent is False:
        messages.append(fitted.goodness.summary())
    best = fitted.minima_values[0][1] if fitted.minima_values else 0.0
    equal = [v for v, c in fitted.minima_values if c <= best * (1 + 1e-6) + 1e-12]
    if len(equal) > 1:
        determined = False
        messages.append(f"{len(equal)} distinct solutions fit equally well (" + "; ".join(
            ", ".join(f"{k} = {x:.4g}" for k, x in v.items()) for v in equal)
            + "): the data do not decide between them")
    return determined, messages


def _monte_carlo(case: Case, rec: Reconstruction, *, samples, seed, include_yaw, sampler,
                 executor, blocks, say) -> ReconstructionSamples:
    """The Monte Carlo of :func:`reconstruct` around the solution ``rec`` of ``case`` (its
    arguments as :func:`reconstruct`'s, ``sampler`` its ``post_impact_samples``): in this
    process, or in seeded blocks on the executor."""
    post, solved, fitted, unknown = rec.post, rec.case, rec.fit, rec.unknown
    if executor is None or sampler is not None:
        extra_nominal = {}
        if post is not None and sampler is None:
            extra_nominal = evidence_nominal(case, post)
            sampler = evidence_sampler(case, post, include_yaw)
        return reconstruction_samples(solved, fitted, unknown, n=samples, seed=seed,
                                      include_yaw=include_yaw, post_impact=sampler,
                                      extra_nominal=extra_nominal)
    k = int(blocks or 4)
    sizes = [len(part) for part in np.array_split(np.arange(samples), k) if len(part)]
    seeds = np.random.SeedSequence(seed).spawn(len(sizes))
    pool = executor.get_executor() if hasattr(executor, "get_executor") else executor
    shown = message_units()             # the workers' messages in the user's units too
    jobs = [(solved, fitted, unknown, size, sq, include_yaw, case, post, shown)
            for size, sq in zip(sizes, seeds, strict=True)]
    done = []
    for block in pool.map(sample_block, jobs):      # in order: the pooled result repeats
        done.append(block)
        say(f"Monte Carlo block {len(done)}/{len(jobs)}")
    return summarise(fitted, done)


def _momentum_of(case: Case, sigma: float | None = None) -> MomentumSpeeds | None:
    """The linear-momentum speeds of the measured motion; ``sigma`` [m/s] (isotropic)
    replaces the stated standard deviations."""
    m = case.measured
    if (m is None or m.velocity1 is None or m.velocity2 is None
            or np.any(case.vehicle2.fixed) or np.any(case.vehicle1.fixed)):
        return None
    return momentum_speeds(float(case.vehicle1.mass), float(case.vehicle2.mass),
                           approach_direction(case.vehicle1),
                           approach_direction(case.vehicle2), m.velocity1, m.velocity2,
                           _covariance(m.velocity1_sigma, sigma),
                           _covariance(m.velocity2_sigma, sigma))


def _covariance(stated, sigma):
    if sigma is not None:
        return float(sigma)
    return 0.0 if stated is None else np.diag(np.asarray(stated) ** 2)


def evidence_sampler(case: Case, post: PostImpact, include_yaw: bool = True):
    """The Monte Carlo's post-impact motion per sample from the evidence.

    Returns ``sampler(values, uniforms, rng, n) -> (targets (n, k), ok (n,), uniforms)``: for
    each vehicle with evidence, its rest position and heading and its tyre-mark points drawn
    normal about the measured ones with the evidence's sigmas (one uniform variate each, for
    the driver attribution),
    its friction, mass, yaw inertia, separation position and heading from the sampled inputs
    ``values``; all samples' run-out inverses solved at once
    (:func:`pim.analysis.runout_fit_batch.fit_runout_many`, started from the nominal fit).
    ``ok`` drops the samples whose run-out fit did not converge or whose motion does not stop.

    When the nominal post-impact motion was fitted through the event (``post.event_fit``:
    the single-impact run-outs re-contact), each sample's is too
    (:func:`pim.analysis.event_samples.event_sampler`, which also returns the fits' counts).
    """
    from scipy.special import ndtri

    from .runout_fit_batch import fit_runout_many  # compiled run-out: numba on first use

    if post.event_fit is not None:
        return event_sampler(case, post, include_yaw)

    terms = measured_terms(post.case, include_yaw)

    def sampler(values, uniforms, rng, n):
        def each(name):
            return np.broadcast_to(np.asarray(values[name], dtype=float), (n,))

        targets = np.empty((n, len(terms)))
        ok = np.ones(n, dtype=bool)
        extra = {}
        for i, nominal in post.runouts.items():
            ev = getattr(case.evidence, f"vehicle{i}")
            p = f"vehicle{i}."
            rest, rest_heading, u = rest_draws(ev, i, rng, n)
            extra.update(u)
            points = None
            if len(ev.path_points):      # the tyre-mark points carry the same position error
                points = np.empty((n,) + ev.path_points.shape)
                for k, point in enumerate(ev.path_points):
                    for axis, name in enumerate("xy"):
                        key = f"evidence.vehicle{i}.path_point{k + 1}_{name}"
                        extra[key] = rng.random(n) + 2.0**-54
                        points[:, k, axis] = point[axis] + ev.position_sigma * ndtri(
                            extra[key])
            vehicle = replace(ev.runout_vehicle(each(p + "mass"), each(p + "yaw_inertia")),
                              friction=each(f"evidence.vehicle{i}.friction"))
            fit = fit_runout_many(
                vehicle, np.stack([each(p + "cg_x"), each(p + "cg_y")], axis=-1),
                each(p + "heading"), rest, rest_heading,
                start=(nominal.speed, nominal.direction, nominal.yaw_rate),
                path_points=points, position_sigma=ev.position_sigma,
                heading_sigma=ev.heading_sigma)
            ok &= fit.converged & fit.stopped
            for j, term in enumerate(terms):
                if isinstance(term, Term) and term.vehicle == i:
                    targets[:, j] = (fit.velocity[:, term.axis] if term.is_velocity
                                     else fit.yaw_rate)
        return targets, ok, extra

    return sampler


def evidence_nominal(case: Case, post: PostImpact) -> dict:
    """Nominal values of the evidence inputs an ``[uncertainty]`` table may vary."""
    return {f"evidence.vehicle{i}.friction": float(getattr(case.evidence, f"vehicle{i}").friction)
            for i in post.runouts}


def sample_block(job):
    """One block of a reconstruction's Monte Carlo (a top-level function, so that a process
    pool or a Dask cluster can run it): ``job`` = (solved case, nominal fit, unknowns, block
    size, SeedSequence, include_yaw, input case, PostImpact or None[, the units of the
    messages, :func:`pim.model.numbers.message_units`, which a process does not inherit])."""
    solved, fitted, unknown, size, seed_sequence, include_yaw, case, post, *shown = job
    sampler, extra = None, {}
    if post is not None:
        sampler, extra = evidence_sampler(case, post, include_yaw), evidence_nominal(case, post)
    with units_in(shown[0] if shown else {}):
        return solve_samples(solved, fitted, unknown, size,
                             np.random.default_rng(seed_sequence), include_yaw=include_yaw,
                             post_impact=sampler, extra_nominal=extra)


#: Blocks of Monte Carlo samples per worker process (:func:`reconstruct`'s ``blocks``).
BLOCKS_PER_WORKER = 2


def worker_blocks(workers: int) -> int:
    """The number of Monte Carlo blocks :func:`reconstruct` spreads over ``workers``
    processes (:data:`BLOCKS_PER_WORKER` each)."""
    return BLOCKS_PER_WORKER * workers


def progress_stages(case: Case, samples: int, workers: int = 1) -> int:
    """How many times :func:`reconstruct` calls ``progress``: the run-out fits (with
    ``[evidence]``), the inverse PIM, and the Monte Carlo (one stage in this process; with
    ``workers`` > 1 its start and two per worker's block, :func:`worker_blocks`)."""
    ev = case.evidence
    has_evidence = ev is not None and (ev.vehicle1 is not None or ev.vehicle2 is not None)
    monte_carlo = 0 if not samples else 1 if workers == 1 else 1 + worker_blocks(workers)
    return int(has_evidence) + 1 + monte_carlo


@dataclass(frozen=True)
class MonteCarloBudget:
    """The time a reconstruction's Monte Carlo may take, against its estimate.

    Attributes
    ----------
    samples : int
        Monte Carlo samples asked for.
    workers : int
        Processes they are spread over (the estimate is for one).
    max_minutes : float
        The longest run allowed [min].
    note_seconds : float
        Runs longer than this [s] are worth a note (default 10 s).
    """

    samples: int
    workers: int
    max_minutes: float
    note_seconds: float = 10.0

    def wall_seconds(self, estimate: float) -> float:
        """The wall time [s] of a run estimated at ``estimate`` [s] in one process."""
        return estimate / self.workers

    def over(self, seconds: float) -> bool:
        """Whether a run of ``seconds`` [s] wall time exceeds the budget."""
        return seconds > 60.0 * self.max_minutes

    def noted(self, seconds: float) -> bool:
        """Whether a run of ``seconds`` [s] wall time is long enough to say so."""
        return seconds > self.note_seconds

    def affordable(self, seconds: float) -> int:
        """The samples that fit in the budget when all of them take ``seconds`` [s]."""
        return int(self.samples * 60.0 * self.max_minutes / seconds)
