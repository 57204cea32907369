#!/usr/bin/env python3
"""Recompute every numeric claim of the `oscillations` deck with SciPy.

Reads the deck itself (decks/oscillations.toml), its explanation files
(content/oscillations/*.toml) and the list of claims
(tests/golden/oscillations_claims.json), then

1. compiles each scene's equations and observables from the expression
   strings written in the deck (the flipcard expression syntax translated
   token by token to NumPy; an unknown name is an error),
2. integrates each scene with solve_ivp at tight tolerances: DOP853, checked
   against Radau, or Radau alone for a stiff scene,
3. computes each prompt's measure exactly as flipcard defines it
   (max, min, final, mean, crossings, period, drift) and checks the number
   answers against their tolerance and the choice answers (exactly one
   `when` holds, it is the expected choice, and not at the edge of its
   threshold),
4. checks that the claims file lists every prompt with the deck's own values,
   that every text claim's number really is written in its card or section
   (in every language), and that the simulation confirms it,
5. recomputes the formula values the texts state (elliptic integrals, the
   Van der Pol asymptotics, resonance formulas) from the formulas.

Prints one table row per claim: claim, deck value, computed value, verdict.
Exit status 0 when everything passes, 1 on any mismatch.

    python3 tests/golden/oscillations_check.py [--quick]

`--quick` skips the slow demonstration (DOP853 on the stiff scene, ~5 min).
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import ellipk

ROOT = Path(__file__).resolve().parents[2]
DECK_ID = "oscillations"
DECK = ROOT / "decks" / f"{DECK_ID}.toml"
CONTENT = ROOT / "content" / DECK_ID
CLAIMS = ROOT / "tests" / "golden" / f"{DECK_ID}_claims.json"

RTOL, ATOL = 1e-11, 1e-12          # DOP853
RTOL_RADAU, ATOL_RADAU = 1e-10, 1e-12
STIFF_PRODUCT = 1e5                # max |eigenvalue| * duration above this: stiff
SAMPLES_PER_UNIT = 400             # uniform samples per unit of scene time
MAX_SAMPLES = 400_001
MIN_MARGIN_REL = 0.02              # a choice threshold must be 2% away
COARSE = 501                       # every verdict must also hold on this many samples

FAILURES: list[str] = []


def fail(msg: str) -> None:
    FAILURES.append(msg)


# ---------------------------------------------------------------------------
# Expressions: flipcard syntax -> NumPy
# ---------------------------------------------------------------------------

FUNCS = {
    "sin": "np.sin", "cos": "np.cos", "tan": "np.tan",
    "asin": "np.arcsin", "acos": "np.arccos", "atan": "np.arctan",
    "atan2": "np.arctan2", "sinh": "np.sinh", "cosh": "np.cosh",
    "tanh": "np.tanh", "exp": "np.exp", "ln": "np.log", "log10": "np.log10",
    "sqrt": "np.sqrt", "abs": "np.abs", "sign": "np.sign",
    "min": "np.minimum", "max": "np.maximum",
}
CONSTS = {"pi": "np.pi", "e": "np.e"}
TOKEN = re.compile(
    r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<op>[-+*/^(),]))"
)


def translate(expr: str, variables: list[str], params: dict, observables: dict[str, str]) -> str:
    """Translate one expression; `observables` holds the already translated
    observables defined before this one (inlined in parentheses)."""
    out, pos = [], 0
    expr = expr.rstrip()
    tokens = []
    while pos < len(expr):
        m = TOKEN.match(expr, pos)
        if not m or m.end() == pos:
            raise ValueError(f"cannot read {expr[pos:]!r} in {expr!r}")
        pos = m.end()
        tokens.append(m)
    for i, m in enumerate(tokens):
        nxt = tokens[i + 1].group("op") if i + 1 < len(tokens) else None
        if m.group("num"):
            out.append(m.group("num"))
        elif m.group("op"):
            op = m.group("op")
            if op == "^":
                # flipcard's ^ is right-associative like Python's **; the deck
                # never chains powers or writes a sign right after ^, so the
                # two precedences cannot differ.
                following = tokens[i + 1] if i + 1 < len(tokens) else None
                if following is not None and following.group("op") in ("-", "+"):
                    raise ValueError(f"sign right after ^ in {expr!r}: write parentheses")
                out.append("**")
            else:
                out.append(op)
        else:
            name = m.group("name")
            if nxt == "(":
                if name not in FUNCS:
                    raise ValueError(f"unknown function {name!r} in {expr!r}")
                out.append(FUNCS[name])
            elif name in variables:
                out.append(f"Y[{variables.index(name)}]")
            elif name in params:
                out.append(f"({float(params[name])!r})")
            elif name in observables:
                out.append(f"({observables[name]})")
            elif name == "t":
                out.append("t")
            elif name in CONSTS:
                out.append(CONSTS[name])
            else:
                raise ValueError(f"unknown name {name!r} in {expr!r}")
    src = " ".join(out)
    compile(src, "<expr>", "eval")  # syntax check
    return src


class Scene:
    def __init__(self, raw: dict):
        self.raw = raw
        self.id = raw["id"]
        self.variables = list(raw["variables"])
        self.initial = [float(v) for v in raw["initial"]]
        self.params = dict(raw.get("params", {}))
        self.duration = float(raw["duration"])
        if len(self.initial) != len(self.variables):
            raise ValueError(f"scene {self.id}: {len(self.initial)} initial values for {len(self.variables)} variables")
        if len(raw["equations"]) != len(self.variables):
            raise ValueError(f"scene {self.id}: equations and variables differ in number")
        for name in list(self.params) + list(raw.get("observables", {})):
            if name in self.variables or name in FUNCS or name in CONSTS or name == "t":
                raise ValueError(f"scene {self.id}: name {name!r} is taken")
        self.obs_src: dict[str, str] = {}
        for name, expr in raw.get("observables", {}).items():
            if name in self.params or name in self.obs_src:
                raise ValueError(f"scene {self.id}: observable {name!r} defined twice")
            self.obs_src[name] = translate(expr, self.variables, self.params, self.obs_src)
        eqs = [translate(e, self.variables, self.params, {}) for e in raw["equations"]]
        self._rhs = eval(f"lambda t, Y: [{', '.join(eqs)}]", {"np": np})
        self._obs = {n: eval(f"lambda t, Y: {src}", {"np": np}) for n, src in self.obs_src.items()}
        # every name shown must exist
        known = set(self.variables) | set(self.obs_src)
        for key in ("plot", "phase", "conserved"):
            for name in raw.get(key, []):
                if name not in known:
                    raise ValueError(f"scene {self.id}: {key} names unknown {name!r}")
        for item in raw.get("sketch", []):
            for exprs in item.values():
                for e in exprs:
                    translate(e, self.variables, self.params, self.obs_src)
        self.samples = None

    def rhs(self, t, y):
        return np.array(self._rhs(t, y), dtype=float)

    def jacobian_scale(self) -> float:
        y = np.array(self.initial)
        f0 = self.rhs(0.0, y)
        n = len(y)
        J = np.zeros((n, n))
        for j in range(n):
            h = 1e-7 * max(1.0, abs(y[j]))
            yp = y.copy()
            yp[j] += h
            J[:, j] = (self.rhs(0.0, yp) - f0) / h
        return float(np.max(np.abs(np.linalg.eigvals(J))))

    def run(self):
        """Integrate once; return the fine sample grid (t, Y)."""
        if self.samples is not None:
            return self.samples
        stiff = self.jacobian_scale() * self.duration > STIFF_PRODUCT
        n = int(min(MAX_SAMPLES, max(20_001, SAMPLES_PER_UNIT * self.duration + 1)))
        t = np.linspace(0.0, self.duration, n)
        runs = {}
        methods = ["Radau"] if stiff else ["DOP853", "Radau"]
        for method in methods:
            rtol, atol = (RTOL, ATOL) if method == "DOP853" else (RTOL_RADAU, ATOL_RADAU)
            sol = solve_ivp(self.rhs, (0.0, self.duration), self.initial, method=method,
                            rtol=rtol, atol=atol, dense_output=True)
            if sol.status != 0:
                raise RuntimeError(f"scene {self.id}: {method} failed: {sol.message}")
            runs[method] = sol
        self.method = methods[0]
        self.stiff = stiff
        self.sol = runs[methods[0]]
        self.nfev = self.sol.nfev
        self.samples = (t, self.sol.sol(t))
        self.cross = runs["Radau"].sol(t) if len(runs) == 2 else None
        return self.samples

    def grid(self, n: int | None = None):
        """The fine grid, or `n` uniform samples of the same run."""
        t, Y = self.run()
        if n is None:
            return t, Y
        tc = np.linspace(0.0, self.duration, n)
        return tc, self.sol.sol(tc)

    def series(self, name: str, n: int | None = None) -> np.ndarray:
        t, Y = self.grid(n)
        if name in self.variables:
            return Y[self.variables.index(name)]
        if name in self._obs:
            return np.broadcast_to(np.asarray(self._obs[name](t, Y), dtype=float), t.shape)
        raise KeyError(f"scene {self.id} has no variable or observable {name!r}")


# ---------------------------------------------------------------------------
# Measures, exactly as flipcard defines them for system scenes
# ---------------------------------------------------------------------------

MEASURE = re.compile(r"^\s*(max|min|final|mean|crossings|period|drift)\(\s*([A-Za-z_][A-Za-z0-9_]*)\s*\)\s*$")
CONDITION = re.compile(r"^\s*(.+?\))\s*(==|!=|<=|>=|<|>)\s*([-+0-9.eE]+)\s*$")


def sign_changes(x: np.ndarray) -> int:
    """Sign changes over the run; samples exactly at zero have no sign and
    are skipped (no verdict of this deck depends on how they count)."""
    s = np.sign(x)
    s = s[s != 0]
    return int(np.count_nonzero(s[1:] != s[:-1]))


def upward_crossings(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    level = 0.5 * (float(np.min(x)) + float(np.max(x)))
    i = np.nonzero((x[:-1] < level) & (x[1:] >= level))[0]
    return t[i] + (level - x[i]) * (t[i + 1] - t[i]) / (x[i + 1] - x[i])


def measure_series(kind: str, t: np.ndarray, x: np.ndarray) -> float:
    if kind == "max":
        return float(np.max(x))
    if kind == "min":
        return float(np.min(x))
    if kind == "final":
        return float(x[-1])
    if kind == "mean":
        return float(np.trapezoid(x, t) / (t[-1] - t[0]))
    if kind == "crossings":
        return float(sign_changes(x))
    if kind == "period":
        up = upward_crossings(t, x)
        if len(up) < 2:
            raise ValueError("period refused: fewer than two upward crossings")
        return float(np.mean(np.diff(up)))
    if kind == "drift":
        return float(np.max(np.abs(x - x[0])) / max(abs(x[0]), 1e-300))
    raise ValueError(kind)


def measure(scene: Scene, text: str, n: int | None = None) -> tuple[float, str, np.ndarray]:
    """A measure over the run, on the fine grid or on `n` samples."""
    m = MEASURE.match(text)
    if not m:
        raise ValueError(f"not a system-scene measure: {text!r}")
    kind, name = m.groups()
    t, _ = scene.grid(n)
    x = scene.series(name, n)
    return measure_series(kind, t, x), kind, x


def compare(value: float, op: str, thr: float) -> bool:
    return {"==": value == thr, "!=": value != thr, "<": value < thr,
            "<=": value <= thr, ">": value > thr, ">=": value >= thr}[op]


def within(expected: float, measured: float, tol: dict) -> bool:
    if "abs" in tol:
        return abs(expected - measured) <= tol["abs"]
    return abs(expected - measured) <= tol["rel"] * abs(measured)


def margin_note(kind: str, x: np.ndarray, value: float, thr: float) -> tuple[bool, str]:
    """Is the verdict of a holding condition clear of its threshold?"""
    if kind == "crossings":
        big = float(np.max(np.abs(x)))
        if value == 0:
            m = float(np.min(np.abs(x))) / big
            return m >= 0.05, f"never within {m:.0%} of max|N| of zero"
        lo, hi = float(np.min(x)) / big, float(np.max(x)) / big
        ok = lo <= -0.05 and hi >= 0.05
        return ok, f"{int(value)} sign changes, swings {lo:+.2f}..{hi:+.2f} of max|N|"
    if thr != 0:
        rel = abs(value - thr) / abs(thr)
        return rel >= MIN_MARGIN_REL, f"{rel:.1%} from the threshold"
    big = float(np.max(np.abs(x)))
    rel = abs(value) / big if big > 0 else 0.0
    return rel >= 1e-3, f"{rel:.1%} of max|N| from 0"


# ---------------------------------------------------------------------------
# Output
# ---------------------------------------------------------------------------

ROWS: list[tuple[str, str, str, str]] = []


def row(claim: str, deck: str, computed: str, ok: bool, why: str = "") -> None:
    ROWS.append((claim, deck, computed, "pass" if ok else "FAIL"))
    if not ok:
        fail(f"{claim}: deck {deck}, computed {computed} {why}".rstrip())


def fmt(v: float) -> str:
    if v == 0 or 1e-3 <= abs(v) < 1e5:
        return f"{v:.6g}"
    return f"{v:.4e}"


def tol_text(tol: dict) -> str:
    return f"±{tol['abs']:g}" if "abs" in tol else f"±{100 * tol['rel']:g}%"


def print_table() -> None:
    w = [max(len(r[i]) for r in ROWS + [("claim", "deck value", "computed", "verdict")]) for i in range(4)]
    head = ("claim", "deck value", "computed", "verdict")
    print("  ".join(h.ljust(w[i]) for i, h in enumerate(head)))
    print("  ".join("-" * w[i] for i in range(4)))
    for r in ROWS:
        print("  ".join(c.ljust(w[i]) for i, c in enumerate(r)))


# ---------------------------------------------------------------------------
# The checks
# ---------------------------------------------------------------------------

def collect_texts(node, langs: list[str], out: dict[str, list[str]]) -> None:
    """Every translatable text inside `node` (a table with one key per language)."""
    if isinstance(node, dict):
        if node and set(node) <= set(langs) and all(isinstance(v, str) for v in node.values()):
            for lang, text in node.items():
                out[lang].append(text)
            return
        for value in node.values():
            collect_texts(value, langs, out)
    elif isinstance(node, list):
        for value in node:
            collect_texts(value, langs, out)


def texts_of(deck: dict, sections, kind: str, ident: str, field: str | None = None) -> dict[str, str]:
    """The texts of a card, a prompt or a section, per language (only
    `field`, a dotted path such as `answer.formula`, when given)."""
    langs = deck["deck"]["languages"]
    if kind == "section":
        return {lang: sections[lang][ident]["title"] + "\n" + sections[lang][ident]["body"] for lang in langs}
    item = {c["id"]: c for c in deck.get(kind, [])}[ident]
    if field:
        for part in field.split("."):
            item = item[part]
    out: dict[str, list[str]] = {lang: [] for lang in langs}
    collect_texts(item, langs, out)
    return {lang: "\n".join(texts) for lang, texts in out.items()}


def plain(text: str) -> str:
    """A text with its math delimiters dropped, so that `$T = 2.041$ s`
    contains the number as written, `2.041 s`."""
    return text.replace("$", "")


def stated(deck, sections, where: list[tuple], name: str) -> None:
    """Each (kind, id, text): `text` is written there, in every language
    (`text` may be a table with one snippet per language)."""
    for kind, ident, text in where:
        for lang, body in texts_of(deck, sections, kind, ident).items():
            snippet = text[lang] if isinstance(text, dict) else text
            if snippet not in plain(body):
                fail(f"{name}: {snippet!r} is not in the {lang} text of {kind} {ident}")


def check_scenes(scenes: dict[str, Scene]) -> None:
    for s in scenes.values():
        t0 = time.time()
        t, Y = s.run()
        extra = ""
        if s.cross is not None:
            # the two integrators must agree on the whole run
            diff = float(np.max(np.abs(Y - s.cross)) / max(1.0, float(np.max(np.abs(Y)))))
            ok = diff < 1e-6
            row(f"scene {s.id}: DOP853 vs Radau", "agree", f"max diff {diff:.1e}", ok)
        for name in s.raw.get("conserved", []):
            d = measure_series("drift", t, s.series(name))
            row(f"scene {s.id}: drift({name})", "conserved", fmt(d), d < 1e-8)
        print(f"  ran {s.id}: {s.method}{' (stiff)' if s.stiff else ''}, {s.nfev} evaluations, "
              f"{len(t)} samples, {time.time() - t0:.1f} s{extra}", file=sys.stderr)


def check_prompts(deck: dict, scenes: dict[str, Scene]) -> dict[str, dict]:
    """Check every prompt; return what each one computed, by prompt id."""
    results = {}
    for p in deck.get("prompt", []):
        pid, ans = p["id"], p["answer"]
        scene = scenes[p["scene"]]
        if ans["kind"] == "number":
            value, _, _ = measure(scene, ans["measure"])
            coarse, _, _ = measure(scene, ans["measure"], COARSE)
            ok = within(ans["expected"], value, ans["tolerance"]) and within(ans["expected"], coarse, ans["tolerance"])
            used = abs(ans["expected"] - value) / (ans["tolerance"].get("abs") or ans["tolerance"]["rel"] * abs(value))
            row(f"prompt {pid}: {ans['measure']} [{scene.id}]",
                f"{fmt(ans['expected'])} {tol_text(ans['tolerance'])}",
                f"{fmt(value)} ({used:.0%} of tol; {COARSE} samples: {fmt(coarse)})", ok)
            results[pid] = {"measured": value, "coarse": coarse}
        else:
            holds, notes = [], []
            for c in ans["choices"]:
                m = CONDITION.match(c["when"])
                if not m:
                    fail(f"prompt {pid}: cannot read condition {c['when']!r}")
                    continue
                mtext, op, thr = m.group(1), m.group(2), float(m.group(3))
                try:
                    value, kind, x = measure(scene, mtext)
                except ValueError as err:
                    notes.append(f"{c['id']}: {err}")
                    continue
                if compare(value, op, thr):
                    holds.append(c["id"])
                    ok, note = margin_note(kind, x, value, thr)
                    notes.append(f"{mtext} = {fmt(value)} {op} {thr:g}: {note}")
                    if not ok:
                        fail(f"prompt {pid}: choice {c['id']} holds only at the edge ({note})")
            coarse_holds = []
            for c in ans["choices"]:
                m = CONDITION.match(c["when"])
                try:
                    value, _, _ = measure(scene, m.group(1), COARSE)
                except (ValueError, AttributeError):
                    continue
                if compare(value, m.group(2), float(m.group(3))):
                    coarse_holds.append(c["id"])
            if coarse_holds != holds:
                notes.append(f"on {COARSE} samples: {coarse_holds}")
            verdict = holds[0] if len(holds) == 1 else ("none" if not holds else "+".join(holds))
            row(f"prompt {pid}: choice [{scene.id}]", ans["expected"],
                f"{verdict} ({'; '.join(notes)})", holds == [ans["expected"]] and coarse_holds == holds)
            results[pid] = {"holds": holds}
    return results


def check_claims(deck: dict, sections, scenes: dict[str, Scene], claims: dict) -> None:
    prompts = {p["id"]: p for p in deck.get("prompt", [])}
    seen_prompts = set()
    ids = set()
    for c in claims["claims"]:
        cid = c["id"]
        if cid in ids:
            fail(f"claims: duplicate id {cid}")
        ids.add(cid)
        src = c["source"]
        scene = scenes.get(c["scene"])
        if scene is None:
            fail(f"claim {cid}: no scene {c['scene']!r}")
            continue
        if src["kind"] == "prompt" and "text" not in src:
            p = prompts.get(src["id"])
            if p is None:
                fail(f"claim {cid}: no prompt {src['id']!r}")
                continue
            seen_prompts.add(src["id"])
            ans = p["answer"]
            same = p["scene"] == c["scene"] and ans["kind"] == c["type"]
            if c["type"] == "number":
                same = same and ans["measure"] == c["measure"] and ans["expected"] == c["value"] \
                    and ans["tolerance"] == c["tolerance"]
            else:
                same = same and ans["expected"] == c["expected"] and \
                    [(ch["id"], ch["when"]) for ch in ans["choices"]] == \
                    [(ch["choice"], ch["when"]) for ch in c["conditions"]] and \
                    [ch["holds"] for ch in c["conditions"]] == [ch["id"] == ans["expected"] for ch in ans["choices"]]
            if not same:
                fail(f"claim {cid}: differs from prompt {src['id']} in the deck")
            row(f"claims file lists prompt {src['id']}", "as in deck", "same" if same else "DIFFERENT", same)
            continue
        # a number written in a card, prompt or section text
        texts = texts_of(deck, sections, src["kind"], src["id"], src.get("field"))
        for lang, text in texts.items():
            if src["text"] not in plain(text):
                fail(f"claim {cid}: {src['text']!r} is not in the {lang} text of {src['kind']} {src['id']}")
        value, _, _ = measure(scene, c["measure"])
        coarse, _, _ = measure(scene, c["measure"], COARSE)
        ok = within(c["value"], value, c["tolerance"]) and within(c["value"], coarse, c["tolerance"])
        row(f"text {src['kind']} {src['id']}: \"{src['text']}\" = {c['measure']} [{scene.id}]",
            f"{fmt(c['value'])} {tol_text(c['tolerance'])}", f"{fmt(value)} ({COARSE} samples: {fmt(coarse)})", ok)
    missing = set(prompts) - seen_prompts
    if missing:
        fail(f"claims file misses prompts: {sorted(missing)}")


def check_formulas(deck: dict, sections) -> None:
    """Numbers the texts derive from formulas rather than from a run: each is
    recomputed here, and checked to be written where the deck says it."""
    g, L = 9.81, 1.0
    w0 = math.sqrt(g / L)
    T0 = 2 * math.pi / w0

    def m_of(deg):
        return math.sin(math.radians(deg) / 2) ** 2

    def ratio(deg):
        return 2 * ellipk(m_of(deg)) / math.pi

    def series(deg):
        return 1 + math.radians(deg) ** 2 / 16

    def amp(r, zeta):  # steady amplitude / f0 at w = r w0
        return 1 / math.sqrt((1 - r * r) ** 2 + (2 * zeta * r) ** 2)

    c = 3 - 2 * math.log(2)
    airy = 2.338107410459767          # |first zero of Ai|
    settle_c = 1.0565265456055208     # (1 + w0 t) exp(-w0 t) = 0.01, w0 = 2π
    C, P, S = "card", "prompt", "section"
    F = [
        # name, stated, computed, tolerance, where it is written
        ("omega0 = sqrt(g/L) (rad/s)", 3.132, w0, 5e-4,
         [(S, "example-pendulum-numbers", "3.132 rad/s"), (P, "pendulum-170-period", "3.132")]),
        ("T0 = 2π sqrt(L/g) (s)", 2.006, T0, 5e-4,
         [(C, "small-angle-limit", "2.006 s"), (P, "pendulum-30-period", "2.006 s"),
          (P, "pendulum-90-period", "2.006 s"), (P, "pendulum-170-period", "2.006 s"),
          (S, "pendulum-exact", "2.006 s"), (S, "example-pendulum-numbers", "2.006 s")]),
        ("m = sin²(15°)", 0.0670, m_of(30), 5e-5, [(S, "example-pendulum-numbers", "0.0670")]),
        ("m = sin²(85°)", 0.9924, m_of(170), 5e-5,
         [(S, "example-pendulum-numbers", "0.9924"), (P, "pendulum-170-period", "0.9924")]),
        ("m = sin²(89.5°)", 0.99992, m_of(179), 5e-6, [(S, "example-pendulum-numbers", "0.99992")]),
        ("K at 30°", 1.5981, ellipk(m_of(30)), 5e-5, [(S, "example-pendulum-numbers", "1.5981")]),
        ("K at 90°", 1.8541, ellipk(m_of(90)), 5e-5, [(S, "example-pendulum-numbers", "1.8541")]),
        ("K at 170°", 3.8317, ellipk(m_of(170)), 5e-5, [(S, "example-pendulum-numbers", "3.8317")]),
        ("K at 179°", 6.1278, ellipk(m_of(179)), 5e-5, [(S, "example-pendulum-numbers", "6.1278")]),
        ("T/T0 at 30°", 1.0174, ratio(30), 5e-5,
         [(C, "period-series", "1.0174"), (P, "pendulum-30-period", "1.0174"),
          (S, "pendulum-exact", "1.0174"), (S, "example-pendulum-numbers", "1.0174")]),
        ("T/T0 at 90°", 1.1803, ratio(90), 5e-5,
         [(C, "period-90", "1.1803"), (S, "pendulum-exact", "1.1803"), (S, "example-pendulum-numbers", "1.1803")]),
        ("T/T0 at 170°", 2.4394, ratio(170), 5e-5,
         [(C, "period-170", "2.4394"), (P, "pendulum-170-period", "2.4394"),
          (S, "pendulum-exact", "2.4394"), (S, "example-pendulum-numbers", "2.4394")]),
        ("T/T0 at 179°", 3.901, ratio(179), 5e-4, [(S, "example-pendulum-numbers", "3.901")]),
        ("T/T0 at 170° (2.44 times)", 2.44, ratio(170), 5e-3,
         [(C, "mistake-isochronous", "2.44"), (S, "mistake-isochronous", "2.44")]),
        ("period excess at 30° (%)", 1.7, 100 * (ratio(30) - 1), 0.05,
         [(C, "period-30-why", "1.7%"), (C, "mistake-isochronous", "1.7%"),
          (S, "example-pendulum-numbers", "1.7%"), (S, "mistake-isochronous", "1.7%")]),
        ("period excess at 90° (%)", 18, 100 * (ratio(90) - 1), 0.5,
         [(C, "period-90", "18%"), (C, "mistake-isochronous", "18%"),
          (S, "example-pendulum-numbers", "18%"), (S, "mistake-isochronous", "18%")]),
        ("period excess at 10° (%)", 0.2, 100 * (ratio(10) - 1), 0.05, [(S, "mistake-isochronous", "0.2%")]),
        ("period excess at 20° below 1% (%)", 0.8, 100 * (ratio(20) - 1), 0.2, [(S, "example-pendulum-numbers", "1%")]),
        ("series 1 + θ²/16 at 30°", 1.017, series(30), 5e-4,
         [(C, "period-series", "1.017"), (P, "pendulum-30-period", "1.017"), (S, "example-pendulum-numbers", "1.017")]),
        ("series at 30° times T0 (s)", 2.040, T0 * series(30), 5e-4, [(P, "pendulum-30-period", "2.040")]),
        ("series 1 + θ²/16 at 90°", 1.154, series(90), 5e-4, [(S, "example-pendulum-numbers", "1.154")]),
        ("series at 90° short of exact (%)", 2, 100 * (1 - series(90) / ratio(90)), 0.5,
         [(S, "example-pendulum-numbers", "2%")]),
        ("30° in radians", 0.524, math.radians(30), 5e-4,
         [(C, "period-series", "0.524"), (P, "pendulum-30-period", "0.524"), (S, "example-pendulum-numbers", "0.524")]),
        ("sin θ short of θ at 30° (%)", 4.5, 100 * (1 - math.sin(math.radians(30)) / math.radians(30)), 0.05,
         [(C, "period-30-why", "4.5%"), (P, "pendulum-30-period", "4.5%"), (S, "example-pendulum-numbers", "4.5%")]),
        ("log estimate 4 ln(8/(π−θ0))/ω0 at 170° (s)", 4.89, 4 * math.log(8 / (math.pi - math.radians(170))) / w0, 5e-3,
         [(P, "pendulum-170-period", "4.89 s"), (S, "example-pendulum-numbers", "4.89 s"),
          (S, "pendulum-phase-portrait", "4.89 s")]),
        ("8/(π − 170°)", 45.8, 8 / (math.pi - math.radians(170)), 0.05, [(P, "pendulum-170-period", "45.8")]),
        ("each tenfold closer to the top adds 4 ln 10/ω0 (s)", 2.94, 4 * math.log(10) / w0, 5e-3,
         [(C, "period-near-top", "2.94 s"), (S, "pendulum-phase-portrait", "2.94 s")]),
        ("rigid rod over the top: 2 sqrt(g/L)", 6.26, 2 * w0, 5e-3,
         [(C, "over-the-top", "6.26 m/s"), (S, "pendulum-phase-portrait", "6.26 rad/s")]),
        ("string over the top: sqrt(5 g L) (m/s)", 7.0, math.sqrt(5 * g * L), 5e-2,
         [(C, "over-the-top", "7.0 m/s"), (S, "pendulum-phase-portrait", "7.0 m/s"), (P, "pendulum-over-the-top", "7 m/s")]),
        ("speed at the top after a 6.5 rad/s kick (rad/s)", 1.73, math.sqrt(6.5 ** 2 - 4 * g / L), 5e-3,
         [(S, "pendulum-phase-portrait", "1.73 rad/s")]),
        ("separatrix energy 2gL (J/kg)", 19.62, 2 * g * L, 5e-3, [(S, "pendulum-phase-portrait", "19.62 J/kg")]),
        ("tau = 1/(zeta w0), zeta = 0.05, w0 = 2π (s)", 3.183, 1 / (0.05 * 2 * math.pi), 5e-4,
         [(P, "damping-efold", "3.183 s"), (S, "damping", "3.18 s"), (S, "example-resonance-numbers", "3.18 s")]),
        ("Q/π cycles per e-fold, Q = 10", 3.2, 10 / math.pi, 5e-2,
         [(C, "q-cycles", "3.2"), (P, "damping-efold", "3.2"), (S, "damping", "3.2 cycles")]),
        ("exp(−π): amplitude left after 10 s at Q = 10", 0.043, math.exp(-math.pi), 5e-4, [(S, "damping", "0.043")]),
        ("omega_d below omega0 at zeta = 0.05 (%)", 0.125, 100 * (1 - math.sqrt(1 - 0.05 ** 2)), 5e-4,
         [(C, "damped-frequency", "0.125%"), (S, "damping", "0.125%")]),
        ("zeta = 3: slow rate w0 (zeta − sqrt(zeta²−1)) (1/s)", 1.08, 2 * math.pi * (3 - math.sqrt(8)), 5e-3,
         [(C, "overdamped-slow", "1.08")]),
        ("critical 1% settling time, w0 = 2π (s)", 1.06, settle_c, 5e-3, []),
        ("settling at zeta = 3 over critical: about four times", 4, 4.2995 / settle_c, 0.25,
         [(C, "mistake-more-damping", {"en": "four times", "hi-Latn": "chaar guna"}),
          (S, "mistake-more-damping", {"en": "four times", "hi-Latn": "chaar guna"})]),
        ("omega_r/omega0 at zeta = 0.4", 0.825, math.sqrt(1 - 2 * 0.4 ** 2), 5e-4,
         [(C, "resonance-peak", "0.825"), (C, "mistake-peak-at-w0", "0.825"),
          (S, "example-resonance-numbers", "0.825"), (S, "mistake-peak-at-w0", "0.825")]),
        ("peak amplitude 1/(2 zeta sqrt(1−zeta²)) at zeta = 0.4", 1.364, 1 / (2 * 0.4 * math.sqrt(1 - 0.16)), 5e-4,
         [(S, "example-resonance-numbers", "1.364")]),
        ("amplitude at 0.8 w0, zeta = 0.4", 1.36, amp(0.8, 0.4), 5e-3, [(S, "example-resonance-numbers", "1.36 f_0")]),
        ("amplitude at w0, zeta = 0.4", 1.25, amp(1.0, 0.4), 5e-4, [(S, "example-resonance-numbers", "1.25 f_0")]),
        ("transient rate zeta w0 at zeta = 0.4 (1/s)", 2.51, 0.4 * 2 * math.pi, 5e-3, [(S, "example-resonance-numbers", "2.51")]),
        ("amplitude at w0, Q = 10", 10, amp(1.0, 0.05), 1e-9, [(P, "resonance-amplitude", "10 f_0")]),
        ("amplitude at 0.9 w0, Q = 10", 4.76, amp(0.9, 0.05), 5e-3,
         [(C, "resonance-width", "4.76 f_0"), (S, "example-resonance-numbers", "4.76 f_0")]),
        ("lag at 0.9 w0, Q = 10 (rad)", 0.44, math.atan2(0.09, 0.19), 5e-3, [(S, "example-resonance-numbers", "0.44 rad")]),
        ("lag at 0.9 w0, Q = 10 (degrees)", 25, math.degrees(math.atan2(0.09, 0.19)), 0.5, [(S, "example-resonance-numbers", "25°")]),
        ("lag at w0 (rad)", 1.571, math.pi / 2, 5e-4,
         [(P, "resonance-lag", "1.571"), (S, "example-resonance-numbers", "1.571 rad")]),
        ("peak shift below w0 at Q = 10 (%)", 0.25, 100 * (1 - math.sqrt(1 - 2 * 0.05 ** 2)), 5e-3,
         [(C, "mistake-peak-at-w0", "0.25%"), (S, "mistake-peak-at-w0", "0.25%"), (S, "example-resonance-numbers", "0.25%")]),
        ("3 − 2 ln 2", 1.614, c, 5e-4,
         [(C, "vdp-period", "1.614"), (P, "vdp-period", "1.614"), (S, "van-der-pol", "1.614")]),
        ("3 × |first zero of Ai|", 7.014, 3 * airy, 5e-4,
         [(C, "vdp-period", "7.014"), (P, "vdp-period", "7.014"), (P, "vdp-stiff-period", "7.014"), (S, "van-der-pol", "7.014")]),
        ("slow branch from 2 to 1, per mu: 3/2 − ln 2", 0.807, 1.5 - math.log(2), 5e-4, [(S, "van-der-pol", "0.807")]),
        ("VdP mu = 10: (3 − 2 ln 2) mu", 16.1, c * 10, 5e-2, [(P, "vdp-period", "16.1"), (S, "van-der-pol", "16.1")]),
        ("VdP mu = 10: 7.014 mu^(−1/3)", 3.3, 3 * airy * 10 ** (-1 / 3), 5e-2, [(P, "vdp-period", "3.3")]),
        ("VdP mu = 10: with the correction", 19.4, c * 10 + 3 * airy * 10 ** (-1 / 3), 5e-2,
         [(C, "vdp-period", "19.4"), (P, "vdp-period", "19.4"), (S, "van-der-pol", "19.4")]),
        ("VdP mu = 1000: (3 − 2 ln 2) mu", 1613.7, c * 1000, 5e-2, [(P, "vdp-stiff-period", "1613.7")]),
        ("VdP mu = 1000: 7.014 mu^(−1/3)", 0.7, 3 * airy * 1000 ** (-1 / 3), 5e-3, [(P, "vdp-stiff-period", "0.7")]),
        ("VdP mu = 1000: with the correction", 1614.4, c * 1000 + 3 * airy * 1000 ** (-1 / 3), 5e-2,
         [(P, "vdp-stiff-period", "1614.4")]),
        ("VdP fast rate 3 mu at |x| = 2, mu = 1000", 3000, 1000 * (2 ** 2 - 1), 0,
         [(C, "why-stiff", "3000"), (S, "stiffness", "3000")]),
        ("VdP harmonic period 2π", 6.28, 2 * math.pi, 5e-3, [(P, "vdp-period", "6.28"), (S, "van-der-pol", "6.28")]),
        ("clock: period change 5° → 4° (%)", 0.017, 100 * (ratio(5) - ratio(4)), 5e-4,
         [(C, "pendulum-clocks", "0.017%"), (S, "applications", "0.017%")]),
        ("clock: gain per day 5° → 4° (s)", 15, 86400 * (ratio(5) - ratio(4)), 0.5,
         [(C, "pendulum-clocks", "15 s"), (S, "applications", "15 s")]),
    ]
    for name, value, computed, tol, where in F:
        row(f"formula {name}", fmt(value), fmt(computed), abs(value - computed) <= tol)
        stated(deck, sections, where, f"formula {name}")


def check_stiff_demo(deck, sections, scenes: dict[str, Scene], quick: bool) -> None:
    """The texts on stiffness say an explicit method needs of the order of a
    million steps for the stiff scene and an implicit one of the order of a
    thousand (card why-stiff, section stiffness). Here: SciPy's Radau and,
    unless --quick, its DOP853 at rtol 1e-6. flipcard's own figures (the
    switch before t = 0.1, fewer than 1500 Radau steps, `adaptive`
    refusing) are checked through its simulator by tests/deck_oscillations.rs."""
    s = scenes["vdp-stiff"]
    tol = dict(rtol=1e-6, atol=1e-9)
    r = solve_ivp(s.rhs, (0, s.duration), s.initial, method="Radau", **tol)
    steps_r = len(r.t) - 1
    row("vdp-stiff: Radau steps at rtol 1e-6", "order of a thousand", str(steps_r), 300 <= steps_r <= 3000)
    stated(deck, sections, [("card", "why-stiff", {"en": "of the order of a thousand", "hi-Latn": "hazaar ke order"}),
                            ("card", "why-stiff", {"en": "of the order of a million", "hi-Latn": "million ke order"}),
                            ("section", "stiffness", {"en": "of the order of a million", "hi-Latn": "million ke order"})],
           "step counts")
    if quick:
        return
    d = solve_ivp(s.rhs, (0, s.duration), s.initial, method="DOP853", **tol)
    steps_d = len(d.t) - 1
    row("vdp-stiff: DOP853 steps at rtol 1e-6", "order of a million", str(steps_d), 300_000 <= steps_d <= 3_000_000)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="skip the slow explicit run of the stiff scene")
    args = ap.parse_args()

    deck = tomllib.loads(DECK.read_text(encoding="utf-8"))
    langs = deck["deck"]["languages"]
    sections = {}
    for lang in langs:
        data = tomllib.loads((CONTENT / f"{lang}.toml").read_text(encoding="utf-8"))
        sections[lang] = {s["id"]: s for s in data.get("section", [])}
    claims = json.loads(CLAIMS.read_text(encoding="utf-8"))

    scenes = {}
    for raw in deck.get("scene", []):
        try:
            scenes[raw["id"]] = Scene(raw)
        except (ValueError, SyntaxError) as err:
            fail(str(err))
    for p in deck.get("prompt", []):
        if p["scene"] not in scenes:
            fail(f"prompt {p['id']}: no scene {p['scene']!r}")

    check_scenes(scenes)
    check_prompts(deck, scenes)
    check_claims(deck, sections, scenes, claims)
    check_formulas(deck, sections)
    if "vdp-stiff" in scenes:
        check_stiff_demo(deck, sections, scenes, args.quick)

    print_table()
    print()
    if FAILURES:
        print(f"{len(FAILURES)} failure(s):")
        for f in FAILURES:
            print(f"  - {f}")
        return 1
    print(f"all {len(ROWS)} checks pass")
    return 0


if __name__ == "__main__":
    sys.exit(main())
