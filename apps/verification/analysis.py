"""Numbers of the verification report, computed from the runs' histories.

Relative L2 errors follow impm's definition (doc/user-guide.md, "Outputs"): sqrt(sum (computed -
reference)^2 / sum reference^2) over the rows of history.csv, here optionally restricted to
t <= t_end so that a study can use a shorter window of a longer run.
"""
import math

import numpy as np

import decks


def rel_l2(values, reference):
    den = float(np.sum(np.square(reference)))
    return math.sqrt(float(np.sum(np.square(values - reference))) / den) if den > 0 else float("nan")


def window(run, t_end=None):
    t = run.history["time"]
    return np.ones_like(t, dtype=bool) if t_end is None else t <= t_end * (1 + 1e-9)


def error_vs_exact(run, monitor, t_end=None):
    """Relative L2 error of a monitor against its `_exact` column (NaN when the run failed)."""
    if not run.ok or monitor not in run.history:
        return float("nan")
    m = window(run, t_end)
    return rel_l2(run.history[monitor][m], run.history[monitor + "_exact"][m])


def orders(errors):
    """Observed orders log2(e_k / e_{k+1}) between successive halvings."""
    out = []
    for a, b in zip(errors[:-1], errors[1:]):
        out.append(math.log2(a / b) if (a > 0 and b > 0 and np.isfinite(a) and np.isfinite(b)) else float("nan"))
    return out


def aligned(runs, monitor, t_end=None):
    """(times, [values of each run]) on the rows the runs share (matched by time)."""
    keys = None
    tables = []
    for r in runs:
        m = window(r, t_end)
        t = r.history["time"][m]
        scale = max(float(np.max(np.abs(t))), 1e-300)
        k = np.round(t / scale * 1e9).astype(np.int64)
        tables.append(dict(zip(k.tolist(), r.history[monitor][m].tolist())))
        keys = set(k.tolist()) if keys is None else keys & set(k.tolist())
    keys = sorted(keys)
    times = np.array(keys, dtype=float) * 1e-9 * scale
    return times, [np.array([tab[k] for k in keys]) for tab in tables]


def self_convergence(runs, monitor, t_end=None):
    """Differences of successive halvings of dt on one grid, relative L2 over the finer run.

    Returns (differences d_k = ||w_k - w_{k+1}|| / ||w_{k+1}||, orders log2(d_k / d_{k+1}), rows)."""
    if not all(r.ok for r in runs):
        return [float("nan")] * (len(runs) - 1), [float("nan")] * max(0, len(runs) - 2), 0
    times, vals = aligned(runs, monitor, t_end)
    diffs = [rel_l2(a, b) for a, b in zip(vals[:-1], vals[1:])]
    return diffs, orders(diffs), len(times)


# ---------------------------------------------------------------- 1D bar reference (tolerance)

def _bar_parameters(case):
    """(E, rho, L, A, F0) of Problem 1's bar, with the modulus the exact column uses."""
    d = case.deck
    E, nu, rho, strain = decks.moduli(d)
    if case.exact_modulus != "Young Modulus" and strain:
        E = E / (1 - nu * nu)
    b = d["impm"]["Body"]
    L = float(b["X Max"]) - float(b["X Min"])
    A = (float(b["Y Max"]) - float(b["Y Min"])) * float(d["impm"]["Material"]["Thickness"])
    F0 = float(d["impm"]["Loads"]["end force"]["Force X"])
    return E, rho, L, A, F0


def bar_closed_form(x, t, E, rho, L, A, F0, stress=False):
    """The bar fixed at x = 0 under a step end force F0 at x = L, written here independently of impm
    (whose exact column it checks): the loaded end sends the strain F0 / (E A) towards x = 0, which
    reflects it with the same sign, and the free end with the opposite one. By images,
        u(x, t) = F0 / (E A) sum_n (-1)^n [R(c t - (2n+1) L + x) - R(c t - (2n+1) L - x)],
    R(s) = max(s, 0), and sigma = E du/dx with the ramps replaced by unit steps (both signs +)."""
    t = np.asarray(t, dtype=float)
    ct = np.sqrt(E / rho) * t
    out = np.zeros_like(ct)
    for n in range(int(np.max(ct) / (2 * L)) + 2):
        lead, trail = ct - (2 * n + 1) * L + x, ct - (2 * n + 1) * L - x
        if stress:
            term = np.heaviside(lead, 0.5) + np.heaviside(trail, 0.5)
        else:
            term = np.maximum(lead, 0.0) - np.maximum(trail, 0.0)
        out += (-1) ** n * term
    return out * (F0 / A if stress else F0 / (E * A))


