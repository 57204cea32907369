"""`auto` against the best single method, on every problem of issue 26's list
at every tolerance 1e-3 … 1e-10 (issue 26, section 3: "auto within 1.2× of
the best single method on every problem of the list, at every tolerance").

The problems: HIRES, the Oregonator, E5 (to 1e5), the 200-variable
Brusselator, Van der Pol at mu = 1e4 and 1e5, the linear system with
eigenvalues -1 and -1e8, Robertson (as in `benches/stiff_problems.py` and
`benches/stiff_table.md`), and the non-stiff ones: Kepler's orbit at
e = 0.9 and 0.99 (GM = a = 1, from pericentre, to 10.25 periods), Lorenz
(sigma = 10, rho = 28, beta = 8/3, from (1, 1, 1), to t = 10) and the
pendulum released at rest from 179.9° (theta'' = -sin theta, to t = 100).
Each is written as a deck scene and run by flipcard's own binary,

    flipcard sim --deck D --scene s --method auto|radau|adaptive --tol T \\
        --samples 2 --format json [--atol …]

with the same absolute tolerance for the three methods (the table's for the
stiff problems, rtol·1e-3 for the non-stiff ones, flipcard's default on E5).
`adaptive` is DOP853 alone: it refuses a problem it finds stiff, which
counts as an infinite cost.

Cost, two ways:
- **instructions**: the whole process under `valgrind --tool=callgrind`
  (machine-independent, repeatable), less the same process on the same deck
  run for 1e-9 of its time (parsing, compiling, start-up), so the column is
  the solve's;
- **CPU ms**: user + system time of the whole process (best of 3) from the
  child's rusage; start-up included, so short runs read near 1×.

The error is the largest relative error of a component of the final state
against the reference: `benches/stiff_reference.txt` and the Brusselator's
fixture for the stiff problems; for the others `benches/auto_reference.txt`
(written by `--reference`: Kepler's equation and Jacobi's sn by mpmath at 30
digits, Lorenz by mpmath's Taylor series at 30 digits, Van der Pol at
mu = 1e5 by SciPy's Radau at rtol 1e-12, its distance to LSODA given).

    cargo build --release
    python3 benches/auto_vs_best.py [--flipcard target/release/flipcard] \\
        [--only hires,e5] [--tols 1e-3,1e-6] [--before old.json]

writes `benches/auto_vs_best.md` and the raw runs to `benches/auto_vs_best.json`
(with `--before`, the table gets the earlier auto/best ratios beside). Not
part of CI: valgrind and SciPy are installed by hand.
"""

import argparse
import concurrent.futures
import json
import math
import os
import pathlib
import platform
import re
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

from stiff_problems import DECKS, PROBLEMS, max_rel_error, read_fixture

ROOT = pathlib.Path(__file__).resolve().parent.parent
HERE = pathlib.Path(__file__).resolve().parent
REFERENCE = HERE / "auto_reference.txt"
TOLS = [f"1e-{k}" for k in range(3, 11)]
METHODS = ("auto", "radau", "adaptive")
ORDER = [
    "hires", "oregonator", "e5", "brusselator", "van-der-pol-1e4", "van-der-pol-1e5", "linear",
    "kepler-0.9", "kepler-0.99", "lorenz", "pendulum-179.9", "robertson",
]

KEPLER_PERIODS = 10.25
LORENZ_END = 10.0
PENDULUM_DEG = 179.9
PENDULUM_END = 100.0
MU5 = 1e5


def kepler_start(e):
    return [1.0 - e, 0.0, 0.0, math.sqrt((1.0 + e) / (1.0 - e))]


