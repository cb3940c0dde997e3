"""SciPy solve_ivp on S5 (forced Coulomb stick-slip) and S6 (Coulomb free decay), theory §4-5.
Event-driven stick/slip mode switching (as a SciPy user would write it) for several
tolerances, and tanh-regularised friction with Radau for a sweep of epsilon.
Usage: scipy_bench.py OUT_JSON"""
import json
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

S5 = dict(f=0.5, force=lambda t: 1.2 * np.sin(0.5 * t), x0=0.25, t_end=30.0)
S6 = dict(f=0.1, force=lambda t: 0.0 * t, x0=1.0, t_end=30.0)


def stick_or_slip(force, x, f):
    """Mode at rest: 0 = stick, +1/-1 = slip in that direction (m = k = 1)."""
    need = force - x
    return 0 if abs(need) <= f else int(np.sign(need))


def event_driven(sc, rtol, atol, method, stick_max_step=0.1):
    """stick_max_step=inf reproduces the naive version: with a zero right-hand side the step
    grows without bound and the release event can be stepped over."""
    f, F, t, x, v = sc["f"], sc["force"], 0.0, sc["x0"], 0.0
    t_end = sc["t_end"]
    mode = stick_or_slip(F(0.0), x, f)
    turns, nfev = [], 0
    while t < t_end:
        if mode == 0:
            xs = x

            def up(t, y):
                return F(t) - xs - f
            up.terminal, up.direction = True, 1

            def down(t, y):
                return F(t) - xs + f
            down.terminal, down.direction = True, -1
            sol = solve_ivp(lambda t, y: [0.0, 0.0], (t, t_end), [x, 0.0], method=method,
                            rtol=rtol, atol=atol, events=[up, down], max_step=stick_max_step)
            nfev += sol.nfev
            if sol.status == 1:
                t = sol.t[-1]
                mode = 1 if sol.t_events[0].size else -1
            else:
                t = t_end
        else:
            s = mode

            def rhs(t, y):
                return [y[1], F(t) - y[0] - s * f]

            def stop(t, y):
                return y[1]
            stop.terminal, stop.direction = True, -s
            sol = solve_ivp(rhs, (t, t_end), [x, v], method=method, rtol=rtol, atol=atol, events=[stop])
            nfev += sol.nfev
            t, x, v = sol.t[-1], sol.y[0, -1], sol.y[1, -1]
            if sol.status == 1:
                t, x = sol.t_events[0][0], sol.y_events[0][0][0]
                v = 0.0
                turns.append((t, x))
                mode = stick_or_slip(F(t), x, f)
    return {"x_end": x, "v_end": v, "turns": turns, "nfev": nfev}


def regularised(sc, eps, rtol, atol, method, t_eval):
    f, F = sc["f"], sc["force"]

    def rhs(t, y):
        return [y[1], F(t) - y[0] - f * np.tanh(y[1] / eps)]
    sol = solve_ivp(rhs, (0.0, sc["t_end"]), [sc["x0"], 0.0], method=method, rtol=rtol, atol=atol,
                    t_eval=t_eval, dense_output=False)
    return sol


def s5_reference():
    """Piecewise closed form for S5: in slip (sign s) x = -s f + 1.6 sin(t/2) + A cos t + B sin t;
    switch times by root bracketing on the analytic expressions (round-off level)."""
    f, t_end = 0.5, 30.0
    F = S5["force"]
    t, x, v = 0.0, 0.25, 0.0
    mode = stick_or_slip(F(0.0), x, f)
    switches = []

    def first_root(g, t0, t1, h=1e-3):
        """First crossing of g from > 0 to <= 0 after t0 (grid h, then Brent)."""
        a, ga = t0, g(t0)
        while a < t1:
            b = min(a + h, t1)
            gb = g(b)
            if ga > 0 and gb <= 0:
                return brentq(g, a, b, xtol=1e-15, rtol=1e-15, maxiter=200)
            a, ga = b, gb
        return None

    while True:
        if mode == 0:
            xs = x
            ts = first_root(lambda s: f - abs(F(s) - xs), t, t_end)
            if ts is None:
                return {"x_end": xs, "v_end": 0.0, "switches": switches}
            t, mode = ts, int(np.sign(F(ts) - xs))
            switches.append(t)
        else:
            s = mode
            # x = c + 1.6 sin(t/2) + A cos t + B sin t with x(t0) = x, v(t0) = v
            c = -s * f
            c0, s0 = np.cos(t), np.sin(t)
            r1 = x - c - 1.6 * np.sin(0.5 * t)
            r2 = v - 0.8 * np.cos(0.5 * t)
            A, B = r1 * c0 - r2 * s0, r1 * s0 + r2 * c0
            pos = lambda u: c + 1.6 * np.sin(0.5 * u) + A * np.cos(u) + B * np.sin(u)
            vel = lambda u: 0.8 * np.cos(0.5 * u) - A * np.sin(u) + B * np.cos(u)
            # first zero of the velocity after it has had the slip direction's sign
            tz = first_root(lambda u: s * vel(u), t, t_end)
            if tz is None:
                return {"x_end": pos(t_end), "v_end": vel(t_end), "switches": switches}
            t, x, v = tz, pos(tz), 0.0
            switches.append(t)
            mode = stick_or_slip(F(t), x, f)


