"""The targets that --check asserts, each a PASS/FAIL line with its numbers."""
import math
import os

import decks
from cases import EXPLICIT_DT_FRACTION, GRIDS, STABLE_USER_DECK

# Problem 1: each method's error of u_x(L, t) and u_x(L/2, t) may be at most a factor times the
# error of a 1D lumped-mass rod model with the seed's 30 cells along the bar (analysis.bar_fe1d),
# computed at the same dt, window, monitored point and modulus, against the closed form written in
# analysis.bar_closed_form (not impm's exact column). Every method here resolves the bar at least as
# finely as 30 linear elements; what limits all of them is the dispersion of the step front on that
# resolution, which the 1D model measures. The lumped-mass methods (MPM and GIMP, explicit and
# implicit) measure 0.93 to 1.08 times the 1D model's error over the full window and 1.01 to 1.08
# over the reduced one: factor 1.25. The FE references use the consistent mass, whose dispersion
# runs the other way, so the lumped rod is only an approximate yardstick for them: FE Q4 measures
# 1.07 (full) and up to 1.31 (reduced window, plane stress), FE Q9 0.12 to 0.23: factor 1.5. Both
# leave room for the 2D effects (Poisson coupling at the loaded face, particle quadrature) and fail
# a wrong modulus by far: with E 5% off, the exact solution itself moves by 7.5% (reduced window)
# to 20% (full window) in relative L2 at x = L.
BAR_TOLERANCE_FACTOR = 1.25
BAR_TOLERANCE_FACTOR_FE = 1.5


def bar_tolerance_factor(method):
    return BAR_TOLERANCE_FACTOR_FE if method.startswith("FE ") else BAR_TOLERANCE_FACTOR


BAR_CHECKED_MONITORS = ("ux_L", "ux_half")
# impm's exact column against analysis.bar_closed_form: the same closed form evaluated twice (C++
# and numpy); history.csv keeps 10 significant digits, so they agree to about 1e-10 (measured
# 8e-11 to 1.7e-10); 1e-8 leaves room for that rounding and still fails any error in the closed
# form (a wrong modulus or load is a difference of percent).
EXACT_COLUMN_AGREEMENT = 1e-8
NEWMARK_ORDER_RANGE = (1.8, 2.2)
# Problem 2's budget closure is bookkeeping, not physics: the links telescope, so the sum of the
# d_k differs from e_total = M - EB(E) only by the two implementations of the Euler-Bernoulli
# series (impm's column and impm_beam_exact's) and by the alignment of the rows. It measures
# about 1e-10; 1e-8 still catches a missing or misaligned link.
BUDGET_CONSISTENCY_MAX = 1e-8
# Problem 2 under grid refinement (full report): linear MPM and GIMP lock on the talk's 40 x 4 grid
# (measured 121%, asserted above 100%: the locking the talk shows) and converge: the error falls
# with every refinement, below 10% on 160 x 16 cells (measured 8.75%; 1.14 times that).
BEAM_LOCKING_MIN = 1.0
BEAM_FINEST_MAX = 0.10
BEAM_LOCKING_METHODS = ("implicit MPM", "implicit GIMP")
SUMMARY_AGREEMENT = 1e-6
NEWMARK_ASSERTED = ("FE Q4", "implicit MPM, consistent mass")
NEWMARK_NOT_ASSERTED = {
    ("bar", "implicit MPM"): "lumped-mass (Guilkey-Weiss) particle update, not one trapezoidal rule with the residual; compare the consistent-mass variant",
    ("bar", "implicit GIMP"): "lumped-mass (Guilkey-Weiss) particle update, not one trapezoidal rule with the residual; compare the consistent-mass variant",
    ("bar", "FE Q9"): "not yet in the asymptotic range at these dt",
    "bar": "see the report",
    "beam": "pre-asymptotic; compare the Newmark modal series in the report",
}


class Check:
    """One target: passed True/False, or None for a figure that is reported but not asserted (INFO)."""
    def __init__(self, name, passed, detail, consistency=False):
        # consistency: a check of the report's own bookkeeping (two code paths agree), not a
        # comparison with an exact or published solution; counted apart from the targets.
        self.name, self.passed, self.detail, self.consistency = name, passed, detail, consistency

    @property
    def failed(self):
        return self.passed is False

    def line(self):
        tag = "INFO" if self.passed is None else ("PASS" if self.passed else "FAIL")
        return f"{tag}  {self.name}: {self.detail}"


def failed_run(name, run):
    """The check `name` failed because its run did not complete."""
    return Check(name, False, f"run {run.case.name} failed: {run.message}")


def _finite(*v):
    return all(x is not None and math.isfinite(x) for x in v)