# name: (variables, equations, params, y0, t_end, atol(rtol) or None)
EXTRA = {
    "van-der-pol-1e5": (["x", "v"], ["v", "mu*(1 - x^2)*v - x"], {"mu": MU5}, [2.0, 0.0], 2e5, lambda r: [r, r]),
    "kepler-0.9": (
        ["x", "y", "vx", "vy"], ["vx", "vy", "-x/sqrt(x^2 + y^2)^3", "-y/sqrt(x^2 + y^2)^3"], {},
        kepler_start(0.9), 2 * math.pi * KEPLER_PERIODS, lambda r: [r * 1e-3] * 4,
    ),
    "kepler-0.99": (
        ["x", "y", "vx", "vy"], ["vx", "vy", "-x/sqrt(x^2 + y^2)^3", "-y/sqrt(x^2 + y^2)^3"], {},
        kepler_start(0.99), 2 * math.pi * KEPLER_PERIODS, lambda r: [r * 1e-3] * 4,
    ),
    "lorenz": (
        ["x", "y", "z"], ["s*(y - x)", "x*(rho - z) - y", "x*y - b*z"], {"s": 10.0, "rho": 28.0, "b": 8.0 / 3.0},
        [1.0, 1.0, 1.0], LORENZ_END, lambda r: [r * 1e-3] * 3,
    ),
    "pendulum-179.9": (
        ["theta", "omega"], ["omega", "-sin(theta)"], {}, [PENDULUM_DEG * math.pi / 180.0, 0.0], PENDULUM_END,
        lambda r: [r * 1e-3] * 2,
    ),
}


def deck(name, variables, equations, params, y0, t_end):
    q = lambda xs: "[" + ", ".join(f'"{x}"' for x in xs) + "]"  # noqa: E731
    lines = [
        "[deck]", f'id = "{name}"', "title = 'T'", 'languages = ["en"]', "",
        "[[card]]", 'id = "c"', "front = 'F'", "back = 'B'", "",
        "[[scene]]", 'id = "s"', f"variables = {q(variables)}",
        "initial = [" + ", ".join(repr(float(v)) for v in y0) + "]",
    ]
    if params:
        lines.append("params = { " + ", ".join(f"{k} = {v!r}" for k, v in params.items()) + " }")
    lines += [f"equations = {q(equations)}", f"duration = {t_end!r}", 'show = ["plot"]', f'plot = ["{variables[0]}"]', ""]
    return "\n".join(lines)


