"""flipcard's default absolute tolerance on stiff and non-stiff problems:
error, steps and f evaluations of `flipcard sim --format json` (no `--atol`)
for each problem × tolerance 1e-3 … 1e-10, radau and auto on the stiff
problems (benches/stiff_problems.py, references in stiff_reference.txt; E5
to 1e13 against SciPy Radau rtol 1e-13 on the form with y2 = y3 + y4
written out, y2 and y3 only), auto on the non-stiff ones (Kepler e = 0.9
over 10 periods, Lorenz to 10, the pendulum from 179.9° to 100, Van der Pol
mu = 10 to 100; error relative to each component's largest size, against
SciPy DOP853 at rtol 1e-13). Counts, not times: the machine may be shared.

    cargo build --release && cp target/release/flipcard /tmp/before   # on the old commit
    python3 benches/default_atol_sweep.py /tmp/before --out before.json
    python3 benches/default_atol_sweep.py target/release/flipcard --out after.json
    python3 benches/default_atol_sweep.py --compare before.json after.json

Not part of CI: SciPy is installed by hand.
"""

import sys, json, subprocess, math, pathlib, os, tempfile
import numpy as np
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from stiff_problems import deck_text, DECKS, read_fixture
from scipy.integrate import solve_ivp
ROOT = pathlib.Path(tempfile.mkdtemp())
ref = read_fixture()
# E5 to 1e13: reduced form, SciPy Radau rtol 1e-13 (BDF/LSODA agree on y2=y3 to 1e-11)
E5_13 = np.array([0.0, 8.861233521283275e-23, 8.861233521283275e-23, 0.0])
NONSTIFF = {
 "kepler": (["x","y","vx","vy"], ["vx","vy","-x/(x^2+y^2)^1.5","-y/(x^2+y^2)^1.5"], {}, [0.1,0.0,0.0,math.sqrt(19.0)], 20*math.pi),
 "lorenz": (["x","y","z"], ["s*(y-x)","x*(r-z)-y","x*y-b*z"], {"s":10.0,"r":28.0,"b":8.0/3.0}, [1.0,1.0,1.0], 10.0),
 "pendulum": (["th","w"], ["w","-sin(th)"], {}, [179.9*math.pi/180, 0.0], 100.0),
 "vdp10": (["x","v"], ["v","mu*(1-x^2)*v-x"], {"mu":10.0}, [2.0,0.0], 100.0),
}
def nonstiff_rhs(name):
    if name=="kepler":
        return lambda t,y: [y[2],y[3],-y[0]/(y[0]**2+y[1]**2)**1.5,-y[1]/(y[0]**2+y[1]**2)**1.5]
    if name=="lorenz":
        return lambda t,y: [10*(y[1]-y[0]), y[0]*(28-y[2])-y[1], y[0]*y[1]-8/3*y[2]]
    if name=="pendulum":
        return lambda t,y: [y[1], -math.sin(y[0])]
    return lambda t,y: [y[1], 10*(1-y[0]**2)*y[1]-y[0]]
def deck(name, variables, equations, params, y0, dur):
    q = lambda xs: "[" + ", ".join(f'"{x}"' for x in xs) + "]"
    lines = ["[deck]", f'id = "{name}"', "title = 'T'", 'languages = ["en"]', "", "[[card]]", 'id = "c"', "front = 'F'", "back = 'B'", "",
             "[[scene]]", 'id = "s"', f"variables = {q(variables)}", "initial = [" + ", ".join(repr(float(v)) for v in y0) + "]"]
    if params: lines.append("params = { " + ", ".join(f"{k} = {v!r}" for k, v in params.items()) + " }")
    lines += [f"equations = {q(equations)}", f"duration = {dur!r}", 'show = ["plot"]', f'plot = ["{variables[0]}"]', ""]
    return "\n".join(lines)
def write(name, text):
    d = ROOT / name
    (d / "decks").mkdir(parents=True, exist_ok=True)
    (d / "content" / name).mkdir(parents=True, exist_ok=True)
    (d / "content" / name / "en.toml").write_text("")
    (d / "decks" / f"{name}.toml").write_text(text)
    return d / "decks" / f"{name}.toml"
