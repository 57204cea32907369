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

With `--table` it writes instead the closing table of issue 26
(`benches/stiff_table.md`): for each problem of `TABLE` in
`benches/stiff_problems.py` (HIRES, the Oregonator, E5 to 1e5, Robertson,
Van der Pol at mu = 1e4, the linear system with eigenvalues -1 and -1e8, the
200-variable Brusselator) and each tolerance 1e-3, 1e-6, 1e-8, 1e-10: the
achieved error, steps and CPU time of flipcard's whole process (`flipcard sim
--method radau|auto --format json` on the problem as a deck scene, with
SciPy's absolute tolerance as `--atol`, on E5 with flipcard's default; time
from the child's rusage) and of SciPy's Radau and
BDF solve alone (process CPU time, best of several runs), then SciPy's time at
flipcard radau's achieved error, read off a finer sweep (1e-3 … 1e-10).

    cargo build --release
    python3 benches/compare_scipy_stiff.py --table [--flipcard target/release/flipcard] \
        [--diffsol FILE]

The table also has diffsol (version from Cargo.lock; BDF and ESDIRK34, dense
nalgebra LU, the Jacobian given as Jacobian-vector products) on the same
problems, tolerances and references, in-process beside flipcard's Radau
in-process: `cargo bench --bench stiff -- --json` prints those runs (one
JSON object a line), which the script runs itself unless `--diffsol` names
a file of its output; diffsol's CPU time at flipcard's in-process error
(read off its sweep 1e-3 … 1e-10) over flipcard's is its equal-error ratio.

Not part of CI: SciPy is installed by hand.
"""

import argparse
import json
import math
import os
import pathlib
import platform
import resource
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np

from scipy.integrate import solve_ivp

from stiff_problems import PROBLEMS, TABLE, deck_text, max_rel_error, read_fixture

ROOT = pathlib.Path(__file__).resolve().parent.parent
BRUSS = ROOT / "tests" / "fixtures" / "brusselator"
TABLE_TOLS = ["1e-3", "1e-6", "1e-8", "1e-10"]
SWEEP = [10.0 ** -k for k in range(3, 11)]

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


def cpu_best(f, budget=1.0):
    """(best process CPU seconds of f(), its last result), within a budget."""
    best, out, start, runs = math.inf, None, time.process_time(), 0
    while runs < 1 or (time.process_time() - start < budget and runs < 20):
        t0 = time.process_time()
        out = f()
        best = min(best, time.process_time() - t0)
        runs += 1
    return best, out


def bruss():
    """The Brusselator of tests/fixtures/brusselator as (f, jac, span, y0,
    reference, variable names)."""
    sys.path.insert(0, str(BRUSS))
    import make  # noqa: E402

    make.np = np
    rows = (BRUSS / "reference.csv").read_text().splitlines()[1:]
    ref = np.array([float(r.split(",")[1]) for r in rows])
    names = [f"u{i}" for i in range(1, make.N + 1)] + [f"v{i}" for i in range(1, make.N + 1)]
    return make.rhs, make.jac, (0.0, make.T_END), make.initial(), ref, names


def flipcard_table_run(binary, deck, method, tol, names, ref, atol=None, runs=3):
    """(error, steps, best CPU seconds) of `flipcard sim` on scene `s`, or
    the reason it failed; `atol` (one per variable) is given as `--atol`,
    else the run keeps flipcard's default."""
    best, err, steps = math.inf, None, None
    extra = [] if atol is None else ["--atol", ",".join(f"{n}={a!r}" for n, a in zip(names, atol))]
    for _ in range(runs):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run(
            [binary, "sim", "--deck", str(deck), "--scene", "s", "--method", method, "--tol", tol,
             "--samples", "2", "--format", "json", *extra],
            capture_output=True, text=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        out = json.loads(proc.stdout)
        if proc.returncode != 0:
            return out.get("error") or proc.stderr.strip()
        last = out["samples"][-1]
        y = np.array([last[n] for n in names])
        err, steps, best = max_rel_error(y, ref), out["stats"]["steps"], min(best, cpu)
    return err, steps, best


def scipy_table_run(fun, jac, span, y0, atol, method, rtol, ref):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run_once = lambda: solve_ivp(fun, span, y0, method=method, rtol=rtol, atol=atol(rtol), jac=jac)  # noqa: E731
        secs, sol = cpu_best(run_once)
    if not sol.success:
        return sol.message
    return max_rel_error(sol.y[:, -1], ref), len(sol.t) - 1, secs


def diffsol_runs(path):
    """(problem, method, rtol string) -> (error, steps, seconds) or the reason
    it failed, from `cargo bench --bench stiff -- --json` (run here unless
    `path` names a file of its output)."""
    if path:
        text = pathlib.Path(path).read_text()
    else:
        print("cargo bench --bench stiff -- --json", file=sys.stderr, flush=True)
        text = subprocess.run(["cargo", "bench", "--quiet", "--bench", "stiff", "--", "--json"], cwd=ROOT,
                              capture_output=True, text=True, check=True).stdout
    out = {}
    for line in text.splitlines():
        if not line.startswith("{"):
            continue
        r = json.loads(line)
        key = (r["problem"], r["method"], f"{r['rtol']:.0e}".replace("e-0", "e-"))
        out[key] = r["failed"] if "failed" in r else (r["error"], r["steps"], r["ms"] / 1e3)
    return out


def diffsol_version():
    lock = (ROOT / "Cargo.lock").read_text()
    i = lock.index('name = "diffsol"\n')
    return lock[i:].splitlines()[1].split('"')[1]


def fmt(r):
    if isinstance(r, str):
        return "failed", "", ""
    e, steps, secs = r
    return f"{e:.1e}", f"{steps:,}", f"{secs * 1e3:.2f}" if secs < 0.01 else f"{secs * 1e3:.1f}"


def table(binary, out_path, diffsol_path=None):
    reference = read_fixture()
    load = os.getloadavg()
    diffsol = diffsol_runs(diffsol_path)
    lines = [
        "# Stiff problems: flipcard against SciPy, problem × tolerance",
        "",
        "Written by `python3 benches/compare_scipy_stiff.py --table` (after `cargo build --release`);",
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {platform.machine()}, {os.cpu_count()} cores,",
        f"load average {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} at the start (a shared machine: times are",
        "CPU seconds of the process, not wall time).",
        "",
        "- **error**: the largest relative error of a component of the final state against the",
        "  reference named under each problem.",
        "- **flipcard**: the whole process (`flipcard sim --method radau|auto --tol T --samples 2",
        "  --format json --atol …` on the problem written as a deck scene, with SciPy's absolute",
        "  tolerance; on E5 with none, so each variable's follows its size, and on the others",
        "  the default's radau errors are listed under the table): its steps from the JSON `stats`, its",
        "  CPU time (user + system, best of 3) from the child's rusage, parsing and compiling the",
        "  deck included.",
        "- **SciPy** " + f"{__import__('scipy').__version__}: `solve_ivp` with the analytic Jacobian and the absolute",
        "  tolerance of `benches/stiff_problems.py`; CPU time of the solve alone, best of several.",
        "- **at equal error**: SciPy's CPU time at the error flipcard's radau reached, read off a",
        "  sweep of rtol 1e-3 … 1e-10 by log-log interpolation (— where that error lies outside",
        "  the sweep), and the ratio to flipcard's whole process.",
        f"- **diffsol** {diffsol_version()} (Rust; BDF and ESDIRK34, dense nalgebra LU, the analytic",
        "  Jacobian given as Jacobian-vector products, from which it assembles the matrix):",
        "  `cargo bench --bench stiff -- --json`, in-process, with SciPy's absolute tolerance (E5's",
        "  too), beside flipcard's Radau in the same process on the same Rust right-hand side and",
        "  Jacobian; CPU time of the solve alone (thread CPU time, best of 3–20 runs). Its",
        "  equal-error ratio: diffsol's time at flipcard's in-process error, read off its sweep",
        "  1e-3 … 1e-10, over flipcard's. A diffsol run is stopped after 200,000 steps. In process",
        "  flipcard's Radau is given no sparsity pattern, so on the Brusselator it factors dense 200×200",
        "  matrices as diffsol does (the app's deck path factors them banded: its whole-process time",
        "  is in the first table).",
        "",
    ]
    notes = {
        "hires": "HIRES, t ∈ [0, 321.8122]. Reference: SciPy Radau rtol 1e-12 (BDF, LSODA within 2.5e-11).",
        "oregonator": "Oregonator, t ∈ [0, 360]. Reference: SciPy Radau rtol 1e-12 (BDF, LSODA within 6.6e-10).",
        "e5": "E5 to t = 1e5, default absolute tolerance. Reference: SciPy Radau rtol 1e-13 with y2 = y3 + y4 "
        "written out (BDF, LSODA within 4.8e-11). Below ~1e-9 no double-precision run of the "
        "four-variable form can go (docs/deck-format.md, \"How far a tolerance goes\").",
        "robertson": "Robertson to t = 1e11. Reference: SciPy Radau rtol 1e-12 (BDF, LSODA within 7.5e-11). "
        "flipcard's default absolute tolerance (the line under the table) follows y1 and y2 down as they "
        "decay (y1 to 2e-8, y2 to 8e-14), each at its recent size.",
        "van-der-pol-1e4": "Van der Pol, mu = 1e4, (2, 0), t ∈ [0, 2e4]. Reference: SciPy Radau rtol 1e-12 "
        "(LSODA within 3.2e-10; BDF fails).",
        "linear": "y' = A y, eigenvalues −1 and −1e8, y(0) = (2, 0), t ∈ [0, 10]. Reference: the closed form "
        "e^−t (1, 1) + e^(−1e8 t) (1, −1).",
        "brusselator": "Brusselator, 200 variables, t ∈ [0, 10] (tests/fixtures/brusselator). Reference: "
        "SciPy Radau rtol 1e-10, atol 1e-12, checked against BDF; errors below ~1e-9 are the reference's.",
    }
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        for name in TABLE:
            print(name, file=sys.stderr, flush=True)
            if name == "brusselator":
                fun, jac, span, y0, ref, names = bruss()
                deck = BRUSS / "decks" / "bruss.toml"
                text = deck.read_text().replace('id = "bruss"\nvariables', 'id = "s"\nvariables')
                (tmp / "decks").mkdir(exist_ok=True)
                (tmp / "content" / "bruss").mkdir(parents=True, exist_ok=True)
                (tmp / "content" / "bruss" / "en.toml").write_text("")
                deck = tmp / "decks" / "bruss.toml"
                deck.write_text(text)
                atol = lambda r: 1e-2 * r  # noqa: E731
            else:
                fun, jac, span, y0, atol = PROBLEMS[name]
                ref, names = reference[name], None
                (tmp / "decks").mkdir(exist_ok=True)
                (tmp / "content" / name).mkdir(parents=True, exist_ok=True)
                (tmp / "content" / name / "en.toml").write_text("")
                deck = tmp / "decks" / f"{name}.toml"
                deck.write_text(deck_text(name))
                names = __import__("stiff_problems").DECKS[name][0]
            lines += [f"## {name}", "", notes[name], ""]
            lines += [
                "| tol | flipcard radau error | steps | ms | flipcard auto error | steps | ms "
                "| SciPy Radau error | steps | ms | SciPy BDF error | steps | ms |",
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
            ]
            radau_points = []
            # flipcard gets SciPy's absolute tolerance, except on E5, run as
            # a user would (each variable's follows its size).
            same = name != "e5"
            for tol in TABLE_TOLS:
                a = [float(v) for v in np.broadcast_to(atol(float(tol)), (len(names),))] if same else None
                fr = flipcard_table_run(binary, deck, "radau", tol, names, ref, a)
                fa = flipcard_table_run(binary, deck, "auto", tol, names, ref, a)
                sr = scipy_table_run(fun, jac, span, y0, atol, "Radau", float(tol), ref)
                sb = scipy_table_run(fun, jac, span, y0, atol, "BDF", float(tol), ref)
                if not isinstance(fr, str):
                    radau_points.append((tol, fr))
                cells = [c for r in (fr, fa, sr, sb) for c in fmt(r)]
                lines.append(f"| {tol} | " + " | ".join(cells) + " |")
                for who, r in (("flipcard radau", fr), ("flipcard auto", fa), ("SciPy Radau", sr), ("SciPy BDF", sb)):
                    if isinstance(r, str):
                        lines.append(f"|  | {who} at {tol}: {r} |")
            if same:
                cells = []
                for tol in TABLE_TOLS:
                    r = flipcard_table_run(binary, deck, "radau", tol, names, ref, runs=1)
                    cells.append(f"{tol} → " + (f"failed ({r})" if isinstance(r, str) else f"{r[0]:.1e} ({r[1]:,} steps)"))
                lines += ["", "flipcard radau with its default absolute tolerance instead (each variable's follows its "
                          "size): " + "; ".join(cells) + "."]
            # SciPy at flipcard radau's error.
            sweeps = {}
            for method in ("Radau", "BDF"):
                pts = []
                for rtol in SWEEP:
                    r = scipy_table_run(fun, jac, span, y0, atol, method, rtol, ref)
                    if not isinstance(r, str):
                        pts.append((r[0], r[2]))
                sweeps[method] = pts
            lines += ["", "At equal error (flipcard radau's): SciPy's CPU time and its ratio to flipcard's whole process.", ""]
            lines += ["| flipcard tol | error | flipcard ms | SciPy Radau ms | ratio | SciPy BDF ms | ratio |", "|---|---|---|---|---|---|---|"]
            for tol, (e, _, secs) in radau_points:
                cells = []
                for method in ("Radau", "BDF"):
                    t = time_at_error(sweeps[method], e)
                    cells += ["—", "—"] if t is None else [f"{t * 1e3:.1f}", f"{t / secs:.1f}×"]
                lines.append(f"| {tol} | {e:.1e} | {secs * 1e3:.1f} | " + " | ".join(cells) + " |")
            lines += ["", "In-process (`cargo bench --bench stiff -- --json`): diffsol against flipcard's Radau "
                      "on the same Rust right-hand side, CPU ms of the solve alone.", ""]
            lines += ["| tol | flipcard radau error | steps | ms | diffsol BDF error | steps | ms "
                      "| diffsol ESDIRK34 error | steps | ms |", "|---|---|---|---|---|---|---|---|---|---|"]
            who = ("flipcard-radau", "diffsol-bdf", "diffsol-esdirk34")
            for tol in TABLE_TOLS:
                rs = [diffsol.get((name, m, tol), "not run") for m in who]
                lines.append(f"| {tol} | " + " | ".join(c for r in rs for c in fmt(r)) + " |")
                for m, r in zip(who, rs):
                    if isinstance(r, str):
                        lines.append(f"|  | {m} at {tol}: {r} |")
            lines += ["", "At equal error (flipcard's in-process radau's): diffsol's CPU time and its ratio to "
                      "flipcard's.", ""]
            lines += ["| flipcard tol | error | flipcard ms | diffsol BDF ms | ratio | diffsol ESDIRK34 ms | ratio |",
                      "|---|---|---|---|---|---|---|"]
            for tol in TABLE_TOLS:
                ours = diffsol.get((name, "flipcard-radau", tol))
                if not isinstance(ours, tuple):
                    continue
                e, _, secs = ours
                cells = []
                for m in who[1:]:
                    pts = [(r[0], r[2]) for (n, mm, _), r in diffsol.items()
                           if n == name and mm == m and isinstance(r, tuple)]
                    t = time_at_error(pts, e)
                    cells += ["—", "—"] if t is None else [f"{t * 1e3:.2f}", f"{t / secs:.1f}×"]
                lines.append(f"| {tol} | {e:.1e} | {secs * 1e3:.2f} | " + " | ".join(cells) + " |")
            lines.append("")
    out_path.write_text("\n".join(lines))
    print(f"wrote {out_path}", file=sys.stderr)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    for name in PROBLEMS:
        parser.add_argument(f"--{name}-ms", type=float, help="flipcard's time (ms) at rtol 1e-6")
        parser.add_argument(f"--{name}-error", type=float, help="flipcard's error at rtol 1e-6")
    parser.add_argument("--rtols", default="1e-4,1e-5,1e-6,1e-7,1e-8,1e-9")
    parser.add_argument("--only", help="comma-separated problem names")
    parser.add_argument("--table", action="store_true", help="write benches/stiff_table.md (issue 26's table)")
    parser.add_argument("--flipcard", default=str(ROOT / "target" / "release" / "flipcard"))
    parser.add_argument("--out", default=str(ROOT / "benches" / "stiff_table.md"))
    parser.add_argument("--diffsol", help="a file of `cargo bench --bench stiff -- --json` output (else run here)")
    args = parser.parse_args()
    if args.table:
        table(args.flipcard, pathlib.Path(args.out), args.diffsol)
        return
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
