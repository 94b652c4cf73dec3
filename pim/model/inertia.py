"""A vehicle's yaw moment of inertia estimated from its mass and wheelbase (yaw dynamic index).

When a case gives no yaw inertia (nor radius of gyration) for a vehicle, the yaw dynamic
index estimates it::

    I_z = D m a b        (D = k_z^2 / (a b), k_z = sqrt(I_z / m) the radius of gyration)

with ``m`` the mass, ``a`` and ``b = L - a`` the CG's distances to the front and rear axle
(``L`` the wheelbase) and ``D`` the yaw dynamic index of the vehicle's body class. The index
is Olley's k^2 / (a b), as Gillespie (1992, "Fundamentals of Vehicle Dynamics", SAE) uses
it for pitch; its yaw values come from NHTSA's measured vehicles (Heydinger et al., SAE
1999-01-1336: 204 vehicles, 73 of them cars, as tabulated by K. Tse 2020; the rows ship in
``pim/io/data/nhtsa_lvipd_yaw_dynamic_index.csv`` and :mod:`pim.io.inertia_data` reads
them). The index varies from vehicle to vehicle by about 7 % (1 sd) within a class: that
scatter, not the mean's, is what an estimate for one vehicle carries, so its standard
deviation is the predictive one, ``s sqrt(1 + 1/n)`` (``s`` the class's sample standard
deviation of D, ``n`` its count). docs/inertia-estimate.md has the figures, written by
``python -m comparisons.docs inertia-estimate``.

Without the CG's axle position, the CG's fraction of the wheelbase behind the front axle,
``f = a / L``, of the vehicle's body class (:class:`AxleFraction`, measured on NHTSA's NCAP
2004 vehicles, :mod:`pim.io.axle_data`) estimates it: with ``f`` of mean ``mu`` and
predictive sd ``s``, ``E[f (1 - f)] = mu (1 - mu) - s^2`` exactly, and its sd is taken to
first order, ``|1 - 2 mu| s``; the two scatters (D's and f's) are independent, so the
estimate's variance is that of a product of independent factors. Only without either
(``fraction=None``) does ``a = b = L / 2`` remain: the largest ``a b`` for the wheelbase, an
upper estimate.

Without a wheelbase, the yaw inertia is estimated from the mass alone by the least-squares
line of the measured vehicles' yaw inertia on their mass (:class:`MassRegression`)::

    I_z = c1 m + c0

fitted on the same NHTSA vehicles per group (cars; light trucks: SUVs, pickups and vans), as
K. Tse (2020) published it (cars: I_z = 3.176 m - 1754.164 kg m^2, R^2 = 0.920, 73
vehicles; trucks: 3.168 m - 2021.319, R^2 = 0.770, 131; all: 2.961 m - 1596.431, R^2 =
0.845, 204). The line's scatter grows with the mass: its residuals are nearly proportional
to the fitted value, so the estimate carries the relative residual sd ``s`` (residual over
fitted value, n - 2 degrees of freedom) as a predictive one,
``s I_z sqrt(1 + 1/n + (m - mean m)^2 / S_mm)``. Outside the group's measured masses the
line is not used (an error says so). It is wider than the dynamic index's estimate
(docs/inertia-estimate.md has both): give the wheelbase where it is known.

With the overall length l but no wheelbase, the wheelbase comes from the length by the
least-squares line of measured vehicles' wheelbase on their length (:class:`WheelbaseLine`,
fitted on Lock's 1993 cars, :mod:`pim.io.length_data`), taken as normal about the line with
its predictive sd, and :func:`yaw_inertia_from_length` carries its scatter with D's and
f's: the three factors are independent, so the estimate's variance is that of their
product.

Everything here is pure and vectorised: masses, wheelbases and axle positions broadcast.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .numbers import InputError, real_array

__all__ = ["ClassSample", "DynamicIndex", "AxleFraction", "InputEstimate", "BODIES",
           "dynamic_index", "MassRegression", "mass_regression", "yaw_inertia_from_mass",
           "axle_fraction", "yaw_inertia_estimate", "WheelbaseLine", "wheelbase_line",
           "yaw_inertia_from_length", "independent_product"]

#: Body classes with their own yaw dynamic index, and the NHTSA database's type codes in each
#: (:mod:`pim.io.inertia_data`): cars (sedans, coupes, hatchbacks, wagons), SUVs
#: ("multi-purpose"), pickups, vans.
BODIES = {"car": ("4S", "2S", "2C", "3H", "5H", "SW"), "suv": ("MP",), "pickup": ("PU",),
          "van": ("VN",)}


@dataclass(frozen=True)
class ClassSample:
    """A quantity measured on the vehicles of one body class: its mean and scatter.

    The base of :class:`DynamicIndex` and :class:`AxleFraction`, which add their own checks.

    Attributes
    ----------
    body : str
        The class, a key of :data:`BODIES` (or "all" for every class pooled).
    mean : float
        Sample mean over the class's measured vehicles.
    sd : float
        Their sample standard deviation (n - 1 in the denominator).
    count : int
        Number of measured vehicles, >= 2.
    source : str
        Short citation of the measurements, for notes and reports.
    """

    body: str
    mean: float
    sd: float
    count: int
    source: str

    @property
    def predictive_sd(self) -> float:
        """Standard deviation for one more vehicle of the class, s sqrt(1 + 1/n): the scatter
        an estimate for one vehicle carries, not the mean's."""
        return self.sd * math.sqrt(1.0 + 1.0 / self.count)

    @classmethod
    def of(cls, values, body: str, source: str, what: str):
        """The class's sample from its vehicles' measured ``values`` (``what`` names the
        quantity in errors): at least 2 finite values."""
        v = real_array(values, f"{what} of {body!r}").ravel()
        if v.size < 2 or not np.isfinite(v).all():
            raise InputError(f"{what} of {body!r} needs at least 2 finite values")
        return cls(body, float(v.mean()), float(v.std(ddof=1)), int(v.size), source)


