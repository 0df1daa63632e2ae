"""Soils: the granular column collapse against the run-out and height laws, and geostatic stress.

Every case is apps/column_collapse_explicit_gimp_dp.yaml with a few keys changed, as in
test_soil_column (which asserts the same figures):
- the column collapse (cohesionless Drucker-Prager sand, phi = 22.2 degrees, psi = 0, smooth back
  wall, rough floor mu = 0.466, explicit GIMP, MUSL) at aspect ratios a = H0 / L0 = 0.5 (h = 1 and
  0.5 cm; with F-bar; Mohr-Coulomb) and 2, against the quasi-2D laws of Lube et al. (2005) and DEM:
  run-out (L_inf - L0) / L0 = 1.2 a (experiments) and 1.67 a (DEM); final height H_f / L0 = a for
  a < 0.7 (the top surface survives), a^(1/3) above. The front is where the deposit, from the last
  particle file, thins below 1 cm (5% of L0 at a = 0.5); the tongue of single particles ahead of it
  is reported apart.
- a layer of the same sand between smooth walls, started stress-free (it drops and rings) and
  geostatic (K0 = 1 - sin phi; linear elastic: nu / (1 - nu)): it stays at rest and holds the
  overburden.
"""
import math
import os

import numpy as np

import decks
from cases import Case
from checks import Check
from checks import _finite as _fin
from checks import failed_run
from report import table

DECK = "apps/column_collapse_explicit_gimp_dp.yaml"
WALL = 0.02
RHO, G, NU, PHI = 1925.0, 9.81, 0.22, 22.2
FRONT_THICKNESS = 0.01      # the front: where the deposit is at least 1 cm thick
RESOLUTION_AGREEMENT = 0.05  # h and h/2 fronts agree to two columns of particles, 0.05 L0
KINETIC_AT_REST = 1e-3      # final over peak kinetic energy
LOW_HEIGHT_TOL = 0.02       # a = 0.5: the top survives to 2%
TALL_HEIGHT_TOL = 0.03      # a = 2: H_f / L0 = a^(1/3) to 3%
TALL_DEM_FACTOR = 1.15      # MPM over-predicts the run-out of tall columns (Kumar; Bandara 2013; Mast 2014)


def _column(repo, name, a, h, steps, fbar=False, model="Drucker-Prager"):
    L0 = 0.2 if a < 1 else 0.1
    H0 = a * L0
    ov = {"Output/Plot": False, "Output/Progress": False, "Output/VTK Interval": steps,
          "Output/Energy And Momentum": True, "Problem/Output Directory": f"output/verification/runs/{name}",
          "Bodies/column/X Max": WALL + L0, "Bodies/column/Y Max": WALL + H0,
          "Grid/Cell Size X": h, "Grid/Cell Size Y": h, "Grid/Cells X": int(round(0.64 / h)),
          "Grid/Cells Y": int(round((WALL + H0) / h)) + 2,
          "Integrator/Time Step": 1e-4 * h / 0.01, "Integrator/Number of Steps": steps}
    if fbar:
        ov["Method/Volumetric Locking"] = "F-bar"
    if model != "Drucker-Prager":
        ov["Materials/sand/Model"] = model
        ov["Materials/sand/Cone"] = decks.DELETE
    d = decks.apply(decks.load(os.path.join(repo, DECK)), ov)
    return Case(name=name, problem="soils", method="explicit GIMP", plane="Plane Strain", deck=d)


