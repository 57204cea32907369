"""The stiff problems of `benches/stiff.rs` in Python, shared by
`benches/stiff_reference.py` (which writes the fixture) and
`benches/compare_scipy_stiff.py` (which times SciPy on them).

Each problem: right-hand side, analytic Jacobian, time span, initial state
and the absolute tolerance per component as a function of rtol (the same as
in `benches/stiff.rs`). Hairer & Wanner's test set (Solving ODEs II) and the
IVP test set (Mazzia et al.) define HIRES, the Oregonator and E5.

`DECKS` writes each problem as a deck scene, so `benches/compare_scipy_stiff.py
--table` can run flipcard's own binary on it; `TABLE` lists the problems of
that table (two more than `benches/stiff.rs`: Van der Pol at mu = 1e4 and a
linear system with eigenvalues -1 and -1e8, whose reference is its closed
form; the 200-variable Brusselator comes from `tests/fixtures/brusselator/`).
"""

from pathlib import Path

import numpy as np

MU = 1000.0
FIXTURE = Path(__file__).with_name("stiff_reference.txt")


def vdp(_t, y):
    return [y[1], MU * (1.0 - y[0] * y[0]) * y[1] - y[0]]


def vdp_jac(_t, y):
    return [[0.0, 1.0], [-2.0 * MU * y[0] * y[1] - 1.0, MU * (1.0 - y[0] * y[0])]]


def rober(_t, y):
    return [
        -0.04 * y[0] + 1e4 * y[1] * y[2],
        0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] * y[1],
        3e7 * y[1] * y[1],
    ]


def rober_jac(_t, y):
    return [
        [-0.04, 1e4 * y[2], 1e4 * y[1]],
        [0.04, -1e4 * y[2] - 6e7 * y[1], -1e4 * y[1]],
        [0.0, 6e7 * y[1], 0.0],
    ]


def hires(_t, y):
    y1, y2, y3, y4, y5, y6, y7, y8 = y
    return [
        -1.71 * y1 + 0.43 * y2 + 8.32 * y3 + 0.0007,
        1.71 * y1 - 8.75 * y2,
        -10.03 * y3 + 0.43 * y4 + 0.035 * y5,
        8.32 * y2 + 1.71 * y3 - 1.12 * y4,
        -1.745 * y5 + 0.43 * y6 + 0.43 * y7,
        -280.0 * y6 * y8 + 0.69 * y4 + 1.71 * y5 - 0.43 * y6 + 0.69 * y7,
        280.0 * y6 * y8 - 1.81 * y7,
        -280.0 * y6 * y8 + 1.81 * y7,
    ]


def hires_jac(_t, y):
    j = np.zeros((8, 8))
    j[0, 0], j[0, 1], j[0, 2] = -1.71, 0.43, 8.32
    j[1, 0], j[1, 1] = 1.71, -8.75
    j[2, 2], j[2, 3], j[2, 4] = -10.03, 0.43, 0.035
    j[3, 1], j[3, 2], j[3, 3] = 8.32, 1.71, -1.12
    j[4, 4], j[4, 5], j[4, 6] = -1.745, 0.43, 0.43
    j[5, 3], j[5, 4], j[5, 5], j[5, 6], j[5, 7] = 0.69, 1.71, -280.0 * y[7] - 0.43, 0.69, -280.0 * y[5]
    j[6, 5], j[6, 6], j[6, 7] = 280.0 * y[7], -1.81, 280.0 * y[5]
    j[7, 5], j[7, 6], j[7, 7] = -280.0 * y[7], 1.81, -280.0 * y[5]
    return j


def oregonator(_t, y):
    y1, y2, y3 = y
    return [
        77.27 * (y2 + y1 * (1.0 - 8.375e-6 * y1 - y2)),
        (y3 - (1.0 + y1) * y2) / 77.27,
        0.161 * (y1 - y3),
    ]


def oregonator_jac(_t, y):
    y1, y2, _ = y
    return [
        [77.27 * (1.0 - 2.0 * 8.375e-6 * y1 - y2), 77.27 * (1.0 - y1), 0.0],
        [-y2 / 77.27, -(1.0 + y1) / 77.27, 1.0 / 77.27],
        [0.161, 0.0, -0.161],
    ]


E5_A, E5_B, E5_C, E5_M = 7.89e-10, 1.1e7, 1.13e3, 1e6


