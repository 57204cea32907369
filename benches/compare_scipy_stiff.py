"""SciPy's Radau IIA against flipcard's on two stiff problems, at equal error.

The problems and tolerances are those of `benches/stiff.rs`:

- Van der Pol, x'' - mu (1 - x^2) x' + x = 0, mu = 1000, (x, v)(0) = (2, 0),
  t in [0, 3000], atol = rtol;
- Robertson's kinetics, y(0) = (1, 0, 0), t in [0, 1e11],
  atol = rtol * (1e-4, 1e-10, 1e-4).

solve_ivp(method="Radau") gets the analytic Jacobian and sweeps rtol; each
setting is timed (best of several runs) and its error is the largest relative
error of a component of the final state against the reference below
(flipcard's Radau at rtol 1e-12, which `cargo bench --bench stiff` recomputes
and checks against diffsol's BDF at rtol 1e-11). With flipcard's time and
error at rtol 1e-6 (printed by that benchmark) the script reads off SciPy's
time at the same error (log-log interpolation along the sweep) and prints the
ratio.

    pip install scipy numpy
    cargo bench --bench stiff      # prints the --...-ms/--...-error arguments
    python3 benches/compare_scipy_stiff.py --van-der-pol-ms X --van-der-pol-error Y \\
        --robertson-ms X --robertson-error Y

Not part of CI: SciPy is installed by hand.
"""

import argparse
import math
import time

import numpy as np
from scipy.integrate import solve_ivp

MU = 1000.0

# flipcard's Radau IIA at rtol 1e-12 (landing on the end time).
REFERENCE = {
    "van-der-pol": np.array([-1.510606937098292, 0.0011783800000050144]),
    "robertson": np.array([2.0833401493200207e-8, 8.333360768809681e-14, 0.9999999791665162]),
}


def vdp(_t, y):
    return [y[1], MU * (1.0 - y[0] * y[0]) * y[1] - y[0]]


def vdp_jac(_t, y):
    return [[0.0, 1.0], [-2.0 * MU * y[0] * y[1] - 1.0, MU * (1.0 - y[0] * y[0])]]


def rober(_t, y):
    return [
        -0.04 * y[0] + 1e4 * y[1] * y[2],
        0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] * y[1],
        3e7 * y[1] * y[1],
    ]


def rober_jac(_t, y):
    return [
        [-0.04, 1e4 * y[2], 1e4 * y[1]],
        [0.04, -1e4 * y[2] - 6e7 * y[1], -1e4 * y[1]],
        [0.0, 6e7 * y[1], 0.0],
    ]


PROBLEMS = {
    "van-der-pol": (vdp, vdp_jac, (0.0, 3000.0), [2.0, 0.0], lambda r: r),
    "robertson": (
        rober,
        rober_jac,
        (0.0, 1e11),
        [1.0, 0.0, 0.0],
        lambda r: np.array([r * 1e-4, r * 1e-10, r * 1e-4]),
    ),
}


def run(name, rtol):
    fun, jac, span, y0, atol = PROBLEMS[name]
    sol = solve_ivp(fun, span, y0, method="Radau", rtol=rtol, atol=atol(rtol), jac=jac)
    if not sol.success:
        return None, sol
    return sol.y[:, -1], sol


def best_time(name, rtol, budget=1.0):
    best = math.inf
    start = time.perf_counter()
    runs = 0
    while runs < 3 or (time.perf_counter() - start < budget and runs < 50):
        t0 = time.perf_counter()
        run(name, rtol)
        best = min(best, time.perf_counter() - t0)
        runs += 1
    return best


def error(name, y):
    ref = REFERENCE[name]
    return float(np.max(np.abs(y - ref) / np.abs(ref)))


def time_at_error(points, err):
    """Log-log interpolation of (error, seconds) at err, or None outside."""
    pts = sorted(points, key=lambda p: -p[0])
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e1 <= err <= e0 and e0 > e1:
            x = (math.log(err) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + x * (math.log(t1) - math.log(t0)))
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for name in PROBLEMS:
        parser.add_argument(f"--{name}-ms", type=float, help="flipcard's time (ms) at rtol 1e-6")
        parser.add_argument(f"--{name}-error", type=float, help="flipcard's error at rtol 1e-6")
    parser.add_argument("--rtols", default="1e-4,1e-5,1e-6,1e-7,1e-8,1e-9")
    args = parser.parse_args()
    rtols = [float(r) for r in args.rtols.split(",")]

    for name in PROBLEMS:
        print(f"\n{name}: scipy solve_ivp(method='Radau'), analytic Jacobian")
        print(f"  {'rtol':>7}  {'error':>9}  {'time':>10}  {'steps':>6}  {'nfev':>6}  {'njev':>5}  {'nlu':>5}")
        points = []
        for rtol in rtols:
            y, sol = run(name, rtol)
            if y is None:
                print(f"  {rtol:>7.0e}  failed: {sol.message}")
                continue
            err = error(name, y)
            secs = best_time(name, rtol)
            points.append((err, secs))
            steps = len(sol.t) - 1
            print(
                f"  {rtol:>7.0e}  {err:>9.2e}  {secs * 1e3:>7.2f} ms  {steps:>6}  "
                f"{sol.nfev:>6}  {sol.njev:>5}  {sol.nlu:>5}"
            )
        ms = getattr(args, f"{name.replace('-', '_')}_ms")
        err = getattr(args, f"{name.replace('-', '_')}_error")
        if ms is None or err is None:
            print("  (give flipcard's --{0}-ms and --{0}-error for the ratio)".format(name))
            continue
        scipy_secs = time_at_error(points, err)
        if scipy_secs is None:
            print(f"  flipcard's error {err:.2e} lies outside SciPy's sweep")
            continue
        print(
            f"  at flipcard's error {err:.2e}: flipcard {ms:.3f} ms, scipy {scipy_secs * 1e3:.2f} ms "
            f"-> flipcard is {scipy_secs * 1e3 / ms:.0f}x faster"
        )


if __name__ == "__main__":
    main()