cases = {}
for name in ["hires","oregonator","e5","robertson","van-der-pol-1e4","linear"]:
    cases[name] = (write(name, deck_text(name)), DECKS[name][0], ref[name], None)
t = deck_text("e5").replace("duration = 100000.0", "duration = 1e13").replace('id = "e5"', 'id = "e5-1e13"')
cases["e5-1e13"] = (write("e5-1e13", t), DECKS["e5"][0], E5_13, np.array([1e-300, 1, 1, 1e-300]))
nsref = {}
for name,(v,e,p,y0,dur) in NONSTIFF.items():
    if name not in nsref:
        s = solve_ivp(nonstiff_rhs(name), (0,dur), y0, method="DOP853", rtol=1e-13, atol=1e-15, dense_output=False)
        nsref[name] = {"end": list(s.y[:,-1]), "amp": list(np.max(np.abs(s.y),axis=1))}
    cases[name] = (write(name, deck(name,v,e,p,y0,dur)), v, np.array(nsref[name]["end"]), np.array(nsref[name]["amp"]))
def runone(binary, case, method, tol, env):
    path, names, r, amp = cases[case]
    proc = subprocess.run([binary, "sim", "--deck", str(path), "--scene", "s", "--method", method, "--tol", tol,
                           "--samples", "2", "--format", "json"], capture_output=True, text=True, env={**os.environ, **env}, timeout=600)
    try:
        out = json.loads(proc.stdout)
    except Exception:
        return {"fail": (proc.stderr or proc.stdout)[:300], "rc": proc.returncode}
    if proc.returncode != 0:
        return {"fail": str(out.get("error"))[:300], "rc": proc.returncode}
    y = np.array([out["samples"][-1][n] for n in names])
    if amp is None:
        err = float(np.max(np.abs(y - r) / np.abs(r)))
    elif case == "e5-1e13":
        err = float(np.max(np.abs(y[1:3] - r[1:3]) / np.abs(r[1:3])))
        err = {"rel23": err, "y1": float(y[0]), "y4": float(y[3])}
    else:
        err = float(np.max(np.abs(y - r) / amp))
    st = out["stats"]
    return {"err": err, "steps": st["steps"], "rej": st["rejected"], "nfev": st["rhs_evals"], "y": list(map(float,y))}
def compare(before, after):
    b, a = json.loads(pathlib.Path(before).read_text()), json.loads(pathlib.Path(after).read_text())
    print("| problem | method | tol | before error | steps | f evals | after error | steps | f evals | steps after/before |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for k, ra in a.items():
        c, m, t = k.split("|")
        rb = b.get(k, {"fail": "missing"})
        def cell(r):
            if "fail" in r:
                return ["refused", "", ""]
            e = r["err"]["rel23"] if isinstance(r["err"], dict) else r["err"]
            return [f"{e:.2e}", str(r["steps"]), str(r["nfev"])]
        ratio = f"{ra['steps'] / rb['steps']:.2f}" if "fail" not in ra and "fail" not in rb else "—"
        print(f"| {c} | {m} | {t} | " + " | ".join(cell(rb) + cell(ra)) + f" | {ratio} |")


if __name__ == "__main__":
    import argparse
    a = argparse.ArgumentParser()
    a.add_argument("binary", nargs="?"); a.add_argument("--compare", nargs=2); a.add_argument("--cases", default=",".join(cases)); a.add_argument("--tols", default="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10")
    a.add_argument("--methods", default="radau,auto"); a.add_argument("--env", default=""); a.add_argument("--out")
    args = a.parse_args()
    if args.compare:
        compare(*args.compare)
        sys.exit()
    env = dict(kv.split("=") for kv in args.env.split(",") if kv)
    res = {}
    for c in args.cases.split(","):
        ms = ["auto"] if c in NONSTIFF else args.methods.split(",")
        for m in ms:
            for tol in args.tols.split(","):
                r = runone(args.binary, c, m, tol, env)
                res[f"{c}|{m}|{tol}"] = r
                e = r.get("err"); 
                print(c, m, tol, r.get("fail", ""), e if not isinstance(e, float) else f"{e:.2e}", r.get("steps"), r.get("nfev"), flush=True)
    if args.out:
        pathlib.Path(args.out).write_text(json.dumps(res))
