"""Crush energy from residual crush profiles (Campbell / CRASH3) and the crush-energy delta-V.

A damaged side is measured as n >= 2 crush depths C1..Cn equally spaced over the damage width
L. With Campbell's linear force-crush law per unit width, F/w = A + B C, the energy absorbed
per unit width at crush C is A C + B C^2 / 2 + G, G = A^2 / (2 B) (the energy below the
no-damage threshold), and the crush energy is its integral over the width (CRASH3 User's
Guide and Technical Manual, NHTSA DOT-HS-805-732, 1981; McHenry, "The Algorithms of CRASH",
SECCC 2001).

Conventions (body frame of the damaged vehicle: x forward, y left, origin at the CG):

* ``side``: "front", "rear", "left" or "right"; :attr:`CrushProfile.normal_body` is the
  outward unit normal of that side ((1, 0), (-1, 0), (0, 1), (0, -1)).
* ``offset``: the signed position of the damage centre along the side, from the CG's
  projection onto the side: along +y (left) for the front and rear, along +x (forward) for the
  left and right sides. It places the centroid of the damage for the PDOF's moment arm.
* Depths C1..Cn run along the side in the direction of increasing offset coordinate; the
  energy does not depend on the direction (a reversed profile absorbs the same energy).

Everything is SI inside: A [N/m], B [N/m^2], G [N], depths and width [m], energies [J].
The functions are pure and vectorised; :func:`crush_energy` and
:func:`force_balance_factor` use only +, -, *, / and abs, so they also run on
:class:`pim.model.dual.Dual` numbers (exact derivatives for the fit).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .dual import Dual, cos_sin, hypot
from .dual import sqrt as sqrt_of  # re-exported: the square root on duals lives in dual
from .numbers import InputError, unit_text

__all__ = ["CrushProfile", "SIDES", "SIDE_NORMALS", "crush_energy", "force_balance_factor",
           "FORCE_BALANCE_CAP", "equivalent_energy_speed", "effective_mass", "moment_arm",
           "crush_impulse", "crush_delta_v", "PARTITIONS", "CrushComparison",
           "compared_energy", "sqrt_of"]

#: The damaged sides a profile can be measured on, and their outward unit normals in the
#: body frame (x forward, y left).
SIDE_NORMALS = {"front": (1.0, 0.0), "rear": (-1.0, 0.0), "left": (0.0, 1.0),
                "right": (0.0, -1.0)}
SIDES = tuple(SIDE_NORMALS)

#: CRASH3's cap on the force-balance (tangential) correction factor 1 + tan^2(alpha): the
#: correction is applied for |alpha| up to 45 degrees, so the factor is at most 2 (CRASH3
#: User's Guide and Technical Manual, DOT-HS-805-732; McHenry Software, "CRASH3 correction
#: factor (1 + tan^2 alpha)", mchenrysoftware.com forum: "The limitation of 2 is for the
#: correction factor based on Alpha").
FORCE_BALANCE_CAP = 2.0

#: Added to numerator and denominator of the force-balance factor so that a zero impulse
#: gives 1 instead of 0/0; far below any impulse^2 of a collision (1 N s)^2.
_TINY = 1e-300


def crush_energy(width, depths, stiffness_a, stiffness_b, stiffness_g=None):
    """Crush energy of a profile of n equally spaced depths [J] (CRASH3).

    The depths are joined by straight lines (the profile is piecewise linear between the
    measuring stations, as CRASH3 assumes), and the energy per unit width
    A C + B C^2 / 2 + G is integrated exactly over each of the n - 1 segments of length
    d = L / (n - 1):

        E = d sum_i [ A (C_i + C_i+1) / 2 + B (C_i^2 + C_i C_i+1 + C_i+1^2) / 6 + G ]

    This is the CRASH3 closed form (CRASH3 Technical Manual eq. 2.48 for six stations,
    E = L/5 [A/2 (C1 + 2 C2 + 2 C3 + 2 C4 + 2 C5 + C6) + B/6 (C1^2 + 2 C2^2 + ... + C6^2
    + C1 C2 + C2 C3 + C3 C4 + C4 C5 + C5 C6) + 5 G], and its 2- and 4-point forms) for any
    n; the trapezoid rule applied to the energy per width instead would add
    B d sum (C_i+1 - C_i)^2 / 12, exact only for a uniform profile.

    Parameters
    ----------
    width : array_like or Dual
        Damage width L [m].
    depths : sequence of array_like or Dual
        The n >= 2 crush depths C1..Cn [m]: a list, or an array whose FIRST axis runs over the
        stations (further axes broadcast, e.g. Monte Carlo samples).
    stiffness_a, stiffness_b : array_like or Dual
        Campbell's coefficients per unit width, A [N/m] and B [N/m^2].
    stiffness_g : array_like or Dual, optional
        G [N]; by default A^2 / (2 B) (zero energy at zero residual crush).

    Returns
    -------
    ndarray or Dual
        Crush energy [J], without the force-balance correction.
    """
    points = list(depths)
    n = len(points)
    if n < 2:
        raise InputError(f"crush depths: {n} given, at least 2 are needed")
    a, b = stiffness_a, stiffness_b
    g = a * a / (2.0 * b) if stiffness_g is None else stiffness_g
    linear, square = 0.0, 0.0
    for c0, c1 in zip(points[:-1], points[1:], strict=True):
        linear = linear + (c0 + c1) * 0.5
        square = square + (c0 * c0 + c0 * c1 + c1 * c1) / 6.0
    spacing = width / (n - 1.0)
    return spacing * (a * linear + b * square) + width * g


def force_balance_factor(impulse_x, impulse_y, normal_x, normal_y, cap=FORCE_BALANCE_CAP):
    """CRASH3's force-balance (tangential) correction factor 1 + tan^2(alpha), capped.

    alpha is the angle between the line of action of the impulse and the normal of the
    damaged side; the crush energy measured along the normal is divided by cos^2(alpha) to
    give the energy of the whole impulse (CRASH3 Technical Manual). Written as
    |P|^2 / max((P . n)^2, |P|^2 / cap) with max(a, b) = (a + b + |a - b|) / 2, i.e. with
    +, -, *, / and abs only, so it runs on :class:`pim.model.dual.Dual` numbers; the sign of
    P does not matter (the line of action), and a zero impulse gives 1.

    Parameters
    ----------
    impulse_x, impulse_y : array_like or Dual
        The impulse (or the PDOF, any length) [N s], in any frame.
    normal_x, normal_y : array_like or Dual
        The outward unit normal of the damaged side in the same frame.
    cap : float
        Largest factor (>= 1); :data:`FORCE_BALANCE_CAP` = 2 is CRASH3's (alpha <= 45 deg).

    Returns
    -------
    ndarray or Dual
        The factor, within [1, cap].
    """
    if not isinstance(cap, Dual) and not float(np.min(cap)) >= 1.0:
        raise InputError(f"force-balance cap = {cap!r} must be at least 1 (CRASH3: 2)")
    p2 = impulse_x * impulse_x + impulse_y * impulse_y
    along = impulse_x * normal_x + impulse_y * normal_y
    d2 = along * along
    floor = p2 / cap
    larger = (d2 + floor + abs(d2 - floor)) * 0.5
    return (p2 + _TINY) / (larger + _TINY)


def equivalent_energy_speed(energy, mass):
    """Equivalent energy speed EES = sqrt(2 E / m) [m/s] of a crush energy.

    Parameters
    ----------
    energy : array_like or Dual
        Crush energy [J] (>= 0).
    mass : array_like or Dual
        The vehicle's mass [kg].
    """
    return sqrt_of(2.0 * energy / mass)


def moment_arm(point_x, point_y, direction_x, direction_y):
    """Moment arm h [m] of a line of action about the CG: |r x p| / |p|.

    Parameters
    ----------
    point_x, point_y : array_like
        A point of the line (the damage centroid) relative to the CG [m].
    direction_x, direction_y : array_like
        The line's direction (the PDOF or impulse), any length, same frame.
    """
    cross = point_x * direction_y - point_y * direction_x
    return abs(cross) / hypot(direction_x, direction_y)


def effective_mass(mass, yaw_inertia, arm):
    """CRASH3's effective mass gamma m, gamma = k^2 / (k^2 + h^2) [kg].

    k^2 = I / m is the squared yaw radius of gyration and h the moment arm of the PDOF about
    the CG (:func:`moment_arm`); gamma m = m I / (I + m h^2) is the mass a point on the line
    of action feels (CRASH3 Technical Manual; McHenry, "The Algorithms of CRASH").
    """
    return mass * yaw_inertia / (yaw_inertia + mass * arm * arm)


def crush_impulse(total_energy, mass1, mass2, restitution=0.0, energy_is="absorbed"):
    """Impulse magnitude [N s] implied by the total crush energy of both vehicles.

    With the effective masses M_i (:func:`effective_mass`; the masses themselves for a
    central impact) and M = M1 M2 / (M1 + M2), a collision of closing speed v_c along the
    PDOF with restitution e has the impulse P = (1 + e) M v_c. Two readings of the crush
    energy E_T (Ziernicki & Rose, SAE 2005-01-1200):

    * ``"absorbed"`` (default): the energy at maximum engagement, E_T = M v_c^2 / 2, which
      is what stiffness coefficients fitted to barrier impact speeds return (Rose, Fenton &
      Beauchamp, SAE 2006-01-0908); P = (1 + e) sqrt(2 M E_T).
    * ``"dissipated"``: the kinetic energy lost, E_T = M v_c^2 (1 - e^2) / 2;
      P = sqrt(2 M E_T (1 + e) / (1 - e)).

    With e = 0 both are CRASH3's P = sqrt(2 M E_T).

    Parameters
    ----------
    total_energy : array_like or Dual
        E1 + E2 [J], each with its force-balance factor.
    mass1, mass2 : array_like or Dual
        Effective masses [kg].
    restitution : array_like or Dual
        e, in [0, 1) (1 excluded for "dissipated").
    energy_is : {"absorbed", "dissipated"}
    """
    reduced = mass1 * mass2 / (mass1 + mass2)
    if energy_is == "absorbed":
        return (1.0 + restitution) * sqrt_of(2.0 * reduced * total_energy)
    if energy_is == "dissipated":
        return sqrt_of(2.0 * reduced * total_energy * (1.0 + restitution)
                       / (1.0 - restitution))
    raise InputError(f"energy_is = {energy_is!r} must be 'absorbed' or 'dissipated'")


def crush_delta_v(total_energy, mass1, mass2, restitution=0.0, energy_is="absorbed",
                  gamma1=1.0, gamma2=1.0):
    """Crush-energy delta-V of both vehicles' centres of mass [m/s] (CRASH3; Rose et al.).

    delta-V_i = P / m_i with P from :func:`crush_impulse` on the effective masses
    gamma_i m_i. For e = 0 and gamma = 1 this is CRASH3's
    delta-V_1 = sqrt(2 E_T m2 / (m1 (m1 + m2))); with restitution (absorbed energy) it is
    (1 + e) times that (Rose, Fenton & Beauchamp, SAE 2006-01-0908). The speed change of the
    damage centroid along the PDOF is delta-V_i / gamma_i.

    Parameters
    ----------
    total_energy : array_like or Dual
        E1 + E2 [J] (force-balance corrected).
    mass1, mass2 : array_like or Dual
        The vehicles' masses [kg].
    restitution, energy_is
        As in :func:`crush_impulse`.
    gamma1, gamma2 : array_like or Dual
        Effective-mass factors k^2 / (k^2 + h^2) (1: central impact).

    Returns
    -------
    (delta_v1, delta_v2)
        Magnitudes [m/s].
    """
    impulse = crush_impulse(total_energy, gamma1 * mass1, gamma2 * mass2, restitution,
                            energy_is)
    return impulse / mass1, impulse / mass2


@dataclass(frozen=True)
class CrushComparison:
    """Which PIM energy a measured crush energy is compared with.

    Attributes
    ----------
    partition : str
        Its name in the case file ("total" or "normal").
    attribute : str
        The energy of a :class:`pim.Result` [J] that the sum of both vehicles' crush
        energies is compared with.
    force_balance : bool
        Whether each vehicle's crush energy is first multiplied by
        :func:`force_balance_factor`.
    description : str
        The rule and its source, for reports.
    """

    partition: str
    attribute: str
    force_balance: bool
    description: str


#: The comparisons a case file may ask for (``partition = "..."``).
PARTITIONS = {
    "total": CrushComparison(
        "total", "energy_loss", True,
        "CRASH3: the crush energies, each times 1 + tan^2(alpha), sum to the total kinetic "
        "energy loss T_L"),
    "normal": CrushComparison(
        "normal", "crush_energy_normal", False,
        "Brach & Welsh (SAE 2007-01-0737): the residual crush energy is the work of the "
        "normal impulse component, -Pn (u_n + U_n) / 2; the tangential loss (sliding, "
        "snagging) is PIM's own and no tangential correction factor is applied"),
}


def compared_energy(partition: str = "total") -> CrushComparison:
    """The PIM energy the measured crush energy is compared with, for ``partition``.

    "total" (CRASH3 practice): E1 (1 + tan^2 alpha1) + E2 (1 + tan^2 alpha2) = T_L
    (:attr:`pim.Result.energy_loss`). "normal" (Brach & Welsh, SAE 2007-01-0737,
    "Residual crush energy partitioning, normal and tangential energy losses": the work of
    the normal and tangential components of the impulse are individually associated with the
    crush energy and with the tangential energy loss): E1 + E2 = the normal crush energy
    (:attr:`pim.Result.crush_energy_normal`), without a correction factor.

    Both PIM energies are *dissipated* energies. Stiffness coefficients fitted to barrier
    impact speeds give the *absorbed* energy at maximum crush, which for a restitution e
    exceeds the normal loss by 1 / (1 - e^2) (Ziernicki & Rose, SAE 2005-01-1200); a caller
    with e > 0 may compare (1 - e^2) times the crush energy (see :func:`crush_impulse`).

    Raises
    ------
    InputError
        An unknown partition (the message lists the known ones).
    """
    if partition not in PARTITIONS:
        raise InputError(f"crush partition = {partition!r} is not known "
                         f"(allowed: {', '.join(PARTITIONS)})")
    return PARTITIONS[partition]


def _check_positive(value, name: str, unit: str, allow_zero: bool = False) -> float:
    number = float(value)
    if not np.isfinite(number) or number < 0 or (number == 0 and not allow_zero):
        relation = ">= 0" if allow_zero else "> 0"
        shown = unit_text(number, "length", "g") if unit == "m" else f"{number:g} {unit}"
        raise InputError(f"{name} = {shown} must be finite and {relation}")
    return number


@dataclass(frozen=True)
class CrushProfile:
    """A measured crush profile of one vehicle with its stiffness (SI).

    Parameters
    ----------
    side : str
        "front", "rear", "left" or "right" (:data:`SIDES`).
    width : float
        Damage width L [m] (> 0).
    depths : tuple of float
        Crush depths C1..Cn [m] (n >= 2, each >= 0), equally spaced over the width.
    stiffness_a : float
        A [N/m] per unit width (> 0).
    stiffness_b : float
        B [N/m^2] per unit width (> 0).
    offset : float
        Signed position of the damage centre along the side [m] (see the module notes).
    stiffness_g : float or None
        G [N]; None: A^2 / (2 B).
    depth_sigma, width_sigma, stiffness_a_sigma, stiffness_b_sigma : float
        Standard deviations [m, m, N/m, N/m^2] of each depth (independent), the width, A and
        B (A and B taken independent).
    energy_sigma_relative : float
        A further relative standard deviation of the energy [-] (e.g. a class default's
        scatter), added in quadrature.
    where : str
        The case-file table, for messages (``evidence.vehicle1.crush``).
    """

    side: str
    width: float
    depths: tuple
    stiffness_a: float
    stiffness_b: float
    offset: float = 0.0
    stiffness_g: float | None = None
    depth_sigma: float = 0.0
    width_sigma: float = 0.0
    stiffness_a_sigma: float = 0.0
    stiffness_b_sigma: float = 0.0
    energy_sigma_relative: float = 0.0
    where: str = field(default="crush", compare=False)

    def __post_init__(self) -> None:
        w = self.where
        if self.side not in SIDE_NORMALS:
            raise InputError(f"{w}.side = {self.side!r} is not a side "
                             f"(allowed: {', '.join(SIDES)})")
        depths = tuple(float(c) for c in self.depths)
        if len(depths) < 2:
            raise InputError(f"{w}.depths: {len(depths)} depth given; at least 2 are needed "
                             f"(C1..Cn equally spaced over the damage width)")
        for i, c in enumerate(depths):
            if not np.isfinite(c) or c < 0:
                raise InputError(f"{w}.depths[{i}] = {unit_text(c, 'length', 'g')}: a crush "
                                 f"depth must be finite and >= 0")
        object.__setattr__(self, "depths", depths)
        _check_positive(self.width, f"{w}.width", "m")
        _check_positive(self.stiffness_a, f"{w}.stiffness_a", "N/m")
        _check_positive(self.stiffness_b, f"{w}.stiffness_b", "N/m^2")
        if self.stiffness_g is not None:
            _check_positive(self.stiffness_g, f"{w}.stiffness_g", "N", allow_zero=True)
        if not np.isfinite(float(self.offset)):
            raise InputError(f"{w}.offset = {self.offset!r} must be finite")
        for name, unit in (("depth_sigma", "m"), ("width_sigma", "m"),
                           ("stiffness_a_sigma", "N/m"), ("stiffness_b_sigma", "N/m^2"),
                           ("energy_sigma_relative", "-")):
            _check_positive(getattr(self, name), f"{w}.{name}", unit, allow_zero=True)

    @property
    def normal_body(self) -> np.ndarray:
        """Outward unit normal of the damaged side in the body frame (x forward, y left)."""
        return np.array(SIDE_NORMALS[self.side])

    def normal(self, heading):
        """Outward unit normal of the damaged side in the global frame, (n_x, n_y), for the
        vehicle's heading [rad] (number, array or :class:`Dual`): the body normal rotated
        by the heading (CCW from +x)."""
        c, s = cos_sin(heading)
        nx, ny = SIDE_NORMALS[self.side]
        return c * nx - s * ny, s * nx + c * ny

    def corrected_energy(self, impulse_x, impulse_y, heading, cap=FORCE_BALANCE_CAP):
        """Crush energy times the force-balance factor of the impulse [J] (CRASH3), the
        impulse in the global frame [N s] and the vehicle's heading [rad]; numbers, arrays
        or :class:`Dual` (the sign of the impulse does not matter)."""
        nx, ny = self.normal(heading)
        return self.energy * force_balance_factor(impulse_x, impulse_y, nx, ny, cap)

    @property
    def centroid_body(self) -> np.ndarray:
        """The damage centre on the undeformed side, relative to the CG along the side, as a
        body-frame vector without the side's distance from the CG: (0, offset) for the front
        and rear, (offset, 0) for the left and right [m]."""
        nx, _ = SIDE_NORMALS[self.side]
        return np.array([0.0, self.offset]) if nx else np.array([self.offset, 0.0])

    @property
    def energy(self) -> float:
        """Crush energy [J] without the force-balance factor (:func:`crush_energy`)."""
        return float(crush_energy(self.width, self.depths, self.stiffness_a,
                                  self.stiffness_b, self.stiffness_g))

    def _gradient(self) -> np.ndarray:
        """dE/d(C1..Cn, L, A, B) [J per SI unit], exact (forward-mode duals)."""
        n = len(self.depths)
        k = n + 3
        eye = np.eye(k)
        depths = [Dual(c, eye[i]) for i, c in enumerate(self.depths)]
        width = Dual(self.width, eye[n])
        a, b = Dual(self.stiffness_a, eye[n + 1]), Dual(self.stiffness_b, eye[n + 2])
        g = None if self.stiffness_g is None else self.stiffness_g
        return crush_energy(width, depths, a, b, g).grad

    @property
    def energy_sigma(self) -> float:
        """Standard deviation of :attr:`energy` [J], first-order propagation.

        sigma_E^2 = sum_i (dE/dC_i)^2 sigma_C^2 + (dE/dL sigma_L)^2 + (dE/dA sigma_A)^2
        + (dE/dB sigma_B)^2 + (E sigma_rel)^2, all inputs independent; with G = A^2/(2B)
        its dependence on A and B is included in dE/dA and dE/dB.
        """
        grad = self._gradient()
        n = len(self.depths)
        sigmas = np.array([self.depth_sigma] * n + [self.width_sigma, self.stiffness_a_sigma,
                                                    self.stiffness_b_sigma])
        variance = float(np.sum((grad * sigmas) ** 2))
        variance += (self.energy * self.energy_sigma_relative) ** 2
        return float(np.sqrt(variance))

    def sample_energy(self, rng: np.random.Generator, size: int) -> np.ndarray:
        """``size`` crush energies [J] drawn from the inputs' normal distributions (depths
        clipped at 0; width, A and B at a small positive floor), times a normal factor
        1 + energy_sigma_relative N(0, 1), for the Monte Carlo."""
        n = len(self.depths)
        depths = np.maximum(np.asarray(self.depths)[:, None]
                            + self.depth_sigma * rng.standard_normal((n, size)), 0.0)
        width = np.maximum(self.width + self.width_sigma * rng.standard_normal(size),
                           1e-3 * self.width)
        a = np.maximum(self.stiffness_a + self.stiffness_a_sigma * rng.standard_normal(size),
                       1e-3 * self.stiffness_a)
        b = np.maximum(self.stiffness_b + self.stiffness_b_sigma * rng.standard_normal(size),
                       1e-3 * self.stiffness_b)
        energy = crush_energy(width, depths, a, b, self.stiffness_g)
        factor = 1.0 + self.energy_sigma_relative * rng.standard_normal(size)
        return energy * np.maximum(factor, 0.0)