def e5(_t, y):
    y1, y2, y3, y4 = y
    a, b, c, m = E5_A, E5_B, E5_C, E5_M
    return [
        -a * y1 - b * y1 * y3,
        a * y1 - m * c * y2 * y3,
        a * y1 - b * y1 * y3 - m * c * y2 * y3 + c * y4,
        b * y1 * y3 - c * y4,
    ]


def e5_jac(_t, y):
    y1, y2, y3, _ = y
    a, b, c, m = E5_A, E5_B, E5_C, E5_M
    return [
        [-a - b * y3, 0.0, -b * y1, 0.0],
        [a, -m * c * y3, -m * c * y2, 0.0],
        [a - b * y3, -m * c * y3, -b * y1 - m * c * y2, c],
        [b * y3, 0.0, b * y1, -c],
    ]


# E5 runs to t = 1e5, not the test set's 1e13: beyond ~1e9 SciPy's Radau, BDF
# and LSODA at rtol 1e-12, atol 1e-30 disagree with each other (at 1e13 in
# the leading digit, and none matches the test set's published values), so
# no reference could be confirmed there.
E5_END = 1e5

# name: (f, jac, (t0, t_end), y0, atol(rtol))
PROBLEMS = {
    "van-der-pol": (vdp, vdp_jac, (0.0, 3000.0), [2.0, 0.0], lambda r: np.array([r, r])),
    "robertson": (
        rober,
        rober_jac,
        (0.0, 1e11),
        [1.0, 0.0, 0.0],
        lambda r: np.array([r * 1e-4, r * 1e-10, r * 1e-4]),
    ),
    "hires": (
        hires,
        hires_jac,
        (0.0, 321.8122),
        [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057],
        lambda r: np.full(8, r * 1e-6),
    ),
    "oregonator": (oregonator, oregonator_jac, (0.0, 360.0), [1.0, 2.0, 3.0], lambda r: np.full(3, r)),
    "e5": (e5, e5_jac, (0.0, E5_END), [1.76e-3, 0.0, 0.0, 0.0], lambda r: np.full(4, 1e-24)),
}


def e5_reduced(_t, y):
    """E5 with its invariant y2 = y3 + y4 written out (state y1, y3, y4).

    d/dt (y2 - y3 - y4) = 0 and all start at 0, so y2 = y3 + y4 exactly. In
    the four-variable form rounding in f (B*y1*y3 and C*y4 cancel to within
    1e-5 of their size in y3' and y4') breaks it by ~1e-21, which E5 never
    damps and its state at 1e5 answers with ~3e11 per unit: ~1e-9 relative,
    whatever the tolerance. Written out, no rounding can break it.
    """
    y1, y3, y4 = y
    a, b, c, m = E5_A, E5_B, E5_C, E5_M
    y2 = y3 + y4
    return [-a * y1 - b * y1 * y3, a * y1 - b * y1 * y3 - m * c * y2 * y3 + c * y4, b * y1 * y3 - c * y4]


def e5_reduced_jac(_t, y):
    y1, y3, y4 = y
    a, b, c, m = E5_A, E5_B, E5_C, E5_M
    return [
        [-a - b * y3, -b * y1, 0.0],
        [a - b * y3, -b * y1 - m * c * (2.0 * y3 + y4), -m * c * y3 + c],
        [b * y3, b * y1, -c],
    ]


MU4 = 1e4


def vdp4(_t, y):
    return [y[1], MU4 * (1.0 - y[0] * y[0]) * y[1] - y[0]]


def vdp4_jac(_t, y):
    return [[0.0, 1.0], [-2.0 * MU4 * y[0] * y[1] - 1.0, MU4 * (1.0 - y[0] * y[0])]]


# y' = A y with A = P diag(-1, -1e8) P^-1, P = [[1, 1], [1, -1]]: from
# y(0) = (2, 0), y(t) = e^-t (1, 1) + e^(-1e8 t) (1, -1). The entries are
# exact in binary.
LIN_D, LIN_O = -50000000.5, 49999999.5
LIN_END = 10.0


def linear(_t, y):
    return [LIN_D * y[0] + LIN_O * y[1], LIN_O * y[0] + LIN_D * y[1]]


def linear_jac(_t, _y):
    return [[LIN_D, LIN_O], [LIN_O, LIN_D]]