def _layer(repo, name, geostatic, elastic):
    width, depth = 0.2, 0.1
    x_mid, y_top, y_mid = WALL + width / 2 + 0.0025, WALL + depth - 0.0025, WALL + depth / 2 + 0.0025
    ov = {"Output/Plot": False, "Output/Progress": False, "Output/VTK Interval": 0, "Output/History Interval": 10,
          "Problem/Output Directory": f"output/verification/runs/{name}",
          "Bodies/column/X Max": WALL + width, "Bodies/column/Y Max": WALL + depth,
          "Grid/Cells X": 26, "Grid/Cells Y": 14, "Integrator/Number of Steps": 2000,
          "Walls/right/Normal": "x-", "Walls/right/Position": WALL + width, "Walls/right/Friction": 0.0,
          "Monitors/top/Quantity": "Velocity Y", "Monitors/top/X": x_mid, "Monitors/top/Y": y_top,
          "Monitors/mid/Quantity": "Stress YY", "Monitors/mid/X": x_mid, "Monitors/mid/Y": y_mid}
    if elastic:
        ov["Materials/sand"] = {"Young Modulus": 1.98e6, "Poisson Ratio": NU, "Density": RHO}
    if geostatic:
        ov.update({"Bodies/column/Initial Stress": "Geostatic", "Bodies/column/Surface Y": WALL + depth,
                   "Bodies/column/K0": NU / (1 - NU) if elastic else 1 - math.sin(math.radians(PHI))})
    d = decks.apply(decks.load(os.path.join(repo, DECK)), ov)
    return Case(name=name, problem="soils", method="explicit GIMP", plane="Plane Strain", deck=d), \
        -RHO * G * (WALL + depth - y_mid)


def plan(repo, reduced):
    p = {"reduced": reduced, "columns": [], "layers": []}
    if reduced:  # test_soil_column asserts these figures; the reduced report leaves them out
        return p
    for text, a, h, steps, fbar, model in (
            ("a = 0.5, h = 1 cm", 0.5, 0.01, 6000, False, "Drucker-Prager"),
            ("a = 0.5, h = 0.5 cm", 0.5, 0.005, 12000, False, "Drucker-Prager"),
            ("a = 0.5, h = 1 cm, F-bar", 0.5, 0.01, 6000, True, "Drucker-Prager"),
            ("a = 0.5, h = 1 cm, Mohr-Coulomb", 0.5, 0.01, 6000, False, "Mohr-Coulomb"),
            ("a = 2, h = 1 cm", 2.0, 0.01, 10000, False, "Drucker-Prager")):
        name = "soils_column_a{:g}_h{:g}mm{}{}".format(a, 1e3 * h, "_fbar" if fbar else "",
                                                     "_mc" if model != "Drucker-Prager" else "")
        p["columns"].append({"text": text, "a": a, "h": h, "case": _column(repo, name, a, h, steps, fbar, model)})
    for elastic in (False, True):
        for geostatic in (False, True):
            name = "soils_layer_{}_{}".format("elastic" if elastic else "dp", "geostatic" if geostatic else "stress_free")
            case, overburden = _layer(repo, name, geostatic, elastic)
            p["layers"].append({"elastic": elastic, "geostatic": geostatic, "overburden": overburden, "case": case})
    return p


def cases_of(p):
    return [e["case"] for e in p["columns"] + p["layers"]]


def _deposit(e, run):
    out = dict(e, run=run, run_out=float("nan"))
    if not run.ok:
        return out
    from taylor_bar import read_particles
    _, pts = read_particles(run.directory)
    x = np.asarray(pts["points"], float)[:, :2]
    a, h = e["a"], e["h"]
    L0 = 0.2 if a < 1 else 0.1
    spacing = h / 2
    bins = np.minimum(1999, (x[:, 0] / spacing).astype(int))
    top = np.full(2000, WALL)
    np.maximum.at(top, bins, x[:, 1] + spacing / 2)
    thick = np.nonzero(top - WALL >= FRONT_THICKNESS)[0]
    front = (thick.max() + 1) * spacing if thick.size else 0.0
    kinetic = np.asarray(run.history["kinetic_energy"], float)
    out.update(L0=L0, run_out=(front - WALL - L0) / L0, tongue=(x[:, 0].max() + spacing / 2 - WALL - L0) / L0,
               height=(x[:, 1].max() + spacing / 2 - WALL) / L0, kinetic=float(kinetic[-1] / kinetic.max()),
               height_law=a if a < 0.7 else a ** (1 / 3), points=x)
    return out


def _layer_result(e, run):
    out = dict(e, run=run, speed=float("nan"), stress=float("nan"))
    if run.ok:
        out["speed"] = float(np.abs(np.asarray(run.history["top"], float)).max())
        out["stress"] = float(run.history["mid"][-1])
    return out