def evaluate(results):
    checks = []
    # Problem 1, every method and plane condition.
    for (problem, method, plane), entry in sorted(results["main"].items()):
        if problem != "bar":
            continue
        run = entry["run"]
        if not run.ok:
            checks.append(Check(f"Problem 1 {method}, {plane.lower()}", False, f"run failed: {run.message}"))
            continue
        for mon in BAR_CHECKED_MONITORS:
            e, ref = entry["errors"][mon], entry["fe1d"][mon]
            factor = bar_tolerance_factor(method)
            tol = factor * ref
            ok = _finite(e, tol) and e <= tol
            checks.append(Check(f"Problem 1 {method}, {plane.lower()}, {mon}", ok,
                                f"relative L2 error {100 * e:.3f}% <= {100 * tol:.3f}% "
                                f"({factor:g} x the 1D {GRIDS[('bar', 'MPM')][0]}-element model's {100 * ref:.3f}%)"))
        for mon, dev in entry["exact_column"].items():
            ok = _finite(dev) and dev <= EXACT_COLUMN_AGREEMENT
            checks.append(Check(f"Problem 1 exact column, {method}, {plane.lower()}, {mon}", ok,
                                f"impm's {mon}_exact against the closed form of analysis.py: relative L2 "
                                f"{dev:.1e} <= {EXACT_COLUMN_AGREEMENT:g}"))
    # Newmark: self-convergence in dt (finest pair). Asserted where the discretisation is
    # Newmark's rule applied to a semi-discrete system whose spectrum the dt resolves (FE Q4 and
    # consistent-mass MPM on the bar); the other series are reported (see the report's text).
    lo, hi = NEWMARK_ORDER_RANGE
    for st in results["studies"]:
        s = st["study"]
        if s.kind != "dt":
            continue
        for method, per_mon in st["selfconv"].items():
            for mon, (diffs, ords, _) in per_mon.items():
                o = ords[-1] if ords else float("nan")
                asserted = s.key == "bar_dt" and method in NEWMARK_ASSERTED
                passed = (_finite(o) and lo <= o <= hi) if asserted else None
                why = "" if asserted else f" (reported, not asserted: {NEWMARK_NOT_ASSERTED.get((s.problem, method), NEWMARK_NOT_ASSERTED[s.problem])})"
                checks.append(Check(f"Newmark self-convergence order, {s.problem} {method}, {mon}", passed,
                                    f"log2(d_k/d_k+1) = {o:.3f}" + (f" in [{lo}, {hi}]" if asserted else "")
                                    + f" (d = {', '.join(f'{d:.3e}' for d in diffs)})" + why))
    # Problem 2: locking on the talk's grid, convergence under refinement.
    for st in results["studies"]:
        s = st["study"]
        if s.key != "beam_grid":
            continue
        for method in BEAM_LOCKING_METHODS:
            e = st["errors"].get(method, {}).get("w_mid")
            if not e:
                continue
            ok = (_finite(*e) and e[0] > BEAM_LOCKING_MIN and all(b < a for a, b in zip(e[:-1], e[1:]))
                  and e[-1] < BEAM_FINEST_MAX)
            checks.append(Check(f"Problem 2 grid refinement, {method}", ok,
                                "w(L/2, t) relative L2 " + ", ".join(f"x{f}: {100 * v:.3g}%" for f, v in zip(s.factors, e))
                                + f" (locked above {100 * BEAM_LOCKING_MIN:g}% on the talk's grid, falling with every "
                                f"refinement, below {100 * BEAM_FINEST_MAX:g}% on the finest)"))
    # Budget closure: bookkeeping of the chain (consistency, not a physics target).
    for method, b in results["budget"].items():
        name = f"Problem 2 budget bookkeeping (consistency), {method}"
        if isinstance(b, str):
            checks.append(Check(name, False, b, consistency=True))
            continue
        aligned = b["rows_used"] == b["rows_model"]
        ok = _finite(b["closure"]) and b["closure"] <= BUDGET_CONSISTENCY_MAX and aligned
        checks.append(Check(name, ok,
                            f"||e_total - sum d_k|| / ||e_total|| = {b['closure']:.2e} <= {BUDGET_CONSISTENCY_MAX:g}; "
                            f"shares sum to {b['share_sum']:.6f}; every computation has all {b['rows_model']} rows of M"
                            + ("" if aligned else f" (only {b['rows_used']} in common)"), consistency=True))
    # Every run of the report completed.
    failed = [r for r in results["all_runs"] if not r.ok]
    checks.append(Check("every run completed", not failed, f"{len(results['all_runs']) - len(failed)} of "
                        f"{len(results['all_runs'])}" + "".join(f"; {r.case.name}: {r.message}" for r in failed)))
    # The user deck of the explicit beam near the stable step follows the report's rule.
    try:
        d = decks.load(os.path.join(results["repo"], STABLE_USER_DECK))
        dt = float(decks.get(d, "Integrator/Time Step"))
        steps = int(decks.get(d, "Integrator/Number of Steps"))
        want = EXPLICIT_DT_FRACTION * decks.stable_time_step(d)
        ok = abs(dt / want - 1) <= 1e-4 and steps * dt >= 1.0 > (steps - 1) * dt
        checks.append(Check(f"{STABLE_USER_DECK}", ok, f"dt = {dt:.6g} s = {dt / want * EXPLICIT_DT_FRACTION:.5f} x impm's "
                            f"stable limit {want / EXPLICIT_DT_FRACTION:.5g} s (want {EXPLICIT_DT_FRACTION:g}); "
                            f"{steps} steps reach {steps * dt:.5g} s"))
    except (OSError, KeyError, TypeError, ValueError) as e:
        checks.append(Check(f"{STABLE_USER_DECK}", False, f"cannot read: {e}"))
    # Our recomputation of impm's errors from history.csv matches summary.yaml.
    worst, where = 0.0, ""
    for run in results["all_runs"]:
        if not run.ok:
            continue
        for mon, e_impm in (run.summary.get("Relative L2 Error") or {}).items():
            e = results["recomputed"][run.case.name].get(mon)
            if e is None or not _finite(e, float(e_impm)):
                continue
            dev = abs(e - float(e_impm)) / max(abs(float(e_impm)), 1e-300)
            if dev > worst:
                worst, where = dev, f"{run.case.name}/{mon}"
    checks.append(Check("errors recomputed from history.csv agree with summary.yaml", worst <= SUMMARY_AGREEMENT,
                        f"largest relative difference {worst:.1e} <= {SUMMARY_AGREEMENT:g}" + (f" ({where})" if where else "")))
    return checks