def linear_exact(t):
    import math

    return np.array([math.exp(-t) + math.exp(-1e8 * t), math.exp(-t) - math.exp(-1e8 * t)])


PROBLEMS["van-der-pol-1e4"] = (vdp4, vdp4_jac, (0.0, 2e4), [2.0, 0.0], lambda r: np.array([r, r]))
# atol = rtol·1e-6: both components end near 4.5e-5.
PROBLEMS["linear"] = (linear, linear_jac, (0.0, LIN_END), [2.0, 0.0], lambda r: np.array([r * 1e-6, r * 1e-6]))

# Each problem as a deck scene: variables, equations, params. No `atol`: the
# table runs flipcard with the default a user gets (each variable's
# absolute tolerance follows its size), SciPy with the atol above.
DECKS = {
    "hires": (
        ["y1", "y2", "y3", "y4", "y5", "y6", "y7", "y8"],
        [
            "-1.71*y1 + 0.43*y2 + 8.32*y3 + 0.0007",
            "1.71*y1 - 8.75*y2",
            "-10.03*y3 + 0.43*y4 + 0.035*y5",
            "8.32*y2 + 1.71*y3 - 1.12*y4",
            "-1.745*y5 + 0.43*y6 + 0.43*y7",
            "-280*y6*y8 + 0.69*y4 + 1.71*y5 - 0.43*y6 + 0.69*y7",
            "280*y6*y8 - 1.81*y7",
            "-280*y6*y8 + 1.81*y7",
        ],
        {},
    ),
    "oregonator": (
        ["y1", "y2", "y3"],
        ["77.27*(y2 + y1*(1 - 8.375e-6*y1 - y2))", "(y3 - (1 + y1)*y2)/77.27", "0.161*(y1 - y3)"],
        {},
    ),
    "e5": (
        ["y1", "y2", "y3", "y4"],
        ["-A*y1 - B*y1*y3", "A*y1 - M*C*y2*y3", "A*y1 - B*y1*y3 - M*C*y2*y3 + C*y4", "B*y1*y3 - C*y4"],
        {"A": E5_A, "B": E5_B, "C": E5_C, "M": E5_M},
    ),
    "robertson": (
        ["y1", "y2", "y3"],
        ["-0.04*y1 + 1e4*y2*y3", "0.04*y1 - 1e4*y2*y3 - 3e7*y2^2", "3e7*y2^2"],
        {},
    ),
    "van-der-pol": (["x", "v"], ["v", "mu*(1 - x^2)*v - x"], {"mu": MU}),
    "van-der-pol-1e4": (["x", "v"], ["v", "mu*(1 - x^2)*v - x"], {"mu": MU4}),
    "linear": (["y1", "y2"], ["d*y1 + o*y2", "o*y1 + d*y2"], {"d": LIN_D, "o": LIN_O}),
}

# The problems of the closing table of issue 26, in its order.
TABLE = ["hires", "oregonator", "e5", "robertson", "van-der-pol-1e4", "linear", "brusselator"]


def deck_text(name):
    """The problem `name` as a deck whose one scene is `s`."""
    variables, equations, params = DECKS[name]
    _, _, span, y0, _ = PROBLEMS[name]
    q = lambda xs: "[" + ", ".join(f'"{x}"' for x in xs) + "]"  # noqa: E731
    lines = [
        "[deck]",
        f'id = "{name}"',
        "title = 'T'",
        'languages = ["en"]',
        "",
        "[[card]]",
        'id = "c"',
        "front = 'F'",
        "back = 'B'",
        "",
        "[[scene]]",
        'id = "s"',
        f"variables = {q(variables)}",
        "initial = [" + ", ".join(repr(float(v)) for v in y0) + "]",
    ]
    if params:
        lines.append("params = { " + ", ".join(f"{k} = {v!r}" for k, v in params.items()) + " }")
    lines += [f"equations = {q(equations)}", f"duration = {span[1]!r}", 'show = ["plot"]', f'plot = ["{variables[0]}"]', ""]
    return "\n".join(lines)


def read_fixture():
    """name -> reference final state, from `benches/stiff_reference.txt`."""
    out = {}
    for line in FIXTURE.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            continue
        name, *values = line.split()
        out[name] = np.array([float(v) for v in values[1:]])  # values[0] is t_end
    return out


def max_rel_error(y, ref):
    return float(np.max(np.abs(np.asarray(y) - ref) / np.abs(ref)))
