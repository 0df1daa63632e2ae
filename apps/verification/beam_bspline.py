"""The seed's beam (Problem 2) on its own 40 x 4 grid with B-spline MPM, against the Timoshenko beam
advanced by Newmark at the run's time step.

Decks: apps/beam_implicit_bspline_plane_strain.yaml (quadratic: Gauss particle placement and three
consistent-projection iterations) and apps/beam_implicit_bspline_cubic_plane_strain.yaml (cubic:
Gauss placement and the consistent mass), both 4 x 4 particles per cell, dt = 1e-3 s, 1000 steps,
plane strain against E / (1 - nu^2). The error is impm's own relative L2 error of w(L/2, t) over
the run against the deck's exact solution (`Beam Theory: Timoshenko`, `Time Discretisation:
Newmark`: each mode advanced by the same Newmark recurrence, so the comparison isolates the
spatial error). The quadratic deck also runs with the uniform particle lattice for contrast.
"""
import math
import os

import numpy as np

import decks
from cases import Case
from checks import Check
from report import table

QUADRATIC_DECK = "apps/beam_implicit_bspline_plane_strain.yaml"
CUBIC_DECK = "apps/beam_implicit_bspline_cubic_plane_strain.yaml"
ERROR_MAX = 0.02  # the 2% target
MONITOR = "w_mid"

# (name, row text, deck, overrides)
FULL_PLAN = (
    ("beam_bspline_quadratic_gauss", "quadratic, Gauss placement, 3 projection iterations (the deck)", QUADRATIC_DECK, {}),
    ("beam_bspline_quadratic_uniform", "quadratic, uniform lattice, 3 projection iterations", QUADRATIC_DECK,
     {"Body/Particle Placement": "Uniform"}),
    ("beam_bspline_cubic_gauss", "cubic, Gauss placement, consistent mass (the deck)", CUBIC_DECK, {}),
)


def plan(repo, reduced):
    rows = []
    if reduced:  # 1000 implicit steps each: the full report only
        return {"reduced": reduced, "rows": rows}
    for name, text, deck, extra in FULL_PLAN:
        ov = {"Output/Plot": False, "Output/Progress": False, "Output/VTK Interval": 0,
              "Problem/Output Directory": f"output/verification/runs/{name}"}
        ov.update(extra)
        d = decks.apply(decks.load(os.path.join(repo, deck)), ov)
        rows.append((text, Case(name=name, problem="beam_bspline", method="implicit " + text.split(",")[0],
                                plane="Plane Strain", deck=d)))
    return {"reduced": reduced, "rows": rows}


def cases_of(p):
    return [c for _, c in p["rows"]]


def _result(text, run):
    out = {"text": text, "run": run, "error": float("nan"), "wall": run.wall, "curve": None}
    if not run.ok:
        return out
    out["error"] = float((run.summary.get("Relative L2 Error") or {}).get(MONITOR, float("nan")))
    h = run.history
    if h is not None and MONITOR in h and MONITOR + "_exact" in h:
        out["curve"] = (np.asarray(h["time"], float), np.asarray(h[MONITOR], float), np.asarray(h[MONITOR + "_exact"], float))
    return out


def compute(runs, p):
    res = {"plan": p, "rows": [_result(text, runs[c.name]) for text, c in p["rows"]]}
    res["checks"] = evaluate(res)
    return res


def evaluate(res):
    out = []
    for r in res["rows"]:
        if "(the deck)" in r["text"]:
            ok = math.isfinite(r["error"]) and r["error"] < ERROR_MAX
            out.append(Check(f"Seed beam, B-spline MPM on 40 x 4 ({r['text'].split(',')[0]}): w(L/2, t) within 2% of the "
                             "Newmark-advanced Timoshenko beam", ok, f"{100 * r['error']:.2f}% (plane strain, E/(1-nu^2))"))
    if res["rows"]:
        failed = [r["run"] for r in res["rows"] if not r["run"].ok]
        out.append(Check("Seed beam with B-splines, every run completed", not failed,
                         f"{len(res['rows']) - len(failed)} of {len(res['rows'])}"
                         + "".join(f"; {r.case.name}: {r.message}" for r in failed)))
    return out


def plot(res, image_dir):
    """beam_bspline.png: w(L/2, t) of the two decks against the Newmark-advanced Timoshenko beam."""
    from plots import _save, plt
    rows = [r for r in res["rows"] if r["curve"] is not None and "(the deck)" in r["text"]]
    if not rows:
        return []
    fig, ax = plt.subplots(1, 1, figsize=(8, 4))
    t, _, exact = rows[0]["curve"]
    ax.plot(t, 1e9 * exact, "k-", lw=1.2, label="Timoshenko, Newmark in time")
    for r, style in zip(rows, ("--", ":")):
        t, w, _ = r["curve"]
        ax.plot(t, 1e9 * w, style, lw=1.2, label=f"B-spline {r['text'].split(',')[0]} ({100 * r['error']:.2f}%)")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("w(L/2, t) (nm)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    _save(fig, os.path.join(image_dir, "beam_bspline.png"))
    return ["beam_bspline.png"]


def markdown(res, rel_img):
    L = ["## 9. The seed beam with B-spline MPM", ""]
    if not res["rows"]:
        return L + ["Not in the reduced report (1000 implicit steps per run).", ""]
    L += [
        f"`{QUADRATIC_DECK}` and `{CUBIC_DECK}`: the seed's Problem 2 beam (steel, 10 m x 0.5 m, simply supported at "
        "mid-depth, harmonic mid-span load at 150 rad/s) on its own 40 x 4 grid, 4 x 4 particles per cell, dt = 1e-3 s, "
        "1000 steps, plane strain (modulus E/(1 - nu^2)), against the Timoshenko beam advanced by Newmark at the same dt "
        "(the spatial error alone). Bilinear MPM cells lock in bending (121% against Euler-Bernoulli in section 3); "
        "B-splines do not. Two details decide the last percent, because the beam is driven near its first mode: the "
        "uniform particle lattice integrates the second moment of the depth 0.39% low (the midpoint rule), which "
        "`Particle Placement: Gauss` (2-point Gauss-Legendre pairs in each half cell) makes exact; and the lumped-mass "
        "projection of the particle velocity smooths it, which three consistent-projection iterations (quadratic) or "
        "the consistent mass (cubic) remove.",
        "",
    ]
    rows = [[r["text"], f"{100 * r['error']:.2f}%" if math.isfinite(r["error"]) else "failed",
             f"{r['wall']:.1f}" if r["wall"] else ""] for r in res["rows"]]
    L += table(["B-spline, particles, mass", "relative L2 error of w(L/2, t)", "wall (s)"], rows).splitlines()
    L += [
        "",
        f"![w(L/2, t) with B-splines against the Newmark-advanced Timoshenko beam]({rel_img}/beam_bspline.png)",
        "",
        "Checks: each deck's error below 2%. The cubic deck's 1.99% is at the limit: with more Gauss pairs per cell it "
        "rises to 2.03% (the cubic discretisation with the consistent mass is itself slightly stiff), so its margin is "
        "luck, not design.",
        "",
    ]
    return L