@dataclass(frozen=True)
class DynamicIndex(ClassSample):
    """The yaw dynamic index D = I_z / (m a b) of one body class: its mean and scatter.

    Attributes
    ----------
    body : str
        The class, a key of :data:`BODIES`.
    mean : float
        Sample mean of D over the class's measured vehicles [-].
    sd : float
        Their sample standard deviation (n - 1 in the denominator) [-].
    count : int
        Number of measured vehicles, >= 2.
    source : str
        Short citation of the measurements, for notes and reports.
    """

    def __post_init__(self) -> None:
        if not (math.isfinite(self.mean) and self.mean > 0 and math.isfinite(self.sd)
                and self.sd >= 0 and self.count >= 2):
            raise InputError(f"dynamic index of {self.body!r}: needs a mean > 0, a finite "
                             f"sd >= 0 and at least 2 vehicles, got {self.mean!r}, "
                             f"{self.sd!r}, {self.count!r}")

    @property
    def relative_sd(self) -> float:
        """:attr:`predictive_sd` over :attr:`mean` [-]: the estimate's relative scatter."""
        return self.predictive_sd / self.mean


def dynamic_index(values, body: str, source: str) -> DynamicIndex:
    """The :class:`DynamicIndex` of a class from its vehicles' measured indices.

    Parameters
    ----------
    values : array_like
        Yaw dynamic indices D = I_z / (m a b) of the class's measured vehicles [-].
    body : str
        The class, a key of :data:`BODIES`.
    source : str
        Short citation of the measurements.
    """
    return DynamicIndex.of(values, body, source, "dynamic index")


