"""Principal direction of force (PDOF) and its clock position (SAE J224 convention)."""

from __future__ import annotations

from functools import cached_property

import numpy as np

__all__ = ["pdof", "clock_position", "wrap_angle", "DirectionOutputs"]


def wrap_angle(angle: np.ndarray) -> np.ndarray:
    """Wrap angles [rad] into (-pi, pi]."""
    return np.pi - np.mod(np.pi - angle, 2 * np.pi)


def pdof(impulse: np.ndarray, heading: np.ndarray) -> np.ndarray:
    """Principal direction of force [rad] of an impulse on a vehicle.

    The direction from which the impulse comes (that of -P), measured from the vehicle's
    heading clockwise, as in SAE J224's clock convention: 0 = from straight ahead (frontal),
    +pi/2 = from the right side, -pi/2 = from the left, pi = from behind. Wrapped to (-pi, pi].
    NaN where there is no impulse (no impact; see ``Result.approaching``).
    """
    came_from = np.arctan2(-impulse[..., 1], -impulse[..., 0])
    none = (impulse[..., 0] == 0) & (impulse[..., 1] == 0)
    return np.where(none, np.nan, wrap_angle(heading - came_from))


def clock_position(pdof: np.ndarray) -> np.ndarray:
    """Clock position (1..12, 12 = frontal) of a PDOF [rad], nearest hour; 0 where PDOF is NaN."""
    hours = np.mod(np.rint(np.nan_to_num(np.degrees(pdof)) / 30.0), 12)
    return np.where(np.isnan(pdof), 0, np.where(hours == 0, 12, hours)).astype(int)


class DirectionOutputs:
    """A mixin of :class:`pim.Result`: direction of the impulse, PDOF and clock positions."""

    @cached_property
    def impulse_angle(self) -> np.ndarray:
        """Direction of the impulse on vehicle 1 from +x [rad]."""
        return np.arctan2(self.impulse[..., 1], self.impulse[..., 0])

    @cached_property
    def pdof1(self) -> np.ndarray:
        """PDOF of vehicle 1 [rad], clockwise from its heading; 0 = frontal (see pdof)."""
        return pdof(self.impulse, self.case.vehicle1.heading)

    @cached_property
    def pdof2(self) -> np.ndarray:
        """PDOF of vehicle 2 [rad], clockwise from its heading; 0 = frontal."""
        return pdof(-self.impulse, self.case.vehicle2.heading)

    @cached_property
    def clock1(self) -> np.ndarray:
        """PDOF of vehicle 1 as a clock position, 12 = frontal, 3 = right side."""
        return clock_position(self.pdof1)

    @cached_property
    def clock2(self) -> np.ndarray:
        """PDOF of vehicle 2 as a clock position, 12 = frontal, 3 = right side."""
        return clock_position(self.pdof2)
