"""Input decks for the verification report: load a base deck from apps/, override keys, write it.

A deck is the Teuchos YAML that build/apps/impm reads: one top-level key `impm` whose value is a
tree of sublists. Keys are addressed by slash paths below `impm`, e.g. "Integrator/Time Step".
"""
import copy
import hashlib
import math

import yaml

DELETE = object()  # override value that removes a key


def load(path):
    with open(path) as f:
        return yaml.safe_load(f)


def get(deck, path, default=None):
    node = deck["impm"]
    for key in path.split("/"):
        if not isinstance(node, dict) or key not in node:
            return default
        node = node[key]
    return node


def apply(deck, overrides):
    """A copy of `deck` with each "A/B/C": value of `overrides` set (sublists created as needed)."""
    out = copy.deepcopy(deck)
    for path, value in overrides.items():
        keys = path.split("/")
        node = out["impm"]
        for key in keys[:-1]:
            node = node.setdefault(key, {})
        if value is DELETE:
            node.pop(keys[-1], None)
        else:
            node[keys[-1]] = value
    return out


def dump(deck):
    """The deck as YAML text, in a stable form (its hash identifies a run)."""
    # (width: no plain scalar folded over two lines, which Teuchos' YAML parser refuses, e.g. a
    # polygon's vertex list.)
    return "%YAML 1.1\n---\n" + yaml.safe_dump(deck, sort_keys=False, default_flow_style=False,
                                                width=1 << 30) + "...\n"


def text_hash(text):
    return hashlib.sha256(text.encode()).hexdigest()


# ---------------------------------------------------------------- material and stability

def moduli(deck):
    """(E, nu, rho, plane strain?) of a deck."""
    m = deck["impm"]["Material"]
    return (float(m.get("Young Modulus", 200e9)), float(m.get("Poisson Ratio", 0.3)),
            float(m.get("Density", 7800.0)), m.get("Plane Condition", "Plane Strain") == "Plane Strain")


def p_wave_speed(deck):
    """P-wave speed of the 2D model, sqrt(c11 / rho) (physics/LinearElastic.hpp)."""
    E, nu, rho, strain = moduli(deck)
    c11 = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) if strain else E / (1 - nu * nu)
    return math.sqrt(c11 / rho)


# solvers/ExplicitStepper.hpp: the particle transfers' share of the bilinear cells' critical step.
TRANSFER_STABILITY_FRACTION = 0.7


def stable_time_step(deck):
    """The explicit limit impm checks (solvers/build/IntegratorSection.cpp): Stability Factor x 0.7 x the
    critical step of lumped bilinear cells, 1 / (c_p sqrt(1/hx^2 + 1/hy^2)) with c_p the 2D P-wave
    speed (0.7: apps/stability_study.py)."""
    g = deck["impm"]["Grid"]
    hx, hy = float(g["Cell Size X"]), float(g["Cell Size Y"])
    factor = float(get(deck, "Integrator/Explicit/Stability Factor", 1.0))
    return factor * TRANSFER_STABILITY_FRACTION / (p_wave_speed(deck) * math.sqrt(1 / hx ** 2 + 1 / hy ** 2))


# ---------------------------------------------------------------- monitored particle

def _axis_points(lo, hi, origin, h, placement, per_cell):
    """Reference coordinates of the particles along one axis of the body [lo, hi]."""
    first = round((lo - origin) / h)
    last = round((hi - origin) / h)
    pts = []
    if placement == "FE Q9":  # 3 Gauss points per element of two cells
        g = math.sqrt(0.6)
        for c in range(first, last, 2):
            mid = origin + (c + 1) * h
            pts += [mid - g * h, mid, mid + g * h]
    elif placement == "FE Q4":  # 2 Gauss points per cell
        g = 0.5 / math.sqrt(3.0)
        for c in range(first, last):
            mid = origin + (c + 0.5) * h
            pts += [mid - g * h, mid + g * h]
    else:  # MPM/GIMP: per_cell particles at the centres of equal sub-cells
        for c in range(first, last):
            pts += [origin + (c + (k + 0.5) / per_cell) * h for k in range(per_cell)]
    return pts


def monitor_position(deck, monitor):
    """Reference position of the particle nearest a monitor's point (what impm monitors).

    Used only when summary.yaml does not record it (Monitors/<name>/X, Y)."""
    d = deck["impm"]
    g, b = d["Grid"], d["Body"]
    shape = get(deck, "Method/Shape Function", "MPM")
    xs = _axis_points(float(b["X Min"]), float(b["X Max"]), float(g.get("Origin X", 0.0)),
                      float(g["Cell Size X"]), shape, int(b.get("Particles Per Cell X", 2)))
    ys = _axis_points(float(b["Y Min"]), float(b["Y Max"]), float(g.get("Origin Y", 0.0)),
                      float(g["Cell Size Y"]), shape, int(b.get("Particles Per Cell Y", 2)))
    m = d["Monitors"][monitor]
    px, py = float(m.get("X", 0.0)), float(m.get("Y", 0.0))
    x = min(xs, key=lambda v: abs(v - px))
    y = min(ys, key=lambda v: abs(v - py))
    return x, y