def write_reference():
    """The references of the non-stiff problems and Van der Pol at 1e5."""
    import mpmath
    from scipy.integrate import solve_ivp

    mpmath.mp.dps = 30
    out = [
        "# Written by benches/auto_vs_best.py --reference: final states of the problems of",
        "# benches/auto_vs_best.py that benches/stiff_reference.txt lacks.",
        "# name t_end y1 y2 ...",
    ]
    for e in ("0.9", "0.99"):
        ee = mpmath.mpf(e)
        m = 2 * mpmath.pi * mpmath.mpf(KEPLER_PERIODS)
        m = m - 2 * mpmath.pi * mpmath.floor(m / (2 * mpmath.pi))
        big_e = mpmath.findroot(lambda x: x - ee * mpmath.sin(x) - m, mpmath.pi)
        den = 1 - ee * mpmath.cos(big_e)
        w = mpmath.sqrt(1 - ee * ee)
        state = [mpmath.cos(big_e) - ee, w * mpmath.sin(big_e), -mpmath.sin(big_e) / den, w * mpmath.cos(big_e) / den]
        out.append(f"# kepler-{e}: exact, from Kepler's equation (mpmath, 30 digits), GM = a = 1, {KEPLER_PERIODS} periods")
        out.append(f"kepler-{e} {2 * math.pi * KEPLER_PERIODS!r} " + " ".join(repr(float(v)) for v in state))
    # Pendulum: sin(theta/2) = k sn(K - t | m), omega = -2 k cn(K - t | m).
    th0 = mpmath.mpf(EXTRA["pendulum-179.9"][3][0])
    k = mpmath.sin(th0 / 2)
    mm = k * k
    u = mpmath.ellipk(mm) - PENDULUM_END
    theta = 2 * mpmath.asin(k * mpmath.ellipfun("sn", u, m=mm))
    omega = -2 * k * mpmath.ellipfun("cn", u, m=mm)
    out.append("# pendulum-179.9: exact, Jacobi's sn and cn (mpmath, 30 digits) from the f64 release angle")
    out.append(f"pendulum-179.9 {PENDULUM_END!r} {float(theta)!r} {float(omega)!r}")
    # Lorenz: mpmath's Taylor-series solver at 30 digits.
    s, rho, b = 10, 28, mpmath.mpf(8) / 3
    f = mpmath.odefun(lambda t, y: [s * (y[1] - y[0]), y[0] * (rho - y[2]) - y[1], y[0] * y[1] - b * y[2]], 0, [1, 1, 1],
                      tol=mpmath.mpf(10) ** -25, degree=30)
    state = f(LORENZ_END)
    lz = lambda t, y: [10 * (y[1] - y[0]), y[0] * (28 - y[2]) - y[1], y[0] * y[1] - 8 / 3 * y[2]]  # noqa: E731
    d = solve_ivp(lz, (0, LORENZ_END), [1.0, 1.0, 1.0], method="DOP853", rtol=1e-13, atol=1e-13).y[:, -1]
    ref = np.array([float(v) for v in state])
    out.append(f"# lorenz: mpmath odefun (Taylor, 30 digits, tol 1e-25); SciPy DOP853 rtol 1e-13 differs by "
               f"{max_rel_error(d, ref):.1e}")
    out.append(f"lorenz {LORENZ_END!r} " + " ".join(repr(float(v)) for v in state))
    # Van der Pol at mu = 1e5.
    mu = MU5
    fv = lambda t, y: [y[1], mu * (1 - y[0] ** 2) * y[1] - y[0]]  # noqa: E731
    jv = lambda t, y: [[0, 1], [-2 * mu * y[0] * y[1] - 1, mu * (1 - y[0] ** 2)]]  # noqa: E731
    r = solve_ivp(fv, (0, 2e5), [2.0, 0.0], method="Radau", rtol=1e-12, atol=1e-14, jac=jv).y[:, -1]
    lsoda = solve_ivp(fv, (0, 2e5), [2.0, 0.0], method="LSODA", rtol=1e-12, atol=1e-14, jac=jv)
    far = f"LSODA differs by {max_rel_error(lsoda.y[:, -1], r):.1e}" if lsoda.success else f"LSODA failed ({lsoda.message})"
    out.append(f"# van-der-pol-1e5: SciPy Radau rtol 1e-12, atol 1e-14; {far}")
    out.append(f"van-der-pol-1e5 {2e5!r} " + " ".join(repr(float(v)) for v in r))
    REFERENCE.write_text("\n".join(out) + "\n")
    print(f"wrote {REFERENCE}", file=sys.stderr)


def read_reference(path):
    out = {}
    for line in path.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        name, *values = line.split()
        out[name] = np.array([float(v) for v in values[1:]])
    return out


def problems(tmp):
    """name -> (deck path, variable names, reference, atol(rtol) or None, short deck path)."""
    ref = read_fixture()
    ref.update(read_reference(REFERENCE))
    out = {}
    for name in ORDER:
        if name == "brusselator":
            bruss = ROOT / "tests" / "fixtures" / "brusselator"
            text = (bruss / "decks" / "bruss.toml").read_text().replace('id = "bruss"\nvariables', 'id = "s"\nvariables')
            names = [f"u{i}" for i in range(1, 101)] + [f"v{i}" for i in range(1, 101)]
            rows = (bruss / "reference.csv").read_text().splitlines()[1:]
            reference = np.array([float(r.split(",")[1]) for r in rows])
            atol = lambda r: [1e-2 * r] * 200  # noqa: E731
            t_end = 10.0
        elif name in EXTRA:
            variables, equations, params, y0, t_end, atol = EXTRA[name]
            text = deck(name.replace(".", "-"), variables, equations, params, y0, t_end)
            names, reference = variables, ref[name]
        else:
            variables, equations, params = DECKS[name]
            _, _, span, y0, atol_np = PROBLEMS[name]
            t_end = span[1]
            text = deck(name, variables, equations, params, y0, t_end)
            names, reference = variables, ref[name]
            atol = None if name == "e5" else (
                lambda a, k: lambda r: [float(x) for x in np.broadcast_to(a(r), (k,))]
            )(atol_np, len(names))
        d = tmp / name
        # Deck ids take no dots.
        deck_id = "bruss" if name == "brusselator" else name.replace(".", "-")
        (d / "decks").mkdir(parents=True, exist_ok=True)
        (d / "content" / deck_id).mkdir(parents=True, exist_ok=True)
        (d / "content" / deck_id / "en.toml").write_text("")
        (d / "decks" / f"{deck_id}.toml").write_text(text)
        short = tmp / f"{name}-short"
        (short / "decks").mkdir(parents=True, exist_ok=True)
        (short / "content" / deck_id).mkdir(parents=True, exist_ok=True)
        (short / "content" / deck_id / "en.toml").write_text("")
        short_text = re.sub(r"(?m)^duration = .*$", f"duration = {t_end * 1e-9!r}", text)
        (short / "decks" / f"{deck_id}.toml").write_text(short_text)
        out[name] = (d / "decks" / f"{deck_id}.toml", names, reference, atol, short / "decks" / f"{deck_id}.toml")
    return out