@dataclass(frozen=True)
class AxleFraction(ClassSample):
    """The CG's position between the axles, f = a / L, of one body class: mean and scatter.

    Attributes
    ----------
    body : str
        The class, a key of :data:`BODIES`, or "all" for every class pooled.
    mean : float
        Sample mean of f over the class's measured vehicles [-], in (0, 1).
    sd : float
        Their sample standard deviation (n - 1 in the denominator) [-].
    count : int
        Number of measured vehicles, >= 2.
    source : str
        Short citation of the measurements, for notes and reports.
    """

    def __post_init__(self) -> None:
        if not (0 < self.mean < 1 and math.isfinite(self.sd) and self.sd >= 0
                and self.count >= 2):
            raise InputError(f"CG position of {self.body!r}: needs a mean fraction of the "
                             f"wheelbase in (0, 1), a finite sd >= 0 and at least 2 vehicles, "
                             f"got {self.mean!r}, {self.sd!r}, {self.count!r}")

    def axle_product(self):
        """Mean and sd of f (1 - f) for one more vehicle [-]: ``mu (1 - mu) - s^2`` (exact
        for any distribution of f with that mean and variance) and ``|1 - 2 mu| s`` (first
        order), s the predictive sd."""
        s = self.predictive_sd
        return self.mean * (1.0 - self.mean) - s * s, abs(1.0 - 2.0 * self.mean) * s


def axle_fraction(values, body: str, source: str) -> AxleFraction:
    """The :class:`AxleFraction` of a class from its vehicles' measured a / L.

    Parameters
    ----------
    values : array_like
        CG-to-front-axle distance over wheelbase, a / L, of the class's vehicles [-].
    body : str
        The class, a key of :data:`BODIES` (or "all").
    source : str
        Short citation of the measurements.
    """
    return AxleFraction.of(values, body, source, "CG position")


def yaw_inertia_estimate(mass, wheelbase, index: DynamicIndex, cg_to_front_axle=None,
                         fraction: AxleFraction | None = None):
    """Yaw moment of inertia about the CG from mass and wheelbase: I_z = D m a (L - a).

    Parameters
    ----------
    mass : array_like
        Vehicle mass m [kg], > 0.
    wheelbase : array_like
        Wheelbase L [m], > 0.
    index : DynamicIndex
        The body class's yaw dynamic index D (:func:`dynamic_index`).
    cg_to_front_axle : array_like, optional
        CG forward to the front axle, a [m], in (0, L).
    fraction : AxleFraction, optional
        Without ``cg_to_front_axle``: the class's CG position f = a / L, whose scatter the
        estimate then carries, ``I_z = D m L^2 E[f (1 - f)]`` (module notes). Without
        either, a = L / 2 (the largest a b: an upper estimate).

    Returns
    -------
    inertia : ndarray
        The estimate [kg m^2].
    sd : ndarray
        Its standard deviation [kg m^2]: D's predictive sd times m a (L - a) for a given
        (or L/2) axle position; with ``fraction``, that of the product of the independent
        D and f (1 - f), ``m L^2 sqrt(sD^2 sg^2 + sD^2 g^2 + sg^2 D^2)`` (mass and wheelbase
        taken as exact).

    Raises
    ------
    InputError
        A mass or wheelbase not > 0, an axle position outside (0, L), or a non-number.
    """
    m = real_array(mass, "mass", "kg")
    length = real_array(wheelbase, "wheelbase", "m")
    a = length / 2 if cg_to_front_axle is None else real_array(cg_to_front_axle,
                                                                 "cg_to_front_axle", "m")
    if not (np.isfinite(m).all() and (m > 0).all()):
        raise InputError("mass must be finite and > 0 [kg] to estimate the yaw inertia")
    if not (np.isfinite(length).all() and (length > 0).all()):
        raise InputError("wheelbase must be finite and > 0 [m] to estimate the yaw inertia")
    if not (np.isfinite(a).all() and ((a > 0) & (a < length)).all()):
        raise InputError("cg_to_front_axle must lie strictly between 0 and the wheelbase [m] "
                         "to estimate the yaw inertia (the CG between the axles)")
    if cg_to_front_axle is None and fraction is not None:
        mean, sd = independent_product((index.mean, index.predictive_sd),
                                       fraction.axle_product())
        scale = m * length * length
        return mean * scale, sd * scale
    scale = m * a * (length - a)
    return index.mean * scale, index.predictive_sd * scale


