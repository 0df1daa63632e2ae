"""The runs of the verification report, built from the base decks in apps/.

Every case is a base deck plus overrides; its name says what differs from the seed's settings, so
two studies that need the same computation share one run (same name, same deck).

Problem 1 (bar) and Problem 2 (beam) are those of ../shared/reference/benchmarks.md.
"""
import math
from dataclasses import dataclass, field

import decks

METHODS = ("explicit MPM", "explicit GIMP", "implicit MPM", "implicit GIMP", "FE Q4", "FE Q9")
IMPLICIT_METHODS = ("implicit MPM", "implicit GIMP", "FE Q4", "FE Q9")
PLANES = ("Plane Stress", "Plane Strain")
PROBLEMS = ("bar", "beam")
MONITORS = {"bar": ("ux_L", "ux_half", "sxx_half"), "beam": ("w_mid",)}
MONITOR_LABELS = {"ux_L": "u_x(L, t)", "ux_half": "u_x(L/2, t)", "sxx_half": "sigma_xx(L/2, t)",
                  "w_mid": "w(L/2, t)"}
PROBLEM_LABELS = {"bar": "Problem 1 (bar, step load)", "beam": "Problem 2 (beam, harmonic load)"}

# Grids: (Cells X, Cells Y, Cell Size X, Cell Size Y). MPM and GIMP use the seed's grids. FE on
# the bar uses the seed's FE layout, 30 x 2 elements (Q4: 30 x 2 cells; Q9: an element is 2 x 2
# cells, so 60 x 4 cells). FE on the beam uses the seed's 40 x 4 grid (Q4: 40 x 4 elements, the
# seed's; Q9: 20 x 2 elements on the same nodes).
GRIDS = {
    ("bar", "MPM"): (30, 1, 1.0e-3, 0.5e-3),
    ("bar", "FE Q4"): (30, 2, 1.0e-3, 0.25e-3),
    ("bar", "FE Q9"): (60, 4, 0.5e-3, 0.125e-3),
    ("beam", "MPM"): (40, 4, 0.25, 0.125),
    ("beam", "FE Q4"): (40, 4, 0.25, 0.125),
    ("beam", "FE Q9"): (40, 4, 0.25, 0.125),
}

# Short windows of the studies (documented in the report):
BAR_STUDY_END = 2.4e-5   # about one period 4L/c = 2.37e-5 s of the plane-stress bar (2400 steps of 1e-8)
REDUCED_BEAM_END = 0.25  # about 2.9 periods of the first mode (250 steps of 1e-3)


# Variants of a method, beside the decks' settings.
VARIANTS = {
    # Consistent mass: the residual uses M_C and each particle takes its own Newmark update, so
    # that residual and particle update are one trapezoidal rule (doc/method.md). Without the
    # consistent-projection correction, which the consistent mass does not need.
    "cmass": {"Integrator/Implicit/Mass Matrix": "Consistent",
              "Integrator/Implicit/Consistent Projection Iterations": 0},
}
CMASS_LABEL = "implicit MPM, consistent mass"
# Explicit beam: this fraction of the stable limit impm checks (decks.stable_time_step).
EXPLICIT_DT_FRACTION = 0.9
STABLE_USER_DECK = "apps/beam_explicit_mpm_plane_strain_stable.yaml"


def shape_of(method):
    return method.split()[-1] if method.startswith(("explicit", "implicit")) else method


def slug(method):
    return method.lower().replace(" ", "_")


@dataclass
class Case:
    name: str
    problem: str
    method: str
    plane: str
    deck: dict
    refine: int = 1
    dt_div: int = 1

    @property
    def dt(self):
        return float(decks.get(self.deck, "Integrator/Time Step"))

    @property
    def steps(self):
        return int(decks.get(self.deck, "Integrator/Number of Steps"))

    @property
    def grid(self):
        g = self.deck["impm"]["Grid"]
        return int(g["Cells X"]), int(g["Cells Y"])

    @property
    def exact_modulus(self):
        return decks.get(self.deck, "Exact Solution/Modulus", "Plane Condition")


@dataclass
class Capabilities:
    """What the impm binary offers (from impm --help)."""
    fe: bool = False
    gimp_consistent_stiffness: bool = False

    @classmethod
    def from_help(cls, text):
        return cls(fe="FE Q4" in text, gimp_consistent_stiffness="GIMP Stiffness" in text)


def base_deck_path(problem, method, plane):
    kind = "explicit" if method.startswith("explicit") else "implicit"
    shape = shape_of(method).lower()
    if shape.startswith("fe"):
        shape = "mpm"  # FE cases start from the implicit MPM deck
    if problem == "beam":
        # The beam decks are implicit plane strain only; the explicit beam and plane stress are overrides.
        return f"apps/beam_implicit_{shape}_plane_strain.yaml"
    return f"apps/bar_{kind}_{shape}_{plane.lower().replace(' ', '_')}.yaml"


