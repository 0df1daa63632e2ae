"""Cell crossing: MPM against GIMP on the standing wave of a bar (apps/standing_wave_{mpm,gimp}.yaml).

On the seed's two problems the particles never cross cell lines and, on their regular lattices,
GIMP equals MPM exactly, so the spatial orders there cannot differ. This study refines the grid
of a free-vibration standing wave (both ends fixed, u = (V/omega) sin(pi X/L) sin(omega t)) whose
amplitude is 0.3 of the finest cell, so that particles cross cell lines on the finest grid, with
a strain amplitude of about 1e-3 (small strain holds). Grids 256, 512, 1024 cells (2 particles
per cell, dt = h / (2 c), one period). Error measures: u_x(L/2, t) and sigma_xx(L/4, t), relative
L2 over the history against the exact solution (doc/method.md, "Cell crossing: MPM against GIMP").
"""
import math
import os

import analysis
import decks
from cases import Case
from checks import Check

METHODS = ("MPM", "GIMP")
CELLS = (256, 512, 1024)
MONITORS = {"ux_half": "u_x(L/2, t)", "sxx_quarter": "sigma_xx(L/4, t)"}
# GIMP must keep converging through the crossing grid; MPM must not (its error jumps once
# particles cross). Thresholds from the measured orders (GIMP 1.75 and 1.79 in u, 1.12 and 1.18
# in sigma; MPM about -13 and -6): GIMP above 1.5 (u: first order fails) and 0.8 (sigma), and
# above MPM's by at least 1.
GIMP_MIN_ORDER = {"ux_half": 1.5, "sxx_quarter": 0.8}
MIN_ORDER_GAP = 1.0


def plan(repo):
    out = []
    for method in METHODS:
        base = decks.load(os.path.join(repo, "apps", f"standing_wave_{method.lower()}.yaml"))
        length = float(decks.get(base, "Body/X Max")) - float(decks.get(base, "Body/X Min"))
        c = math.sqrt(float(decks.get(base, "Material/Young Modulus")) / float(decks.get(base, "Material/Density")))
        period = 2.0 * length / c
        for n in CELLS:
            h = length / n
            dt = h / (2.0 * c)
            deck = decks.apply(base, {
                "Grid/Cells X": n, "Grid/Cell Size X": h, "Integrator/Time Step": dt,
                "Integrator/Number of Steps": int(round(period / dt)),
                "Problem/Name": f"standing wave, explicit {method}, {n} cells",
                "Output/Plot": False, "Output/Progress": False, "Output/VTK Interval": 0,
            })
            out.append(Case(name=f"standing_wave_{method.lower()}_{n}", problem="standing wave",
                            method=f"explicit {method}", plane="Plane Stress", deck=deck, refine=n // CELLS[0]))
    return out


def compute(runs, case_list):
    res = {"rows": [], "checks": [], "orders": {}}
    for method in METHODS:
        series = [c for c in case_list if c.method == f"explicit {method}"]
        for mon, label in MONITORS.items():
            errs = []
            for c in series:
                r = runs[c.name]
                errs.append(analysis.error_vs_exact(r, mon) if r.ok else float("nan"))
            ords = analysis.orders(errs)
            res["orders"][(method, mon)] = ords
            res["rows"].append((method, label, errs, ords))
    for mon, label in MONITORS.items():
        g, m = res["orders"][("GIMP", mon)][-1], res["orders"][("MPM", mon)][-1]
        ok = all(map(math.isfinite, (g, m))) and g >= GIMP_MIN_ORDER[mon] and g >= m + MIN_ORDER_GAP
        res["checks"].append(Check(
            f"Cell crossing, {label}: GIMP's spatial order above MPM's", ok,
            f"observed order 512 -> 1024 cells: GIMP {g:.2f} (>= {GIMP_MIN_ORDER[mon]}), MPM {m:.2f} "
            f"(GIMP must exceed it by >= {MIN_ORDER_GAP})"))
    return res


def markdown(res):
    def pct(e):
        return "n/a" if not math.isfinite(e) else f"{100 * e:.3g}%"

    lines = ["## 5. Cell crossing: spatial order of MPM against GIMP", "",
             __doc__.split("\n\n", 1)[1].strip().replace("\n", " "), "",
             "| method | monitor | " + " | ".join(f"{n} cells" for n in CELLS) + " | order 256->512 | order 512->1024 |",
             "|---|---|" + "---|" * len(CELLS) + "---|---|"]
    for method, label, errs, ords in res["rows"]:
        lines.append(f"| explicit {method} | {label} | " + " | ".join(pct(e) for e in errs) + " | "
                     + " | ".join("n/a" if not math.isfinite(o) else f"{o:.2f}" for o in ords) + " |")
    lines += ["", "Both converge until particles cross cell lines (on 256 and 512 cells they move less than a "
              "sixth of a cell); on 1024 cells they cross, MPM's gradient jumps as each particle crosses and its "
              "error grows by orders of magnitude, while GIMP's smooth weights keep it converging. Stress converges "
              "at first order for both (the particles sit a quarter cell off the cell centres, where the grid "
              "gradient is first-order accurate).", ""]
    return lines
