"""An independent reference: Brach's scalar PIM equations (n-t form) in exact rational arithmetic.

Written from Brach & Brach (2011) eqs. 6.45-6.60 as the design sheet states them, with the
sign-consistent arms of ricsac9.md (C - CG1 = -(d_d, d_c), C - CG2 = (d_b, d_a)), for
Gamma = 0 (n = +x, t = +y), so every operation is exact on fractions.Fraction. It shares no
code and no formulation with pim.solver (which solves a 2x2 effective-mass system in vector
form), and has no round-off: a test against it measures the solver's own error.
"""

from fractions import Fraction as F


def brach_exact(m1, I1, g1, v1, w1, m2, I2, g2, v2, w2, c, eps, beta):
    """Post-impact state for Gamma = 0. Vectors are (x, y) pairs; m2 = I2 = None: fixed."""
    m1, I1, eps, beta, w1 = F(m1), F(I1), F(eps), F(beta), F(w1)
    fixed = m2 is None
    inv_m2 = F(0) if fixed else 1 / F(m2)
    inv_i2 = F(0) if fixed else 1 / F(I2)
    w2 = F(w2)
    c = [F(x) for x in c]
    g1, g2 = [F(x) for x in g1], [F(x) for x in g2]
    v1, v2 = [F(x) for x in v1], [F(x) for x in v2]
    d_d, d_c = -(c[0] - g1[0]), -(c[1] - g1[1])
    d_b, d_a = c[0] - g2[0], c[1] - g2[1]
    mc = 1 / (1 / m1 + inv_m2)
    # Velocities of C (eq. 6.45) and relative approach velocities (positive on approach).
    vcn1, vct1 = v1[0] + d_c * w1, v1[1] - d_d * w1
    vcn2, vct2 = v2[0] - d_a * w2, v2[1] + d_b * w2
    v_rn, v_rt = vcn2 - vcn1, vct2 - vct1
    a = 1 + mc * d_c ** 2 / I1 + mc * d_a ** 2 * inv_i2                  # eq. 6.46
    b = mc * d_c * d_d / I1 + mc * d_a * d_b * inv_i2
    cc = mc * d_d ** 2 / I1 + mc * d_b ** 2 * inv_i2
    r = v_rt / v_rn                                                       # eq. 6.60
    mu0 = (r * a + (1 + eps) * b) / ((1 + eps) * (1 + cc) + r * b)
    mu = beta * mu0
    q = 1 / (a - mu * b)                                                  # eq. 6.55
    pn = mc * (1 + eps) * v_rn * q
    pt = mu * pn
    out = {
        "velocity1": (v1[0] + pn / m1, v1[1] + pt / m1),
        "velocity2": (v2[0] - pn * inv_m2, v2[1] - pt * inv_m2),
        "yaw_rate1": w1 + pn * (d_c - mu * d_d) / I1,                     # eqs. 6.52-6.53
        "yaw_rate2": w2 + pn * (d_a - mu * d_b) * inv_i2,
        "impulse": (pn, pt), "mu0": mu0, "q": q, "A": a, "B": b, "C": cc,
    }
    return out