def command(binary, deck_path, method, tol, names, atol):
    extra = [] if atol is None else ["--atol", ",".join(f"{n}={a!r}" for n, a in zip(names, atol(float(tol))))]
    return [binary, "sim", "--deck", str(deck_path), "--scene", "s", "--method", method, "--tol", tol,
            "--samples", "2", "--format", "json", *extra]


def instructions(cmd):
    """Instructions of the whole process under callgrind, or None."""
    proc = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", *cmd],
                          capture_output=True, text=True)
    m = re.search(r"Collected : (\d+)", proc.stderr)
    return int(m.group(1)) if m else None


def cpu_run(cmd, runs=3):
    """(best CPU seconds, parsed JSON, exit code) of the process."""
    best, out, code = math.inf, None, None
    for _ in range(runs):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run(cmd, capture_output=True, text=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        best = min(best, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime))
        try:
            out = json.loads(proc.stdout)
        except json.JSONDecodeError:
            out = {"error": proc.stderr.strip() or "no output"}
        code = proc.returncode
        if code != 0:
            break
    return best, out, code


def one(binary, probs, name, method, tol):
    print(f"{name} {method} {tol}", file=sys.stderr, flush=True)
    deck_path, names, reference, atol, _ = probs[name]
    cmd = command(binary, deck_path, method, tol, names, atol)
    secs, out, code = cpu_run(cmd)
    row = {"problem": name, "method": method, "tol": tol}
    if code != 0:
        msg = out.get("error") if isinstance(out, dict) else None
        row["failed"] = (msg or "failed").splitlines()[0][:200]
        return row
    last = out["samples"][-1]
    y = np.array([last[n] for n in names])
    st = out["stats"]
    row.update({
        "error": max_rel_error(y, reference), "steps": st["steps"], "rejected": st["rejected"],
        "rhs_evals": st["rhs_evals"], "jacobian_evals": st["jacobian_evals"],
        "lu": st["lu_decompositions"], "stiff_from": st.get("stiff_from"), "cpu_ms": secs * 1e3,
        "instructions": instructions(cmd),
    })
    return row


def baseline(binary, probs, name):
    deck_path, names, _, atol, short = probs[name]
    return instructions(command(binary, short, "adaptive", "1e-6", names, atol))


