"""SciPy's DOP853 on the notes' case (a), for a side-by-side with
`cargo bench --bench integrators`.

I = (1, 2, 3), omega0 = (0.01, 10, 0.01), t in [0, 100], rtol = atol = tol
(ω only). Prints the best wall time of several runs, the steps taken and
the final ω, and, given `--reference=W1,W2,W3` (ω(100) from `flipcard sim
--method exact`), the error of the final ω relative to |ω|.

    python3 benches/scipy_dop853.py [--tol 1e-10] [--repeat 5] [--reference=W1,W2,W3]
"""

import argparse
import time

import numpy as np
from scipy.integrate import solve_ivp

I = np.array([1.0, 2.0, 3.0])
A = np.array([(I[1] - I[2]) / I[0], (I[2] - I[0]) / I[1], (I[0] - I[1]) / I[2]])
W0 = np.array([0.01, 10.0, 0.01])
T_END = 100.0


def euler(_t, w):
    return [A[0] * w[1] * w[2], A[1] * w[2] * w[0], A[2] * w[0] * w[1]]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--tol", type=float, default=1e-10)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--reference", type=str, default=None)
    args = parser.parse_args()
    best = float("inf")
    for _ in range(args.repeat):
        start = time.perf_counter()
        sol = solve_ivp(euler, (0.0, T_END), W0, method="DOP853", rtol=args.tol, atol=args.tol * np.linalg.norm(W0))
        best = min(best, time.perf_counter() - start)
    final = sol.y[:, -1]
    print(f"scipy DOP853 tol {args.tol:g}: best {best * 1e3:.2f} ms, {sol.nfev} rhs evaluations, {sol.t.size - 1} steps")
    print("final omega:", ",".join(repr(float(v)) for v in final))
    if args.reference:
        ref = np.array([float(v) for v in args.reference.split(",")])
        print(f"error |w - w_ref| / |w_ref| = {np.linalg.norm(final - ref) / np.linalg.norm(ref):.3e}")


if __name__ == "__main__":
    main()