def make_case(repo, caps, problem, method, plane, *, refine=1, dt_div=1, t_end=None,
              exact_modulus=None, fast_solver=False, variant=None):
    """One run: the base deck of (problem, method, plane) with the study's changes.

    refine      grid refinement factor (bar: along the bar only, it is one-dimensional; beam: both)
    dt_div      time step divided by this (History Interval multiplied, so rows keep their times)
    t_end       final time (default: the base deck's, 1e-4 s for the bar, 1 s for the beam)
    exact_modulus  'Young Modulus' for the seed's comparison (default: the plane condition's)
    fast_solver Newton with the assembled Jacobian and a direct solve (KLU2): one Newton
                iteration per step for MPM and FE, faster than the Jacobian-free decks on
                refined grids; the converged answer is the same to the solver tolerance.
    variant     a key of VARIANTS: further overrides, named in the case name
    """
    base = decks.load(f"{repo}/{base_deck_path(problem, method, plane)}")
    shape = shape_of(method)
    fe = shape.startswith("FE")
    ov = {"Material/Plane Condition": plane, "Output/Plot": False, "Output/Progress": False,
          "Output/VTK Interval": 0}
    nx, ny, hx, hy = GRIDS[(problem, shape if fe else "MPM")]
    if problem == "bar":
        nx, hx = nx * refine, hx / refine
    else:
        nx, ny, hx, hy = nx * refine, ny * refine, hx / refine, hy / refine
    ov.update({"Grid/Cells X": nx, "Grid/Cells Y": ny, "Grid/Cell Size X": hx, "Grid/Cell Size Y": hy})
    if fe:
        ov.update({"Method/Shape Function": shape, "Integrator/Implicit/Mass Matrix": "Consistent",
                   "Integrator/Implicit/Consistent Projection Iterations": decks.DELETE,
                   "Body/Particles Per Cell X": decks.DELETE, "Body/Particles Per Cell Y": decks.DELETE})
    if exact_modulus:
        ov["Exact Solution/Modulus"] = exact_modulus
    dt0 = float(decks.get(base, "Integrator/Time Step"))
    end0 = dt0 * int(decks.get(base, "Integrator/Number of Steps"))
    end = t_end if t_end is not None else end0
    hist0 = int(decks.get(base, "Output/History Interval", 10))
    if problem == "beam" and method.startswith("explicit"):
        # The seed's explicit beam (dt = 1e-7, 1e7 steps) takes long; a step near the stable limit.
        ov.update({"Integrator/Type": "Explicit", "Integrator/Implicit": decks.DELETE,
                   "Implicit Solver": decks.DELETE,
                   "Integrator/Explicit": {"Update Scheme": "USL", "FLIP Fraction": 1.0,
                                           "Consistent Projection Iterations": 1}})
        limit = decks.stable_time_step(decks.apply(base, ov))
        dt = EXPLICIT_DT_FRACTION * limit / dt_div
        steps = math.ceil(end / dt - 1e-9)
        hist = max(1, round(1e-3 / dt))
    else:
        dt = dt0 / dt_div
        steps = int(round(end / dt))
        hist = hist0 * dt_div
    ov.update({"Integrator/Time Step": dt, "Integrator/Number of Steps": steps, "Output/History Interval": hist})
    # GIMP's assembled Newton needs its consistent stiffness to converge in one iteration.
    fast = fast_solver and not method.startswith("explicit") and not (
        shape == "GIMP" and not caps.gimp_consistent_stiffness)
    if fast:
        ov["Implicit Solver/Jacobian"] = "Assembled"
        if shape == "GIMP":
            ov["Integrator/Implicit/GIMP Stiffness"] = "Consistent"
    if variant in VARIANTS:
        ov.update(VARIANTS[variant])
    deck = decks.apply(base, ov)

    name = f"{problem}_{slug(method)}_{plane.split()[1].lower()}"
    if variant:
        name += f"_{variant}"
    if refine != 1:
        name += f"_h{refine}"
    if dt_div != 1:
        name += f"_dt{dt_div}"
    if t_end is not None and abs(end - end0) > 1e-12 * end0:
        name += f"_t{end:g}"
    if exact_modulus == "Young Modulus":
        name += "_E"
    if fast:
        name += "_asm"
    deck["impm"]["Problem"]["Name"] = name.replace("_", " ")
    deck["impm"]["Problem"]["Output Directory"] = f"output/verification/runs/{name}"
    return Case(name=name, problem=problem, method=method, plane=plane, deck=deck, refine=refine, dt_div=dt_div)


# ---------------------------------------------------------------- the plan

@dataclass
class Study:
    """A refinement study: for each method, a list of runs (coarse first)."""
    key: str
    problem: str
    plane: str
    kind: str            # "grid" or "dt"
    factors: list
    t_end: float
    monitors: tuple
    series: dict = field(default_factory=dict)  # method -> [Case]


@dataclass
class Budget:
    """Problem 2's discrepancy budget: runs M (seed's grid and dt, compared with EB at E)."""
    t_end: float
    models: dict          # method -> Case (Exact Solution/Modulus: Young Modulus)
    fe_fine: Case         # FE Q9 on a fine grid, same dt
    fe_same: Case         # FE Q9 on the seed's 40 x 4 grid