@dataclass(frozen=True)
class MassRegression:
    """The least-squares line I_z = slope m + intercept of measured vehicles' yaw inertia on
    their mass, with the relative scatter about it.

    Attributes
    ----------
    group : str
        The vehicles it is fitted on (e.g. "car", "truck").
    slope : float
        [kg m^2 / kg] = [m^2].
    intercept : float
        [kg m^2].
    r_squared : float
        Share of the inertias' variance the line explains [-].
    relative_sd : float
        Sample sd of the residuals over the fitted values, (I - fit) / fit, with n - 2
        degrees of freedom [-].
    count : int
        Number of vehicles, >= 3.
    mass_mean : float
        Mean of their masses [kg].
    mass_ss : float
        Sum of their masses' squared deviations from the mean, S_mm [kg^2], > 0.
    mass_range : tuple of float
        Lightest and heaviest measured mass [kg]: the line is used only between them.
    source : str
        Short citation of the measurements and of the line, for notes and reports.
    """

    group: str
    slope: float
    intercept: float
    r_squared: float
    relative_sd: float
    count: int
    mass_mean: float
    mass_ss: float
    mass_range: tuple
    source: str

    def predictive_sd(self, mass):
        """Relative sd of one more vehicle's inertia at ``mass`` [kg] [-]:
        s sqrt(1 + 1/n + (m - mean m)^2 / S_mm)."""
        m = np.asarray(mass, dtype=float)
        return self.relative_sd * np.sqrt(1.0 + 1.0 / self.count
                                          + (m - self.mass_mean) ** 2 / self.mass_ss)


def mass_regression(masses, inertias, group: str, source: str) -> MassRegression:
    """The :class:`MassRegression` of measured vehicles.

    Parameters
    ----------
    masses : array_like
        Their masses m [kg], at least 3, not all equal.
    inertias : array_like
        Their measured yaw inertias I_z [kg m^2], as many.
    group : str
        What the vehicles are (for messages).
    source : str
        Short citation.
    """
    m = real_array(masses, f"masses of {group!r}", "kg").ravel()
    izz = real_array(inertias, f"yaw inertias of {group!r}", "kg m^2").ravel()
    if m.size != izz.size or m.size < 3 or not (np.isfinite(m).all()
                                                and np.isfinite(izz).all()) or np.ptp(m) == 0:
        raise InputError(f"mass regression of {group!r} needs at least 3 finite (mass, "
                         f"inertia) pairs with different masses")
    slope, intercept = np.polyfit(m, izz, 1)
    fit = slope * m + intercept
    residual = izz - fit
    r2 = 1.0 - float(residual @ residual) / float(((izz - izz.mean()) ** 2).sum())
    rel = float(np.sqrt(np.sum((residual / fit) ** 2) / (m.size - 2)))
    return MassRegression(group=group, slope=float(slope), intercept=float(intercept),
                          r_squared=r2, relative_sd=rel, count=int(m.size),
                          mass_mean=float(m.mean()),
                          mass_ss=float(((m - m.mean()) ** 2).sum()),
                          mass_range=(float(m.min()), float(m.max())), source=source)


def yaw_inertia_from_mass(mass, regression: MassRegression):
    """Yaw moment of inertia about the CG from the mass alone: I_z = slope m + intercept.

    Parameters
    ----------
    mass : array_like
        Vehicle mass m [kg], within ``regression.mass_range``.
    regression : MassRegression
        The line of the vehicle's group (:func:`mass_regression`).

    Returns
    -------
    inertia : ndarray
        The estimate [kg m^2].
    sd : ndarray
        Its predictive standard deviation [kg m^2] (:meth:`MassRegression.predictive_sd`
        times the estimate; the mass taken as exact).

    Raises
    ------
    InputError
        A mass that is not finite, or outside the measured masses of the group.
    """
    m = real_array(mass, "mass", "kg")
    low, high = regression.mass_range
    inside = np.isfinite(m) & (m >= low) & (m <= high)
    if not inside.all():
        bad = float(np.ravel(m)[int(np.argmin(np.ravel(inside)))])
        raise InputError(f"mass must lie within the {low:.0f}-{high:.0f} kg of the "
                         f"{regression.count} measured {regression.group}s the mass-only "
                         f"yaw-inertia estimate is fitted on, got {bad:.6g} kg")
    inertia = regression.slope * m + regression.intercept
    return inertia, regression.predictive_sd(m) * inertia