def compute(runs, p):
    res = {"plan": p, "columns": [_deposit(e, runs[e["case"].name]) for e in p["columns"]],
           "layers": [_layer_result(e, runs[e["case"].name]) for e in p["layers"]]}
    res["checks"] = evaluate(res)
    return res



def evaluate(res):
    out = []
    for r in res["columns"]:
        name = f"Soils, column collapse {r['text']}"
        if not r["run"].ok:
            out.append(failed_run(name, r["run"]))
            continue
        a = r["a"]
        hi = 1.67 * a * (1.0 if a < 1 else TALL_DEM_FACTOR)
        tol = LOW_HEIGHT_TOL if a < 1 else TALL_HEIGHT_TOL
        herr = r["height"] / r["height_law"] - 1
        ok = (r["kinetic"] < KINETIC_AT_REST and 1.2 * a <= r["run_out"] <= hi and abs(herr) < tol)
        out.append(Check(name + (": run-out between the experiments' and DEM's laws" if a < 1 else
                                 ": run-out between the experiments' law and 1.15 x DEM's") +
                         f", final height within {100 * tol:g}% of its law, at rest", ok,
                         f"(L_inf - L0)/L0 = {r['run_out']:.3f} in [{1.2 * a:.3g}, {hi:.3g}], H_f/L0 = {r['height']:.4f} "
                         f"against {r['height_law']:.4f} ({100 * herr:+.2f}%), final/peak kinetic {r['kinetic']:.2g}"))
    pair = [r for r in res["columns"] if r["a"] == 0.5 and "F-bar" not in r["text"] and "Mohr" not in r["text"]]
    if len(pair) == 2 and all(r["run"].ok for r in pair):
        diff = abs(pair[0]["run_out"] - pair[1]["run_out"])
        out.append(Check("Soils, column collapse a = 0.5: the fronts at h and h / 2 agree to 0.05 L0",
                         diff <= RESOLUTION_AGREEMENT + 1e-12, f"{pair[0]['run_out']:.3f} and {pair[1]['run_out']:.3f}"))
    for elastic in (False, True):
        rows = {r["geostatic"]: r for r in res["layers"] if r["elastic"] == elastic}
        if len(rows) != 2:
            continue
        law = "linear elastic, K0 = nu/(1 - nu)" if elastic else "Drucker-Prager, K0 = 1 - sin phi"
        dropped, held = rows[False], rows[True]
        ok = (dropped["run"].ok and held["run"].ok and _fin(dropped["speed"], held["speed"], held["stress"])
              and dropped["speed"] > 1e-3 and held["speed"] < 1e-8 * dropped["speed"]
              and abs(held["stress"] - held["overburden"]) < 1e-8 * abs(held["overburden"]))
        out.append(Check(f"Soils, geostatic layer ({law}): at rest and holding the overburden", ok,
                         f"top speed {held['speed']:.2g} m/s against {dropped['speed']:.3g} started stress-free; "
                         f"mid-depth sigma_yy {held['stress']:.6g} Pa against {held['overburden']:.6g}"))
    return out


def plot(res, image_dir):
    from plots import _save, plt
    rows = [r for r in res["columns"] if r["run"].ok and ("h = 1 cm" == r["text"].split(", ", 1)[1])]
    if not rows:
        return []
    fig, axes = plt.subplots(len(rows), 1, figsize=(9, 2.6 * len(rows)), squeeze=False)
    for ax, r in zip(axes[:, 0], rows):
        x = r["points"]
        ax.plot((x[:, 0] - WALL) / r["L0"], (x[:, 1] - WALL) / r["L0"], ".", ms=1.5, color="tab:brown")
        a = r["a"]
        for value, style, label in ((1 + 1.2 * a, "k--", "experiments 1.2 a"), (1 + 1.67 * a, "k:", "DEM 1.67 a")):
            ax.axvline(value, color="k", ls=style[1:], lw=1, label=label)
        ax.axvline(1 + r["run_out"], color="tab:red", lw=1, label=f"impm front {r['run_out']:.2f}")
        ax.axhline(r["height_law"], color="tab:blue", lw=0.8, ls="-.", label="height law")
        ax.plot([0, 1, 1], [a, a, 0], color="0.6", lw=0.8, label="initial column")
        ax.set_xlim(0, 1 + 1.9 * a)
        ax.set_ylabel("y / L0")
        ax.set_title(f"column collapse, {r['text']}: deposit at rest", fontsize=9)
        ax.set_aspect("equal")
        ax.legend(fontsize=7, loc="upper right")
    axes[-1, 0].set_xlabel("x / L0 (from the back wall)")
    fig.tight_layout()
    _save(fig, os.path.join(image_dir, "soils_columns.png"))
    return ["soils_columns.png"]