def bar_exact_series(case, run, monitor):
    """bar_closed_form at the run's monitored particle and history rows."""
    E, rho, L, A, F0 = _bar_parameters(case)
    x0, _ = run.monitor_position(monitor)
    x0 -= float(case.deck["impm"]["Body"]["X Min"])
    return bar_closed_form(x0, run.history["time"], E, rho, L, A, F0, stress=monitor.startswith("sxx"))


def exact_column_deviation(case, run, monitor):
    """Relative L2 difference between impm's `_exact` column and bar_closed_form (NaN if absent)."""
    if not run.ok or monitor + "_exact" not in run.history:
        return float("nan")
    return rel_l2(run.history[monitor + "_exact"], bar_exact_series(case, run, monitor))


def bar_fe1d(case, run, monitor, elements):
    """Relative L2 error of a 1D two-node-element, lumped-mass model of the bar with `elements`
    elements, Newmark average acceleration at the run's dt, evaluated at the run's monitored
    particle and history rows, against bar_closed_form (not the run's exact column, so that a
    wrong exact column cannot widen the tolerance built on this error).

    With the seed's MPM grid (30 cells along the bar) it is what that nodal resolution gives for a
    1D rod; the Problem 1 tolerance of --check is a multiple of it."""
    E, rho, L, A, F0 = _bar_parameters(case)
    b = case.deck["impm"]["Body"]
    h = L / elements
    n = elements  # unknowns: nodes 1..n (node 0 fixed)
    K = np.zeros((n, n))
    k = E * A / h
    for e in range(elements):  # element e joins nodes e and e+1 (unknown index node-1)
        i, j = e - 1, e
        if i >= 0:
            K[i, i] += k; K[i, j] -= k; K[j, i] -= k
        K[j, j] += k
    m = np.full(n, rho * A * h)
    m[-1] *= 0.5
    F = np.zeros(n)
    F[-1] = F0
    dt = case.dt
    S = np.diag(4 / dt ** 2 * m) + K
    Sinv = np.linalg.inv(S)
    x0, _ = run.monitor_position(monitor)
    x0 -= float(b["X Min"])
    t = run.history["time"]
    idx = np.round(t / dt).astype(int)
    u, v = np.zeros(n), np.zeros(n)
    a = F / m
    want = set(idx.tolist())
    series = {}
    stress = monitor.startswith("sxx")
    e_el = min(int(x0 / h), elements - 1)
    xi = x0 / h - e_el

    def sample(u):
        full = np.concatenate([[0.0], u])
        if stress:
            return E * (full[e_el + 1] - full[e_el]) / h
        return (1 - xi) * full[e_el] + xi * full[e_el + 1]

    if 0 in want:
        series[0] = sample(u)
    for step in range(1, int(idx.max()) + 1):
        rhs = F + m * (4 / dt ** 2 * u + 4 / dt * v + a)
        un = Sinv @ rhs
        an = 4 / dt ** 2 * (un - u) - 4 / dt * v - a
        v = v + dt / 2 * (a + an)
        u, a = un, an
        if step in want:
            series[step] = sample(u)
    values = np.array([series[i] for i in idx])
    return rel_l2(values, bar_exact_series(case, run, monitor))


# ---------------------------------------------------------------- first-mode frequency

