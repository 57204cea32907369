"""SciPy's Radau against flipcard's on the 200-variable Brusselator, at equal error;
with --grid, on the Brusselator on a 15x15 grid (450 variables, a Jacobian no
ordering makes a narrow band: flipcard factors it sparse).

The problem, its deck scene and its reference (SciPy Radau at rtol 1e-10,
atol 1e-12, checked against BDF) are those of tests/fixtures/brusselator/
(or tests/fixtures/brusselator2d/ with --grid; make.py). SciPy's solve_ivp(method="Radau") gets the Jacobian's sparsity
(`jac_sparsity`, grouped differences) or the exact sparse Jacobian; each
rtol of the sweep (atol = 1e-2 rtol, flipcard's default) is timed, solve
alone, best of several runs, and its error is the largest absolute error of
the state at t = 10 against the reference. flipcard's whole process is timed
the same way (best of several runs of the binary) with its error read from
its JSON output.

    pip install scipy numpy
    cargo build --release
    python3 benches/compare_scipy_bruss.py [--grid] [--flipcard target/release/flipcard]

Not part of CI: SciPy is installed by hand.
"""

import argparse
import importlib.util
import json
import pathlib
import subprocess
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

ROOT = pathlib.Path(__file__).resolve().parent.parent
# The problem compared: its fixture folder, deck file and scene id.
PROBLEMS = {
    False: ("brusselator", "bruss.toml", "bruss"),
    True: ("brusselator2d", "bruss2d.toml", "bruss2d"),
}
FIXTURE = None
make = None


def load(grid):
    """Takes the fixture of the problem compared (its make.py as `make`)."""
    global FIXTURE, make
    FIXTURE = ROOT / "tests" / "fixtures" / PROBLEMS[grid][0]
    spec = importlib.util.spec_from_file_location("make", FIXTURE / "make.py")
    make = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(make)
    make.np = np


def names():
    if hasattr(make, "names"):
        return make.names()
    return [f"u{i}" for i in range(1, make.N + 1)] + [f"v{i}" for i in range(1, make.N + 1)]


def reference():
    rows = (FIXTURE / "reference.csv").read_text().splitlines()[1:]
    return np.array([float(r.split(",")[1]) for r in rows])


def best_of(runs, f):
    best = float("inf")
    out = None
    for _ in range(runs):
        t0 = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t0)
    return best, out


def scipy_run(rtol, how):
    y0 = np.array(make.initial())
    kw = {"jac_sparsity": make.sparsity()} if how == "sparsity" else {"jac": make.jac}
    sol = solve_ivp(make.rhs, (0.0, make.T_END), y0, method="Radau", rtol=rtol,
                    atol=1e-2 * rtol, **kw)
    assert sol.success, sol.message
    return sol.y[:, -1]


def flipcard_run(binary, tol, grid):
    _, deck, scene = PROBLEMS[grid]
    out = subprocess.run(
        [binary, "sim", "--deck", str(FIXTURE / "decks" / deck), "--scene", scene,
         "--method", "radau", "--tol", tol, "--samples", "2", "--format", "json"],
        check=True, capture_output=True, text=True).stdout
    last = json.loads(out)["samples"][-1]
    return np.array([last[n] for n in names()])


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--flipcard", default=str(ROOT / "target" / "release" / "flipcard"))
    p.add_argument("--runs", type=int, default=5)
    p.add_argument("--grid", action="store_true", help="the 15x15 grid (450 variables)")
    a = p.parse_args()
    load(a.grid)
    ref = reference()
    print("who,rtol,seconds,max_abs_error")
    for tol in ["1e-4", "1e-5", "1e-6", "1e-7", "1e-8"]:
        sec, y = best_of(a.runs, lambda: flipcard_run(a.flipcard, tol, a.grid))
        print(f"flipcard (whole process),{tol},{sec:.4f},{np.max(np.abs(y - ref)):.3e}")
    for how in ["sparsity", "exact"]:
        for rtol in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8]:
            sec, y = best_of(a.runs, lambda: scipy_run(rtol, how))
            print(f"scipy radau ({how}),{rtol:.0e},{sec:.4f},{np.max(np.abs(y - ref)):.3e}")


if __name__ == "__main__":
    main()
