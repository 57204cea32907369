"""SciPy's Radau IIA, BDF and LSODA against flipcard's Radau IIA on the five
stiff problems of `benches/stiff.rs`, at equal error.

The problems, tolerances and references are those of `benches/stiff.rs`
(defined in `benches/stiff_problems.py`; references in
`benches/stiff_reference.txt`, written by `benches/stiff_reference.py`):
Van der Pol (mu = 1000, to t = 3000), Robertson (to 1e11), HIRES (to
321.8122), the Oregonator (to 360) and E5 (to 1e5, atol 1e-24).

solve_ivp gets the analytic Jacobian and each method sweeps rtol; each setting
is timed (best of several runs) and its error is the largest relative error of
a component of the final state against the reference. With flipcard's time
and error at rtol 1e-6 (printed by that benchmark) the script reads off each
SciPy method's time at the same error (log-log interpolation along its sweep)
and prints the ratio.

    pip install scipy numpy
    cargo bench --bench stiff      # prints the --...-ms/--...-error arguments
    python3 benches/compare_scipy_stiff.py --van-der-pol-ms X --van-der-pol-error Y \\
        --robertson-ms X --robertson-error Y --hires-ms X --hires-error Y ...

Not part of CI: SciPy is installed by hand.
"""

import argparse
import math
import time
import warnings

from scipy.integrate import solve_ivp

from stiff_problems import PROBLEMS, max_rel_error, read_fixture

METHODS = ("Radau", "BDF", "LSODA")


def run(name, method, rtol):
    fun, jac, span, y0, atol = PROBLEMS[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = solve_ivp(fun, span, y0, method=method, rtol=rtol, atol=atol(rtol), jac=jac)
    if not sol.success:
        return None, sol
    return sol.y[:, -1], sol


def best_time(name, method, rtol, budget=1.0):
    best = math.inf
    start = time.perf_counter()
    runs = 0
    while runs < 3 or (time.perf_counter() - start < budget and runs < 50):
        t0 = time.perf_counter()
        run(name, method, rtol)
        best = min(best, time.perf_counter() - t0)
        runs += 1
    return best


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
    parser.add_argument("--only", help="comma-separated problem names")
    args = parser.parse_args()
    rtols = [float(r) for r in args.rtols.split(",")]
    reference = read_fixture()
    names = args.only.split(",") if args.only else list(PROBLEMS)

    for name in names:
        ms = getattr(args, f"{name.replace('-', '_')}_ms")
        err = getattr(args, f"{name.replace('-', '_')}_error")
        print(f"\n{name}: scipy solve_ivp, analytic Jacobian, reference benches/stiff_reference.txt")
        print(f"  {'method':<6} {'rtol':>7}  {'error':>9}  {'time':>10}  {'steps':>6}  {'nfev':>6}  {'njev':>5}  {'nlu':>5}")
        for method in METHODS:
            points = []
            for rtol in rtols:
                y, sol = run(name, method, rtol)
                if y is None:
                    print(f"  {method:<6} {rtol:>7.0e}  failed: {sol.message}")
                    continue
                e = max_rel_error(y, reference[name])
                secs = best_time(name, method, rtol)
                points.append((e, secs))
                steps = len(sol.t) - 1
                print(
                    f"  {method:<6} {rtol:>7.0e}  {e:>9.2e}  {secs * 1e3:>7.2f} ms  {steps:>6}  "
                    f"{sol.nfev:>6}  {sol.njev:>5}  {sol.nlu:>5}"
                )
            if ms is None or err is None:
                continue
            scipy_secs = time_at_error(points, err)
            if scipy_secs is None:
                print(f"  {method}: flipcard's error {err:.2e} lies outside the sweep")
            else:
                print(
                    f"  {method}: at flipcard's error {err:.2e}: flipcard radau {ms:.3f} ms, "
                    f"scipy {scipy_secs * 1e3:.2f} ms -> flipcard is {scipy_secs * 1e3 / ms:.0f}x faster"
                )
        if ms is None or err is None:
            print("  (give flipcard's --{0}-ms and --{0}-error for the ratios)".format(name))


if __name__ == "__main__":
    main()