def fit_first_mode(t, w, forcing, guess, lo=0.3, hi=3.0):
    """Frequency of the free-vibration part of a forced response.

    w(t) ~ a sin(W t) + b cos(W t) + c sin(w1 t) + d cos(w1 t) + e sin(9 w1 t) + f cos(9 w1 t)
    (forcing W; the third mode, about 9 w1 in a beam, is a small correction): linear least squares
    for the amplitudes at each trial w1, and w1 minimises the residual (grid, then golden section)."""
    t = np.asarray(t, dtype=float)
    w = np.asarray(w, dtype=float)

    def residual(om):
        B = np.column_stack([np.sin(forcing * t), np.cos(forcing * t), np.sin(om * t), np.cos(om * t),
                             np.sin(9 * om * t), np.cos(9 * om * t)])
        coef, *_ = np.linalg.lstsq(B, w, rcond=None)
        return float(np.sum(np.square(B @ coef - w)))

    grid = np.linspace(lo * guess, hi * guess, 2701)
    res = [residual(o) for o in grid]
    i = int(np.argmin(res))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    g = (math.sqrt(5) - 1) / 2
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = residual(c), residual(d)
    for _ in range(80):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = residual(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = residual(d)
    return 0.5 * (a + b)


# ---------------------------------------------------------------- Problem 2 budget

# The chain of computations, each differing from the previous one in one respect.
BUDGET_LINKS = [
    ("eb_E", "Euler-Bernoulli, E (the seed's formula)", None),
    ("eb_Eprime", "Euler-Bernoulli, E' = E/(1-nu^2)", "plane strain modulus"),
    ("timo_Eprime", "Timoshenko, E'", "shear deformation + rotary inertia"),
    ("timo_Eprime_newmark", "Timoshenko, E', Newmark in time", "Newmark period elongation"),
    ("fe_fine", "FE Q9, fine grid, same dt", "2D continuum: point load and supports on the grid"),
    ("fe_same", "FE Q9, seed's 40 x 4 grid", "grid resolution (locking-free element)"),
    ("model", "the method's run M", "locking / interpolation of the method"),
]


def _index(times, dt):
    k = np.round(times / dt).astype(np.int64)
    if np.max(np.abs(times - k * dt)) > 1e-6 * dt:
        raise ValueError("history rows are not at multiples of dt")
    return k


def budget(model_run, exact_cols, freqs, fe_fine_run, fe_same_run, forcing):
    """The discrepancy budget of one run M against EB(E). Links whose run failed are merged into
    the next link (its label says so). Returns a dict with rows and the closure."""
    dt = model_run.case.dt
    km = _index(model_run.history["time"], dt)
    ke = _index(exact_cols["t"], dt)
    series = {name: dict(zip(ke.tolist(), exact_cols[name].tolist()))
              for name in ("eb_E", "eb_Eprime", "timo_Eprime", "timo_Eprime_newmark")}
    for name, run in (("fe_fine", fe_fine_run), ("fe_same", fe_same_run)):
        if run is not None and run.ok:
            kr = _index(run.history["time"], dt)
            series[name] = dict(zip(kr.tolist(), run.history["w_mid"].tolist()))
    series["model"] = dict(zip(km.tolist(), model_run.history["w_mid"].tolist()))
    e_total_map = dict(zip(km.tolist(), (model_run.history["w_mid"] - model_run.history["w_mid_exact"]).tolist()))
    common = set(km.tolist())
    for s in series.values():
        common &= set(s.keys())
    common = sorted(common)
    times = np.array(common, dtype=float) * dt
    vals = {n: np.array([s[k] for k in common]) for n, s in series.items()}
    e_total = np.array([e_total_map[k] for k in common])
    ref_norm = float(np.linalg.norm(vals["eb_E"]))
    ee = float(np.dot(e_total, e_total))

    # Fitted first-mode frequencies (the fitter is checked against the printed exact ones).
    guess = freqs.get("eb_E", 72.0)
    fitted = {n: fit_first_mode(times, v, forcing, guess) for n, v in vals.items()}

    rows = []
    prev = None
    skipped = []
    for name, what, effect in BUDGET_LINKS:
        if name not in vals:
            skipped.append(effect)
            continue
        if prev is not None:
            d = vals[name] - vals[prev]
            label = " + ".join(skipped + [effect]) if skipped else effect
            printed = None
            if name in freqs and prev in freqs:
                printed = freqs[name] / freqs[prev] - 1
            rows.append({
                "from": prev, "to": name, "effect": label, "what": what,
                "rel": float(np.linalg.norm(d)) / ref_norm,
                "share": float(np.dot(d, e_total)) / ee if ee > 0 else float("nan"),
                "freq_shift_exact": printed,
                "freq_shift_fit": fitted[name] / fitted[prev] - 1,
                "d": d,
            })
            skipped = []
        prev = name
    total = sum(r["d"] for r in rows)
    closure = float(np.linalg.norm(e_total - total)) / math.sqrt(ee) if ee > 0 else float("nan")
    return {
        "times": times, "values": vals, "e_total": e_total, "rows": rows,
        "total_rel": math.sqrt(ee) / ref_norm, "share_sum": sum(r["share"] for r in rows),
        "closure": closure, "fitted": fitted, "freqs": freqs, "rows_used": len(common),
        "rows_model": len(km),
    }