@dataclass(frozen=True)
class WheelbaseLine:
    """The least-squares line L = slope l + intercept of vehicles' wheelbase L on their
    overall length l, with the scatter about it: what stands in for the wheelbase of a
    vehicle whose case gives its length but not its wheelbase.

    Attributes
    ----------
    group : str
        The vehicles it is fitted on (e.g. "car").
    slope : float
        [m / m] = [-].
    intercept : float
        [m].
    r_squared : float
        Share of the wheelbases' variance the line explains [-].
    sd : float
        Sample sd of the residuals, n - 2 degrees of freedom [m].
    count : int
        Number of vehicles, >= 3.
    length_mean : float
        Mean of their lengths [m].
    length_ss : float
        Sum of their lengths' squared deviations from the mean, S_ll [m^2], > 0.
    length_range : tuple of float
        Shortest and longest length [m]: the line is used only between them.
    source : str
        Short citation of the data, for notes and reports.
    """

    group: str
    slope: float
    intercept: float
    r_squared: float
    sd: float
    count: int
    length_mean: float
    length_ss: float
    length_range: tuple
    source: str

    def wheelbase(self, length):
        """The line's wheelbase [m] at overall ``length`` [m]."""
        return self.slope * np.asarray(length, dtype=float) + self.intercept

    def predictive_sd(self, length):
        """Sd of one more vehicle's wheelbase at ``length`` [m] [m]:
        s sqrt(1 + 1/n + (l - mean l)^2 / S_ll)."""
        dl = np.asarray(length, dtype=float) - self.length_mean
        return self.sd * np.sqrt(1.0 + 1.0 / self.count + dl * dl / self.length_ss)


def wheelbase_line(lengths, wheelbases, group: str, source: str) -> WheelbaseLine:
    """The :class:`WheelbaseLine` of vehicles of known overall length and wheelbase.

    Parameters
    ----------
    lengths : array_like
        Their overall lengths l [m], at least 3, not all equal.
    wheelbases : array_like
        Their wheelbases L [m], as many.
    group : str
        What the vehicles are (for messages).
    source : str
        Short citation.
    """
    x = real_array(lengths, f"lengths of {group!r}", "m").ravel()
    y = real_array(wheelbases, f"wheelbases of {group!r}", "m").ravel()
    if x.size != y.size or x.size < 3 or not (np.isfinite(x).all() and np.isfinite(y).all()) \
            or np.ptp(x) == 0:
        raise InputError(f"wheelbase line of {group!r} needs at least 3 finite (length, "
                         f"wheelbase) pairs with different lengths")
    slope, intercept = np.polyfit(x, y, 1)
    residual = y - (slope * x + intercept)
    ss = float(residual @ residual)
    return WheelbaseLine(group=group, slope=float(slope), intercept=float(intercept),
                         r_squared=1.0 - ss / float(((y - y.mean()) ** 2).sum()),
                         sd=math.sqrt(ss / (x.size - 2)), count=int(x.size),
                         length_mean=float(x.mean()),
                         length_ss=float(((x - x.mean()) ** 2).sum()),
                         length_range=(float(x.min()), float(x.max())), source=source)