def fmt_int(x):
    return "—" if x is None else f"{x / 1e6:,.2f}M"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--flipcard", default=str(ROOT / "target" / "release" / "flipcard"))
    parser.add_argument("--only", help="comma-separated problem names")
    parser.add_argument("--tols", help="comma-separated tolerances (default 1e-3 … 1e-10)")
    parser.add_argument("--out", default=str(HERE / "auto_vs_best.md"))
    parser.add_argument("--json", default=str(HERE / "auto_vs_best.json"))
    parser.add_argument("--before", help="an earlier --json file: its auto/best ratios go beside")
    parser.add_argument("--jobs", type=int, default=2, help="processes at once (counts are unaffected)")
    parser.add_argument("--reference", action="store_true", help="write benches/auto_reference.txt and stop")
    args = parser.parse_args()
    if args.reference:
        write_reference()
        return
    names = args.only.split(",") if args.only else ORDER
    tols = args.tols.split(",") if args.tols else TOLS
    load = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        probs = problems(pathlib.Path(tmp))
        jobs = [(n, m, t) for n in names for t in tols for m in METHODS]
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            base = dict(zip(names, pool.map(lambda n: baseline(args.flipcard, probs, n), names)))
            rows = list(pool.map(lambda j: one(args.flipcard, probs, *j), jobs))
    for r in rows:
        b = base.get(r["problem"])
        if r.get("instructions") is not None and b is not None:
            r["solve_instructions"] = max(r["instructions"] - b, 1)
    before = {}
    if args.before:
        for r in json.loads(pathlib.Path(args.before).read_text())["ratios"]:
            before[(r["problem"], r["tol"])] = r
    by = {(r["problem"], r["method"], r["tol"]): r for r in rows}
    lines = [
        "# auto against the best single method",
        "",
        f"Written by `python3 benches/auto_vs_best.py` (after `cargo build --release`); "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {platform.machine()}, {os.cpu_count()} cores, "
        f"load average {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} at the start.",
        "",
        "For each problem and tolerance: `flipcard sim --method auto|radau|adaptive --tol T --samples 2 "
        "--format json` on the problem as a deck scene, every method with the same absolute tolerance. "
        "**instr** is the solve's instructions (callgrind, the whole process less the same deck run for "
        "1e-9 of its time); **CPU ms** the whole process's user + system time, best of 3. **best** is the "
        "cheaper of radau and adaptive (DOP853 alone; refused = infinite); **auto/best** the ratio by "
        "instructions and by CPU time; ✗ marks a ratio by instructions above 1.2. Errors: the largest "
        "relative error of a component of the final state against the reference (the script's docstring).",
        "",
    ]
    ratios = []
    for name in names:
        lines += [f"## {name}", ""]
        head = "| tol | auto error | steps | instr | CPU ms | radau error | steps | instr | CPU ms | adaptive error | steps | instr | CPU ms | auto/best instr | auto/best CPU |"
        if before:
            head += " before (instr) |"
        lines += [head, "|" + "---|" * (head.count("|") - 1)]
        for tol in tols:
            cells = []
            for m in METHODS:
                r = by[(name, m, tol)]
                if "failed" in r:
                    cells += ["refused" if m == "adaptive" else "failed", "", "∞" if m == "adaptive" else "", ""]
                else:
                    cells += [f"{r['error']:.1e}", f"{r['steps']:,}", fmt_int(r.get("solve_instructions")), f"{r['cpu_ms']:.1f}"]
            a, rd, ad = (by[(name, m, tol)] for m in METHODS)
            inf = math.inf

            def cost(r, key):
                return inf if "failed" in r or r.get(key) is None else r[key]

            best_i = min(cost(rd, "solve_instructions"), cost(ad, "solve_instructions"))
            best_c = min(cost(rd, "cpu_ms"), cost(ad, "cpu_ms"))
            ri = cost(a, "solve_instructions") / best_i if best_i < inf else math.nan
            rc = cost(a, "cpu_ms") / best_c if best_c < inf else math.nan
            ratios.append({"problem": name, "tol": tol, "instr": ri, "cpu": rc})
            mark = " ✗" if ri > 1.2 else ""
            cells += [f"{ri:.2f}{mark}", f"{rc:.2f}"]
            if before:
                b = before.get((name, tol))
                cells.append("—" if b is None else f"{b['instr']:.2f}")
            lines.append(f"| {tol} | " + " | ".join(cells) + " |")
        fails = [r for r in rows if r["problem"] == name and "failed" in r]
        for r in fails:
            lines.append(f"|  | {r['method']} at {r['tol']}: {r['failed']} |")
        lines.append("")
    worst = [r for r in ratios if r["instr"] > 1.2]
    lines += ["## Summary", "",
              f"{len(ratios)} problem × tolerance cases; auto above 1.2× the best by instructions in {len(worst)}: "
              + (", ".join(f"{r['problem']} {r['tol']} ({r['instr']:.2f}×)" for r in worst) or "none") + ".", ""]
    pathlib.Path(args.out).write_text("\n".join(lines))
    pathlib.Path(args.json).write_text(json.dumps({"rows": rows, "baseline": base, "ratios": ratios}, indent=1))
    print(f"wrote {args.out} and {args.json}", file=sys.stderr)


if __name__ == "__main__":
    main()
