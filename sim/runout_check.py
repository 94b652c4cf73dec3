"""pymunk check of the run-out model: pymunk integrates the rigid body, the tyre force law
of :mod:`pim.model.tyres` is applied at the CG (force and yaw moment) every step.

This checks :func:`pim.model.runout.runout`'s equations of motion and integration with an
independent integrator (Chipmunk's semi-implicit Euler); the force law itself is the one
under test in tests/pim/model/test_tyres.py against closed forms. A vehicle on the field tyre
or with
driver tables gets the same forces as the run-out: its one right-hand side
(:class:`pim.model.runout.TimedRhs`: either tyre law, load transfer, inputs at pymunk's time).
"""

from __future__ import annotations

import numpy as np
import pymunk

from pim.model.runout import MAX_TIME, Runout, RunoutVehicle, TimedRhs

__all__ = ["pymunk_runout"]


def pymunk_runout(vehicle: RunoutVehicle, position, heading, velocity, yaw_rate, *,
                  dt=2e-4, max_time=MAX_TIME, stop_speed=None) -> Runout:
    """The run-out of one vehicle integrated by pymunk (same state, same stop rule).

    Parameters are those of :func:`pim.model.runout.runout`; ``dt`` [s] is pymunk's step
    (its first-order integrator needs a small one: positions err by about v dt).
    """
    stop_speed = vehicle.regularisation / 5 if stop_speed is None else stop_speed
    positions = vehicle.positions
    reach = float(np.max(np.hypot(positions[:, 0], positions[:, 1])))
    space = pymunk.Space()
    space.gravity = (0.0, 0.0)
    body = pymunk.Body(float(vehicle.mass), float(vehicle.yaw_inertia))
    body.position = tuple(map(float, position))
    body.angle = float(heading)
    body.velocity = tuple(map(float, velocity))
    body.angular_velocity = float(yaw_rate)
    space.add(body)
    times, states = [], []
    rhs = TimedRhs(vehicle)

    def forces_at(t, v):
        rate = rhs(t, [0.0, 0.0, body.angle, v[0], v[1], body.angular_velocity])
        return vehicle.mass * rate[3:5], vehicle.yaw_inertia * rate[5]

    def record(t):
        times.append(t)
        states.append([body.position.x, body.position.y, body.angle, body.velocity.x,
                       body.velocity.y, body.angular_velocity])

    t = 0.0
    record(t)
    stopped = False
    while t < max_time:
        v = np.array(body.velocity)
        if np.hypot(*v) + abs(body.angular_velocity) * reach < stop_speed:
            stopped = True
            break
        force, moment = forces_at(t, v)
        body.force = tuple(map(float, force))
        body.torque = float(moment)
        space.step(dt)
        t += dt
        record(t)
    states = np.array(states)
    return Runout(np.array(times), states, states[-1, :2].copy(), float(states[-1, 2]),
                  float(t), stopped)