def yaw_inertia_from_length(mass, length, line: WheelbaseLine, index: DynamicIndex,
                            fraction: AxleFraction):
    """Yaw moment of inertia about the CG from mass and overall length, the wheelbase from
    the length: I_z = D m L^2 f (1 - f), L = slope l + intercept.

    The three factors are independent: the yaw dynamic index D (``index``), f (1 - f) of
    the class's CG position (``fraction``, :meth:`AxleFraction.axle_product`) and L^2, L
    normal about the line's wheelbase ``mu`` with its predictive sd ``s``
    (:class:`WheelbaseLine`), so E[L^2] = mu^2 + s^2 and var L^2 = 4 mu^2 s^2 + 2 s^4. The
    estimate is their product's mean, m E[D] E[f (1 - f)] E[L^2], and its variance that of
    a product of independent factors, m^2 (E[D^2] E[g^2] E[L^4] - (E[D] E[g] E[L^2])^2).

    Parameters
    ----------
    mass : array_like
        Vehicle mass m [kg], > 0.
    length : array_like
        Overall length l [m], within ``line.length_range``.
    line : WheelbaseLine
        The wheelbase line of the vehicle's class (:func:`wheelbase_line`).
    index : DynamicIndex
        The class's yaw dynamic index D.
    fraction : AxleFraction
        The class's CG position f = a / L.

    Returns
    -------
    inertia : ndarray
        The estimate [kg m^2].
    sd : ndarray
        Its standard deviation [kg m^2] (mass and length taken as exact).

    Raises
    ------
    InputError
        A mass not > 0, or a length that is not finite or outside the line's lengths.
    """
    m = real_array(mass, "mass", "kg")
    x = real_array(length, "length", "m")
    if not (np.isfinite(m).all() and (m > 0).all()):
        raise InputError("mass must be finite and > 0 [kg] to estimate the yaw inertia")
    low, high = line.length_range
    if not (np.isfinite(x).all() and ((x >= low) & (x <= high)).all()):
        raise InputError(f"length must lie within the {low:.2f}-{high:.2f} m of the "
                         f"{line.count} {line.group}s of the wheelbase line")
    mu, s = line.wheelbase(x), line.predictive_sd(x)
    square = (mu * mu + s * s, np.sqrt(4 * mu * mu * s * s + 2 * s ** 4))    # L^2
    mean, sd = independent_product((index.mean, index.predictive_sd),
                                   fraction.axle_product(), square)
    return m * mean, m * sd


def independent_product(*factors):
    """Mean and sd of a product of independent factors, each given as (mean, sd):
    ``prod mu_i`` and ``sqrt(prod (mu_i^2 + s_i^2) - prod mu_i^2)`` (exact for any
    distributions with those moments)."""
    mean, second = 1.0, 1.0
    for mu, s in factors:
        mean, second = mean * mu, second * (mu * mu + s * s)
    return mean, np.sqrt(np.maximum(second - mean * mean, 0.0))


@dataclass(frozen=True)
class InputEstimate:
    """Provenance of an input the case file left out and the program estimated.

    Attributes
    ----------
    name : str
        The input's dotted name (a key of :data:`pim.model.quantities.UNCERTAIN`, e.g.
        "vehicle1.yaw_inertia").
    value : float
        The estimate [SI unit of the input].
    sd : float
        Its standard deviation [SI unit of the input], >= 0: the Monte Carlo draws the input
        with it unless the ``[uncertainty]`` table gives the input a distribution.
    method : str
        The equation and its constants in words, without the case's own figures (e.g.
        "D m a b, D = 1.091 the yaw dynamic index of cars (n = 73)").
    source : str
        Short citation of the data behind it (e.g. "Heydinger et al. 1999").
    inputs : tuple of (str, float, str)
        The case's figures it used: (label, value [SI], unit kind of
        :data:`pim.io.units.DIMENSIONS`), shown in the reader's units.
    assumptions : tuple of str
        What it assumed for figures the case does not give (e.g. "a = L/2").
    """

    name: str
    value: float
    sd: float
    method: str
    source: str
    inputs: tuple = ()
    assumptions: tuple = ()

    @property
    def relative_sd(self) -> float:
        """sd over value [-] (0 for a zero value)."""
        return self.sd / abs(self.value) if self.value else 0.0

    @property
    def short(self) -> str:
        """``"estimated, ±7.0 % (1 sd), <source>"``: the tag tables put beside the value."""
        return f"estimated, ±{100 * self.relative_sd:.1f} % (1 sd), {self.source}"
