"""Writes `benches/stiff_reference.txt`: the final state of each stiff problem
of `benches/stiff.rs` (see `benches/stiff_problems.py`), from SciPy's Radau
IIA at rtol 1e-12 with a tight absolute tolerance, confirmed by SciPy's BDF
and LSODA at rtol 1e-12 (their largest relative distance from it, component
by component, is written beside each line).

    pip install scipy numpy
    python3 benches/stiff_reference.py

`cargo bench --bench stiff` reads the file (it needs no Python) and checks
flipcard's Radau at rtol 1e-12 against it.
"""

import numpy as np
import scipy
from scipy.integrate import solve_ivp

from stiff_problems import FIXTURE, PROBLEMS, max_rel_error

RTOL = 1e-12
# Absolute tolerance of the references, per problem (below every component's
# size at the end of the run by several decades).
ATOL = {"van-der-pol": 1e-14, "robertson": 1e-26, "hires": 1e-20, "oregonator": 1e-14, "e5": 1e-32}


def solve(name, method):
    fun, jac, span, y0, _ = PROBLEMS[name]
    sol = solve_ivp(fun, span, y0, method=method, rtol=RTOL, atol=ATOL[name], jac=jac)
    if not sol.success:
        return None, sol.message
    return sol.y[:, -1], None


def main():
    lines = [
        f"# Written by benches/stiff_reference.py (SciPy {scipy.__version__}, NumPy {np.__version__}):",
        "# final states of the stiff problems of benches/stiff.rs from solve_ivp(method='Radau'),",
        "# rtol 1e-12, analytic Jacobian; each problem is preceded by the largest relative",
        "# distance of BDF and of LSODA at rtol 1e-12 from it.",
        "# name t_end y1 y2 ...",
    ]
    for name, (_, _, span, _, _) in PROBLEMS.items():
        ref, err = solve(name, "Radau")
        if ref is None:
            raise SystemExit(f"{name}: Radau failed: {err}")
        checks = []
        for method in ("BDF", "LSODA"):
            y, err = solve(name, method)
            checks.append(f"{method} failed ({err})" if y is None else f"{method} differs by {max_rel_error(y, ref):.1e}")
        if all("failed" in c for c in checks):
            raise SystemExit(f"{name}: no second method confirms the reference")
        lines.append(f"# {name}: atol {ATOL[name]:g}; " + ", ".join(checks))
        lines.append(" ".join([name, repr(span[1])] + [repr(float(v)) for v in ref]))
        print(lines[-2])
    FIXTURE.write_text("\n".join(lines) + "\n")
    print(f"wrote {FIXTURE}")


if __name__ == "__main__":
    main()
