"""Writes `benches/stiff_reference.txt`: the final state of each stiff problem
of `benches/stiff.rs` (see `benches/stiff_problems.py`), from SciPy's Radau
IIA at rtol 1e-12 with a tight absolute tolerance, confirmed by SciPy's BDF
and LSODA at rtol 1e-12 (their largest relative distance from it, component
by component, is written beside each line).

Two exceptions. E5 is solved with its invariant y2 = y3 + y4 written out
(`e5_reduced` in `benches/stiff_problems.py`) at rtol 1e-13, where the three
methods agree to 5e-11: in the four-variable form rounding breaks the
invariant by ~1e-21 and every method's answer scatters by ~1e-9 (SciPy's
Radau at rtol 1e-12 lands 5.4e-10 from this reference, at 1e-11 1.7e-9), so
that form cannot confirm a reference below 1e-9. The linear system's
reference is its closed form (the methods' distances from it are written).

    pip install scipy numpy
    python3 benches/stiff_reference.py

`cargo bench --bench stiff` reads the file (it needs no Python) and checks
flipcard's Radau at rtol 1e-12 against it.
"""

import numpy as np
import scipy
from scipy.integrate import solve_ivp

from stiff_problems import FIXTURE, LIN_END, PROBLEMS, e5_reduced, e5_reduced_jac, linear_exact, max_rel_error

RTOL = 1e-12
# Absolute tolerance of the references, per problem (below every component's
# size at the end of the run by several decades).
ATOL = {
    "van-der-pol": 1e-14,
    "robertson": 1e-26,
    "hires": 1e-20,
    "oregonator": 1e-14,
    "e5": 1e-32,
    "van-der-pol-1e4": 1e-14,
    "linear": 1e-14,
}
RTOL_OF = {"e5": 1e-13, "linear": 1e-10}


def solve(name, method):
    fun, jac, span, y0, _ = PROBLEMS[name]
    rtol = RTOL_OF.get(name, RTOL)
    if name == "e5":
        y0r = [y0[0], y0[2], y0[3]]
        sol = solve_ivp(e5_reduced, span, y0r, method=method, rtol=rtol, atol=ATOL[name], jac=e5_reduced_jac)
        if not sol.success:
            return None, sol.message
        y1, y3, y4 = sol.y[:, -1]
        return np.array([y1, y3 + y4, y3, y4]), None
    sol = solve_ivp(fun, span, y0, method=method, rtol=rtol, atol=ATOL[name], jac=jac)
    if not sol.success:
        return None, sol.message
    return sol.y[:, -1], None


def main():
    lines = [
        f"# Written by benches/stiff_reference.py (SciPy {scipy.__version__}, NumPy {np.__version__}):",
        "# final states of the stiff problems of benches/stiff.rs from solve_ivp(method='Radau'),",
        "# rtol 1e-12, analytic Jacobian; each problem is preceded by the largest relative",
        "# distance of BDF and of LSODA at rtol 1e-12 from it. E5: at rtol 1e-13 with y2 = y3 + y4",
        "# written out (see the script); linear: the closed form.",
        "# name t_end y1 y2 ...",
    ]
    for name, (_, _, span, _, _) in PROBLEMS.items():
        if name == "linear":
            ref, methods = linear_exact(LIN_END), ("Radau", "BDF", "LSODA")
        else:
            (ref, err), methods = solve(name, "Radau"), ("BDF", "LSODA")
            if ref is None:
                raise SystemExit(f"{name}: Radau failed: {err}")
        checks = []
        for method in methods:
            y, err = solve(name, method)
            checks.append(f"{method} failed ({err})" if y is None else f"{method} differs by {max_rel_error(y, ref):.1e}")
        if all("failed" in c for c in checks):
            raise SystemExit(f"{name}: no second method confirms the reference")
        lines.append(f"# {name}: rtol {RTOL_OF.get(name, RTOL):g}, atol {ATOL[name]:g}; " + ", ".join(checks))
        lines.append(" ".join([name, repr(span[1])] + [repr(float(v)) for v in ref]))
        print(lines[-2])
    FIXTURE.write_text("\n".join(lines) + "\n")
    print(f"wrote {FIXTURE}")


if __name__ == "__main__":
    main()