@dataclass
class Plan:
    reduced: bool
    main: dict            # (problem, method, plane) -> Case
    main_t_end: dict      # problem -> final time of the main runs
    studies: list
    budget: Budget
    caps: Capabilities

    def cases(self):
        seen = {}
        for c in self.main.values():
            seen.setdefault(c.name, c)
        for s in self.studies:
            for runs in s.series.values():
                for c in runs:
                    seen.setdefault(c.name, c)
        b = self.budget
        for c in list(b.models.values()) + [b.fe_same, b.fe_fine]:
            seen.setdefault(c.name, c)
        return list(seen.values())


def build_plan(repo, caps, reduced):
    mk = lambda *a, **k: make_case(repo, caps, *a, **k)  # noqa: E731
    # The FE cases stay in the plan even when the binary lacks FE: they fail with impm's own
    # message, and the report and --check say so.
    methods, implicit = METHODS, IMPLICIT_METHODS

    main, main_end = {}, {}
    if reduced:
        # Problem 1 on the seed's grids and dt over about one period (2400 steps).
        main_end["bar"] = BAR_STUDY_END
        for plane in PLANES:
            for m in methods:
                main[("bar", m, plane)] = mk("bar", m, plane, t_end=BAR_STUDY_END)
    else:
        main_end["bar"], main_end["beam"] = 1.0e-4, 1.0
        for problem in PROBLEMS:
            for plane in PLANES:
                for m in methods:
                    main[(problem, m, plane)] = mk(problem, m, plane)

    studies = []
    if reduced:
        # Newmark's order where the discrete spectrum is resolved (FE Q4 bar), and the beam's.
        s = Study("bar_dt", "bar", "Plane Stress", "dt", [1, 2, 4], BAR_STUDY_END, MONITORS["bar"])
        s.series["FE Q4"] = [mk("bar", "FE Q4", s.plane, dt_div=d, t_end=BAR_STUDY_END, fast_solver=True)
                             for d in s.factors]
        studies.append(s)
        s = Study("beam_dt", "beam", "Plane Strain", "dt", [1, 2, 4, 8], REDUCED_BEAM_END, ("w_mid",))
        s.series["implicit MPM"] = [mk("beam", "implicit MPM", "Plane Strain", dt_div=d, t_end=REDUCED_BEAM_END,
                                       fast_solver=True) for d in s.factors]
        studies.append(s)
    else:
        s = Study("bar_grid", "bar", "Plane Stress", "grid", [1, 2, 4], 1.0e-4, MONITORS["bar"])
        # The explicit methods too (cheap on the bar: dt = 1e-8 stays below the x4 grid's limit).
        for m in ("explicit MPM", "explicit GIMP") + tuple(implicit):
            s.series[m] = [mk("bar", m, s.plane, refine=r, fast_solver=True) for r in s.factors]
        studies.append(s)
        s = Study("bar_dt", "bar", "Plane Stress", "dt", [1, 2, 4], BAR_STUDY_END, MONITORS["bar"])
        for m in implicit:
            s.series[m] = [mk("bar", m, s.plane, dt_div=d, t_end=BAR_STUDY_END, fast_solver=True) for d in s.factors]
        s.series[CMASS_LABEL] = [mk("bar", "implicit MPM", s.plane, dt_div=d, t_end=BAR_STUDY_END, fast_solver=True,
                                    variant="cmass") for d in s.factors]
        studies.append(s)
        s = Study("beam_grid", "beam", "Plane Strain", "grid", [1, 2, 4], 1.0, ("w_mid",))
        for m in implicit:
            s.series[m] = [mk("beam", m, s.plane, refine=r, fast_solver=True) for r in s.factors]
        studies.append(s)
        s = Study("beam_dt", "beam", "Plane Strain", "dt", [1, 2, 4, 8], 1.0, ("w_mid",))
        for m in implicit:
            s.series[m] = [mk("beam", m, s.plane, dt_div=d, fast_solver=True) for d in s.factors]
        studies.append(s)

    # Budget: each implicit method's run M on the seed's grid and dt, compared with EB at E.
    t_end = REDUCED_BEAM_END if reduced else None
    fine = 2 if reduced else 4
    budget_methods = ("implicit MPM",) if reduced else implicit
    models = {m: mk("beam", m, "Plane Strain", t_end=t_end, exact_modulus="Young Modulus") for m in budget_methods}
    fe_same = mk("beam", "FE Q9", "Plane Strain", t_end=t_end, exact_modulus="Young Modulus")
    fe_fine = mk("beam", "FE Q9", "Plane Strain", refine=fine, t_end=t_end, exact_modulus="Young Modulus",
                 fast_solver=True)
    budget = Budget(t_end=t_end if t_end else 1.0, models=models, fe_fine=fe_fine, fe_same=fe_same)
    return Plan(reduced=reduced, main=main, main_t_end=main_end, studies=studies, budget=budget, caps=caps)
