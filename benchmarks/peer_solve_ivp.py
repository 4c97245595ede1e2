"""The peer: a straightforward event-driven rocking solver with ``scipy.integrate.solve_ivp``.

This is the implementation a researcher would write (and the one murus is benchmarked against):
RK45 with events for the impact (theta = 0), overturning (|theta| = pi/2) and the peaks
(theta' = 0, located on the dense output), restarted after each
impact with the velocity times e; at rest, the record is scanned sample by sample for
``|a_g| > g tan(alpha)`` and the uplift instant interpolated linearly; the ground acceleration is
interpolated with ``numpy.interp``. Same equation and sign convention as murus. Rest rule: the
body is put at rest at once when ``|theta'| < rest_tol p alpha`` after an impact (murus's rule
before issue 15; murus now sums the cascade and puts the body at rest at its accumulation point
when the ground allows). With ``rest_tol = 1e-9`` the difference is below 1e-8 s of rest, and the
peer at rtol 1e-10 is the independent accurate reference of ``validation/rest_rule.py``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp


def rocking_solve_ivp(m, R, alpha, I_O, e, dt, acc, t_end, g=9.81, rtol=1e-8, atol=None,
                      theta0=0.0, omega0=0.0, rest_tol=1e-3):
    """Return ``(theta_max, n_impacts, overturned, uplift_time)``.

    ``acc``: ground acceleration [m/s²] sampled at ``dt`` (zero after its end)."""
    p = math.sqrt(m * g * R / I_O)
    if atol is None:
        atol = [rtol * alpha, rtol * p * alpha]
    tr = np.arange(acc.size) * dt
    t_rec_end = tr[-1]

    def ag(t):
        return float(np.interp(t, tr, acc, left=0.0, right=0.0))

    def rhs_for(s):
        def rhs(t, y):
            x = s * alpha - y[0]
            return [y[1], (-m * g * R * math.sin(x) + m * ag(t) * R * math.cos(x)) / I_O]

        return rhs

    def impact(t, y):
        return y[0]

    impact.terminal = True

    def over(t, y):
        return abs(y[0]) - 0.5 * math.pi

    over.terminal = True
    over.direction = 1

    def peak(t, y):
        return y[1]

    thr = g * math.tan(alpha)
    t = 0.0
    theta_max = abs(theta0)
    n_imp = 0
    uplift = None
    if theta0 != 0.0 or omega0 != 0.0:
        s = 1.0 if (theta0 > 0 or (theta0 == 0 and omega0 > 0)) else -1.0
        y = [theta0, omega0]
        uplift = 0.0
    else:
        s = 0.0
        y = [0.0, 0.0]
    k = 0
    while t < t_end:
        if s == 0.0:
            # scan the record for the uplift
            k = max(k, int(math.floor(t / dt)))
            found = False
            a_now = ag(t)
            if abs(a_now) > thr:  # the ground lifts the body right away
                found = True
                s = 1.0 if a_now > 0 else -1.0
            while not found and k < acc.size - 1 and k * dt < t_end:
                a0, a1 = acc[k], acc[k + 1]
                for sgn in (1.0, -1.0):
                    if sgn * a1 > thr and sgn * a0 <= thr:
                        tu = k * dt + dt * (thr - sgn * a0) / (sgn * a1 - sgn * a0)
                        if tu >= t:
                            found = True
                            s = sgn
                            t = tu
                            break
                    elif sgn * a0 > thr and k * dt >= t:
                        found = True
                        s = sgn
                        t = max(t, k * dt)
                        break
                if found:
                    break
                k += 1
            if not found:
                break
            if uplift is None:
                uplift = t
            y = [0.0, 0.0]
        impact.direction = -s
        sol = solve_ivp(rhs_for(s), (t, t_end), y, method="RK45", rtol=rtol, atol=atol,
                        events=(impact, over, peak), dense_output=False,
                        max_step=max(dt, 1e-3) if t < t_rec_end else np.inf)
        if sol.y.size:
            theta_max = max(theta_max, float(np.max(np.abs(sol.y[0]))))
        if sol.t_events[2].size:
            theta_max = max(theta_max, float(np.max(np.abs(sol.y_events[2][:, 0]))))
        if sol.status == 1 and sol.t_events[1].size:
            return 0.5 * math.pi, n_imp, True, uplift
        if sol.status == 1 and sol.t_events[0].size:
            t = float(sol.t_events[0][0])
            w = float(sol.y_events[0][0][1]) * e
            n_imp += 1
            if abs(w) < rest_tol * p * alpha:
                s = 0.0
                y = [0.0, 0.0]
            else:
                s = -s
                y = [0.0, w]
            continue
        break
    return theta_max, n_imp, False, uplift