def markdown(res, rel_img):
    L = ["## 11. Soils: granular column collapse and geostatic stress", ""]
    if not res["columns"] and not res["layers"]:
        return L + ["Not in the reduced report (test_soil_column asserts these figures).", ""]
    L += [f"`{DECK}`: a column of dry sand (cohesionless Drucker-Prager, the plane-strain cone, phi = 22.2 degrees, no "
          "dilatancy; E = 1.98 MPa, rho = 1925 kg/m^3) against a smooth back wall on a rough floor (mu = 0.466), the "
          "material and floor of Kumar's plane-strain MPM study of the quasi-2D experiments of Lube et al. (2005); "
          "explicit GIMP, MUSL, 2 x 2 particles per cell, released at t = 0. With a = H0 / L0, the experiments give the "
          "run-out (L_inf - L0) / L0 = 1.2 a and DEM 1.67 a, and the final height H_f / L0 = a below a = 0.7 (the top "
          "survives) and a^(1/3) above. The front is where the deposit thins below 1 cm; the foremost particle "
          "(the tongue of single particles ahead of it, which grows as the particles get smaller) is reported apart.",
          ""]
    rows = []
    for r in res["columns"]:
        if not r["run"].ok:
            rows.append([r["text"], "failed", "", "", "", "", ""])
            continue
        a = r["a"]
        rows.append([r["text"], f"{r['run_out']:.3f}", f"{1.2 * a:.2f} / {1.67 * a:.2f}", f"{r['tongue']:.3f}",
                     f"{r['height']:.4f} ({r['height_law']:.4f})", f"{r['kinetic']:.1e}", f"{r['run'].wall:.1f}"])
    L += table(["column", "run-out (L_inf - L0)/L0", "experiments / DEM", "foremost particle",
                "H_f/L0 (law)", "final/peak kinetic energy", "wall (s)"], rows).splitlines()
    L += ["", f"![deposits against the run-out laws]({rel_img}/soils_columns.png)", "",
          "MPM over-predicts the run-out of tall columns (Kumar's thesis, Bandara 2013, Mast 2014): at a = 2 the check "
          "allows up to 1.15 times DEM's law.", ""]
    if res["layers"]:
        L += ["Geostatic stress: a layer of the same sand (0.2 m wide, 0.1 m deep) between smooth walls on the rough "
              "floor, 2000 steps. Started stress-free it drops under gravity and rings; started geostatic (`Initial "
              "Stress: Geostatic`, K0 = 1 - sin phi, Jaky's normally consolidated soil; linear elastic: "
              "K0 = nu / (1 - nu)) it stays at rest: on the layer's regular lattice GIMP's nodal internal force of "
              "the linear stress field balances the nodal weight exactly.", ""]
        rows = []
        for r in res["layers"]:
            rows.append(["linear elastic" if r["elastic"] else "Drucker-Prager",
                         "geostatic" if r["geostatic"] else "stress-free",
                         f"{r['speed']:.2g}" if _fin(r["speed"]) else "failed",
                         f"{r['stress']:.6g} ({r['overburden']:.6g})" if _fin(r["stress"]) else ""])
        L += table(["material", "start", "largest top speed (m/s)", "mid-depth sigma_yy at the end (overburden) (Pa)"],
                   rows).splitlines()
        L += [""]
    L += ["Checks (section 4): the tolerances of test_soil_column.", ""]
    return L
