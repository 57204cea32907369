"""SciPy's DOP853 against flipcard's adaptive solver on case (a) at equal error.

Case (a): I = (1, 2, 3), omega0 = (0.01, 10, 0.01), t in [0, 100] (about 36
flips), omega only, 1001 evenly spaced output points. SciPy's
solve_ivp(method='DOP853') runs over a tolerance sweep (rtol = tol,
atol = tol * |omega0|, the error weights flipcard uses); each setting is
timed (best of several runs) and its error, the largest |w - w_exact| / |w_exact|
over the 1001 points, is measured against the exact solution printed by
`flipcard sim --method exact`. flipcard's time and error at tol 1e-10 (omega
only, the same points) come from `cargo bench --bench compare_rust`, which
prints them as the arguments of this script. The script then reads off
SciPy's time at flipcard's error (log-log interpolation along the sweep) and
prints the ratio.

    pip install scipy numpy
    cargo build --release
    cargo bench --bench compare_rust   # prints --flipcard-ms X --flipcard-error Y
    python3 benches/compare_scipy.py --flipcard-ms X --flipcard-error Y

Without --flipcard-error the error is taken from `flipcard sim --method
adaptive --tol 1e-10`, which also integrates the orientation (its error
control then includes q, so it is more accurate than the omega-only run).
"""

import argparse
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

INERTIA = (1.0, 2.0, 3.0)
OMEGA0 = np.array([0.01, 10.0, 0.01])
T_END = 100.0
POINTS = 1001
I = np.array(INERTIA)
A = np.array([(I[1] - I[2]) / I[0], (I[2] - I[0]) / I[1], (I[0] - I[1]) / I[2]])


def euler(_t, w):
    return [A[0] * w[1] * w[2], A[1] * w[2] * w[0], A[2] * w[0] * w[1]]


def flipcard_omega(binary, method, tol=None):
    """omega at the 1001 points, from `flipcard sim` (CSV, full precision)."""
    cmd = [
        str(binary), "sim",
        "--inertia", ",".join(repr(v) for v in INERTIA),
        "--omega", ",".join(repr(float(v)) for v in OMEGA0),
        "--t-end", repr(T_END),
        "--samples", str(POINTS),
        "--method", method,
        "--format", "csv",
    ]
    if tol is not None:
        cmd += ["--tol", repr(tol)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    lines = out.strip().splitlines()
    header = lines[0].split(",")
    cols = [header.index(c) for c in ("w1", "w2", "w3")]
    rows = [[float(line.split(",")[c]) for c in cols] for line in lines[1:]]
    return np.array(rows)


def max_error(omega, exact):
    return float(np.max(np.linalg.norm(omega - exact, axis=1) / np.linalg.norm(exact, axis=1)))


def scipy_run(tol, times):
    return solve_ivp(
        euler, (0.0, T_END), OMEGA0, method="DOP853",
        rtol=tol, atol=tol * np.linalg.norm(OMEGA0), t_eval=times,
    )


def time_at_error(sweep, target):
    """SciPy's time at `target` error, interpolated in log-log along the sweep
    (None when the sweep does not bracket it)."""
    points = sorted((e, t) for _, t, _, e in sweep if e > 0)
    for (e0, t0), (e1, t1) in zip(points, points[1:]):
        if e0 <= target <= e1:
            if e0 == e1:
                return t0
            x = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + x * (math.log(t1) - math.log(t0)))
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    root = Path(__file__).resolve().parent.parent
    parser.add_argument("--flipcard", default=str(root / "target" / "release" / "flipcard"),
                        help="the flipcard binary (default: target/release/flipcard)")
    parser.add_argument("--flipcard-ms", type=float, default=None,
                        help="flipcard's time at tol 1e-10 from `cargo bench --bench compare_rust`")
    parser.add_argument("--flipcard-error", type=float, default=None,
                        help="flipcard's error at tol 1e-10 from `cargo bench --bench compare_rust`")
    parser.add_argument("--repeat", type=int, default=5, help="runs per setting (the best counts)")
    args = parser.parse_args()
    if not Path(args.flipcard).exists():
        sys.exit(f"{args.flipcard}: not found (run `cargo build --release` first)")

    times = np.linspace(0.0, T_END, POINTS)
    exact = flipcard_omega(args.flipcard, "exact")
    if args.flipcard_error is not None:
        flipcard_error, how = args.flipcard_error, "omega only, from compare_rust"
    else:
        flipcard_error = max_error(flipcard_omega(args.flipcard, "adaptive", 1e-10), exact)
        how = "with the orientation, from flipcard sim"

    print("SciPy solve_ivp DOP853, case (a), omega only, 1001 points")
    print(f"{'tol':>8} {'best ms':>10} {'rhs evals':>10} {'error':>10}")
    sweep = []
    for e in range(3, 14):
        tol = 10.0 ** -e
        best = math.inf
        for _ in range(args.repeat):
            start = time.perf_counter()
            sol = scipy_run(tol, times)
            best = min(best, time.perf_counter() - start)
        err = max_error(sol.y.T, exact)
        sweep.append((tol, best * 1e3, sol.nfev, err))
        print(f"{tol:8.0e} {best * 1e3:10.2f} {sol.nfev:10d} {err:10.2e}")

    print(f"\nflipcard adaptive tol 1e-10 ({how}): error {flipcard_error:.2e}")
    scipy_ms = time_at_error(sweep, flipcard_error)
    if scipy_ms is None:
        print("SciPy's sweep does not reach that error")
        return
    print(f"SciPy at the same error: {scipy_ms:.2f} ms")
    if args.flipcard_ms:
        print(f"flipcard: {args.flipcard_ms:.3f} ms -> {scipy_ms / args.flipcard_ms:.0f}x faster than SciPy")
    else:
        print("pass --flipcard-ms (from `cargo bench --bench compare_rust`) for the ratio")


if __name__ == "__main__":
    main()