TIMES = []  # (median, min, max) of every timing, in the order taken


def timed(fn, reps=5):
    """Median wall time of `reps` runs after a warm-up, and the last result; the fastest
    and slowest run are kept in TIMES (and written beside each row as s_min, s_max)."""
    fn()
    ts = []
    for _ in range(reps):
        t0 = time.perf_counter()
        r = fn()
        ts.append(time.perf_counter() - t0)
    TIMES.append((float(np.median(ts)), float(min(ts)), float(max(ts))))
    return float(np.median(ts)), r


def main():
    out = {"event": [], "tanh": []}
    # S6 closed form: turning points (-1)^n (1 - 0.2 n) at n pi, n = 1..5; at rest at 0 afterwards
    s6_turns = [(n * np.pi, (-1) ** n * (1.0 - 0.2 * n)) for n in range(1, 6)]
    s5_ref = s5_reference()
    out["s5_reference"] = {"x_end": s5_ref["x_end"], "v_end": s5_ref["v_end"], "switches": len(s5_ref["switches"])}
    for rtol, method in [(1e-3, "RK45"), (1e-6, "RK45"), (1e-9, "DOP853"), (1e-12, "DOP853")]:
        atol = rtol * 1e-2
        sec, r = timed(lambda: event_driven(S6, rtol, atol, method))
        turns = r["turns"][:5]
        if len(turns) < 5:
            err_x = err_t = float("nan")
        else:
            err_x = max(abs(x - xr) for (_, x), (_, xr) in zip(turns, s6_turns))
            err_t = max(abs(t - tr) for (t, _), (tr, _) in zip(turns, s6_turns))
        out["event"].append({"scene": "S6", "method": method, "rtol": rtol, "atol": atol, "s": sec, "s_min": TIMES[-1][1], "s_max": TIMES[-1][2],
                             "nfev": r["nfev"], "turns": len(r["turns"]), "err_turn_x": err_x, "err_turn_t": err_t,
                             "err_end": abs(r["x_end"] - 0.0)})
        sec, r = timed(lambda: event_driven(S5, rtol, atol, method))
        out["event"].append({"scene": "S5", "method": method, "rtol": rtol, "atol": atol, "s": sec, "s_min": TIMES[-1][1], "s_max": TIMES[-1][2],
                             "nfev": r["nfev"], "turns": len(r["turns"]),
                             "err_end": abs(r["x_end"] - s5_ref["x_end"])})
        print(out["event"][-2:], flush=True)
    # the naive version (no max_step in the stick phase) at one tolerance, to show the pitfall
    sec, r = timed(lambda: event_driven(S5, 1e-6, 1e-8, "RK45", np.inf))
    out["event"].append({"scene": "S5", "method": "RK45, stick phase without max_step", "rtol": 1e-6, "atol": 1e-8,
                         "s": sec, "s_min": TIMES[-1][1], "s_max": TIMES[-1][2], "nfev": r["nfev"], "turns": len(r["turns"]),
                         "err_end": abs(r["x_end"] - s5_ref["x_end"])})
    t_eval_6 = np.array([t for t, _ in s6_turns] + [30.0])
    for eps in [1e-1, 1e-2, 1e-3, 1e-4]:
        for method in ["Radau", "LSODA"]:
            rtol, atol = 1e-8, 1e-10
            sec, sol = timed(lambda: regularised(S6, eps, rtol, atol, method, t_eval_6), reps=3)
            ok = sol.success and sol.y.shape[1] == len(t_eval_6)
            err_x = max(abs(sol.y[0, i] - xr) for i, (_, xr) in enumerate(s6_turns)) if ok else float("nan")
            err_end = abs(sol.y[0, -1]) if ok else float("nan")
            out["tanh"].append({"scene": "S6", "eps": eps, "method": method, "rtol": rtol, "s": sec, "s_min": TIMES[-1][1], "s_max": TIMES[-1][2],
                                "nfev": int(sol.nfev), "err_turn_x": err_x, "err_end": err_end, "ok": bool(ok)})
            sec, sol = timed(lambda: regularised(S5, eps, rtol, atol, method, np.array([30.0])), reps=3)
            ok = sol.success and sol.y.shape[1] == 1
            out["tanh"].append({"scene": "S5", "eps": eps, "method": method, "rtol": rtol, "s": sec, "s_min": TIMES[-1][1], "s_max": TIMES[-1][2],
                                "nfev": int(sol.nfev), "err_end": abs(sol.y[0, -1] - s5_ref["x_end"]) if ok else float("nan"),
                                "ok": bool(ok)})
            print(out["tanh"][-2:], flush=True)
    with open(sys.argv[1], "w") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
