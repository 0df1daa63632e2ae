#!/usr/bin/python3
"""impm against another MPM code on the same explicit bar, at equal cores.

The bar: 300 x 10 square cells of 1 mm, 5 x 5 particles per cell (75,000 particles), linear
elastic steel (E = 200 GPa, nu = 0.3, rho = 7800 kg/m^3, plane strain), linear MPM, USL, FLIP,
dt = 1e-8 s, the left end fixed in x. Each code runs it for N1 and N2 steps (default 300 and 900)
and the script reports, per code:
  loop   particle-steps per second of the time-stepping loop, from the difference of the two runs'
         loop times (set-up, first-touch and output cancel out);
  whole  the whole process's seconds for N1 steps (as a user waits for it: start, set-up, loop,
         output, exit), and its overhead beyond N1 steps of the loop.
impm runs as one process with --cores OpenMP threads (its loop time is summary.yaml's Wall Time);
Karamelo (github.com/adevaucorbeil/karamelo, MPI only) runs as --cores MPI ranks, its loop time
the interval between its step-0 and step-N log lines (it prints no loop timer). The ratio
impm / peer is of the loop rates and of the whole-process times.

  /usr/bin/python3 apps/peer_comparison.py                      (impm only, when no peer is found)
  /usr/bin/python3 apps/peer_comparison.py --karamelo /path/to/karamelo --cores 2 --repeat 3

A peer is used when --karamelo names it or `karamelo` is on PATH. Run on a quiet machine: another
process on the cores measures contention. Writes peer_comparison.md and .yaml into --out.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(HERE, "verification"))
import decks  # noqa: E402

BASE_DECK = os.path.join(HERE, "scaling_bar_explicit_mpm.yaml")
PPC = 5
CELL = 1.0e-3  # m, square cells (Karamelo takes one cell size)

KARAMELO_STEP = re.compile(r"^(\d+)\t([-+0-9.eE]+)\t([-+0-9.eE]+)\t?$")

# Karamelo's input language reads number literals in single precision: non-integers are written
# as ratios, which it evaluates in double.
KARAMELO_DECK = """# impm's peer-comparison bar (apps/peer_comparison.py): 2D ULMPM, linear basis, FLIP, USL
E      = 2e+11
nu     = 3/10
rho    = 7800
Lx     = {cells_x}/1000
Ly     = {cells_y}/1000
h      = 1/1000
ppc1d  = {ppc}
v0     = 1
alpha  = 1
method(ulmpm, FLIP, linear, alpha)
scheme(usl)
dimension(2, 0, Lx, 0, Ly, h)
region(rBar, block, 0, Lx, 0, Ly)
material(mSteel, linear, rho, E, nu)
solid(sBar, region, rBar, ppc1d, mSteel, h, 0)
region(rLeft, block, INF, h/4, INF, INF)
group(gLeft, nodes, region, rLeft, solid, sBar)
fix(fLeft, velocity_nodes, gLeft, 0, NULL)
fix(fV0, initial_velocity_particles, all, v0, NULL, NULL)
set_dt(1e-8)
set_output({steps})
run({steps})
"""


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--build-dir", default=os.path.join(REPO, "build"), help="impm build directory (default: build)")
    p.add_argument("--cores", type=int, default=2, help="OpenMP threads for impm, MPI ranks for the peer (default 2)")
    p.add_argument("--steps", default="300,900", help="the two step counts N1,N2 (default 300,900)")
    p.add_argument("--cells-x", type=int, default=300, help="cells along the bar (default 300: 75,000 particles)")
    p.add_argument("--repeat", type=int, default=1, help="runs per step count; the fastest counts (default 1)")
    p.add_argument("--karamelo", default=None, help="the Karamelo executable (default: `karamelo` on PATH, if any)")
    p.add_argument("--mpiexec", default="mpiexec", help="MPI launcher for the peer (default mpiexec)")
    p.add_argument("--out", default=os.path.join(REPO, "output", "peer_comparison"), help="output directory")
    return p.parse_args(argv)


def fail(message):
    print(f"peer_comparison: error: {message}", file=sys.stderr)
    sys.exit(2)


def check_args(a):
    try:
        steps = [int(s) for s in a.steps.split(",")]
    except ValueError:
        fail(f"--steps '{a.steps}' is not two integers N1,N2")
    if len(steps) != 2 or not 0 < steps[0] < steps[1]:
        fail(f"--steps '{a.steps}' must be two step counts 0 < N1 < N2")
    if a.cores < 1:
        fail(f"--cores {a.cores} must be at least 1")
    if a.cells_x < 2:
        fail(f"--cells-x {a.cells_x} must be at least 2")
    if a.repeat < 1:
        fail(f"--repeat {a.repeat} must be at least 1")
    impm = os.path.join(os.path.abspath(a.build_dir), "apps", "impm")
    if not os.access(impm, os.X_OK):
        fail(f"no impm in {a.build_dir}/apps (build first: cmake/build.sh)")
    peer = a.karamelo
    if peer is not None:
        if not os.access(peer, os.X_OK) or os.path.isdir(peer):
            fail(f"--karamelo '{peer}' is not an executable")
    else:
        peer = shutil.which("karamelo")
    return steps, impm, peer and os.path.abspath(peer)


# ---------------------------------------------------------------- impm

def impm_deck(cells_x, steps, out_dir):
    cells_y = 10
    ov = {"Problem/Name": "peer-comparison bar, explicit MPM",
          "Problem/Output Directory": out_dir,
          "Grid/Cells X": cells_x, "Grid/Cells Y": cells_y, "Grid/Cell Size X": CELL, "Grid/Cell Size Y": CELL,
          "Grid/Plane Condition": "Plane Strain",
          "Bodies/bar/X Max": cells_x * CELL, "Bodies/bar/Y Max": cells_y * CELL,
          "Integrator/Number of Steps": steps,
          "Integrator/Explicit/Consistent Projection Iterations": 0,
          "Integrator/Explicit/FLIP Fraction": 1.0,
          "Output/History Interval": steps, "Output/VTK Interval": 0, "Output/Plot": False, "Output/Progress": False}
    return decks.apply(decks.load(BASE_DECK), ov)


def run_impm(impm, cells_x, steps, cores, work):
    run_dir = os.path.join(work, f"impm_{steps}")
    os.makedirs(run_dir, exist_ok=True)
    deck_path = os.path.join(work, f"impm_{steps}.yaml")
    with open(deck_path, "w") as f:
        f.write(decks.dump(impm_deck(cells_x, steps, run_dir)))
    env = dict(os.environ, OMP_NUM_THREADS=str(cores))
    t0 = time.monotonic()
    p = subprocess.run([impm, deck_path, "--output", run_dir], capture_output=True, text=True, env=env)
    whole = time.monotonic() - t0
    if p.returncode != 0:
        fail(f"impm failed on {deck_path} (exit {p.returncode}): " + "".join(p.stderr.strip().splitlines()[-1:]))
    with open(os.path.join(run_dir, "summary.yaml")) as f:
        s = yaml.safe_load(f)["summary"]
    return {"loop": float(s["Wall Time"]), "whole": whole, "particles": int(s["Particles"])}


# ---------------------------------------------------------------- Karamelo

def run_karamelo(exe, mpiexec, cells_x, steps, cores, work):
    run_dir = os.path.join(work, f"karamelo_{steps}")
    os.makedirs(run_dir, exist_ok=True)
    with open(os.path.join(run_dir, "bar.mpm"), "w") as f:
        f.write(KARAMELO_DECK.format(cells_x=cells_x, cells_y=10, ppc=PPC, steps=steps))
    cmd = ["stdbuf", "-oL", exe, "-i", "bar.mpm"] if shutil.which("stdbuf") else [exe, "-i", "bar.mpm"]
    if cores > 1:
        cmd = [mpiexec, "--allow-run-as-root", "--bind-to", "core", "-np", str(cores)] + cmd
    stamps, lines = {}, []
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, cwd=run_dir, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
    for line in p.stdout:
        now = time.monotonic()
        lines.append(line)
        m = KARAMELO_STEP.match(line.rstrip("\n"))
        if m:
            stamps.setdefault(int(m.group(1)), now)
    p.wait()
    whole = time.monotonic() - t0
    with open(os.path.join(run_dir, "karamelo.log"), "w") as f:
        f.writelines(lines)
    if p.returncode != 0 or 0 not in stamps or steps not in stamps:
        fail(f"the peer failed on {run_dir}/bar.mpm (exit {p.returncode}; log lines for steps 0 and {steps} "
             f"{'found' if 0 in stamps and steps in stamps else 'missing'}; see karamelo.log there)")
    particles = sum(int(m.group(1)) for m in (re.match(r"^np_local=(\d+)", l) for l in lines) if m)
    return {"loop": stamps[steps] - stamps[0], "whole": whole, "particles": particles or cells_x * 10 * PPC * PPC}


# ---------------------------------------------------------------- figures

def best_of(repeat, run):
    runs = [run() for _ in range(repeat)]
    return min(runs, key=lambda r: r["loop"])


def figures(runs, steps):
    """Loop particle-steps/s from the difference of the runs; whole-process time and overhead at N1."""
    (n1, r1), (n2, r2) = sorted(runs.items())
    particles = r1["particles"]
    per_step = (r2["loop"] - r1["loop"]) / (n2 - n1)
    return {"particles": particles, "loop_rate": particles / per_step if per_step > 0 else float("nan"),
            "whole": r1["whole"], "overhead": r1["whole"] - n1 * per_step, "steps": n1,
            "loop_seconds": {n1: r1["loop"], n2: r2["loop"]}, "whole_seconds": {n1: r1["whole"], n2: r2["whole"]}}


def measure(label, repeat, steps, run):
    runs = {}
    for n in steps:
        print(f"peer_comparison: {label}, {n} steps ...", flush=True)
        runs[n] = best_of(repeat, lambda: run(n))
    return figures(runs, steps)


def table(rows):
    head = ["code", "cores", "particles", "loop M particle-steps/s", "whole process, N1 steps (s)", "overhead (s)"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for name, cores, f in rows:
        out.append(f"| {name} | {cores} | {f['particles']} | {f['loop_rate'] / 1e6:.3g} | {f['whole']:.3g} | "
                   f"{f['overhead']:.3g} |")
    return out


def main(argv=None):
    a = parse_args(argv if argv is not None else sys.argv[1:])
    steps, impm, peer = check_args(a)
    out = os.path.abspath(a.out)
    work = os.path.join(out, "runs")
    os.makedirs(work, exist_ok=True)
    rows = [("impm", a.cores, measure("impm", a.repeat, steps,
                                      lambda n: run_impm(impm, a.cells_x, n, a.cores, work)))]
    if peer:
        rows.append(("Karamelo", a.cores, measure("Karamelo", a.repeat, steps,
                                                  lambda n: run_karamelo(peer, a.mpiexec, a.cells_x, n, a.cores, work))))
    else:
        print("peer_comparison: no peer code found (give --karamelo PATH or put karamelo on PATH); impm figures only")
    lines = [f"Bar of {a.cells_x} x 10 cells, {PPC} x {PPC} particles per cell, {steps[0]} and {steps[1]} steps, "
             f"best of {a.repeat}; impm: {impm}" + (f"; peer: {peer}" if peer else ""), ""] + table(rows)
    result = {"cores": a.cores, "steps": steps, "cells_x": a.cells_x, "repeat": a.repeat,
              "codes": {name: {k: v for k, v in f.items()} for name, _, f in rows}}
    if peer:
        i, k = rows[0][2], rows[1][2]
        result["ratio"] = {"loop": i["loop_rate"] / k["loop_rate"], "whole": k["whole"] / i["whole"]}
        lines += ["", f"impm / Karamelo at {a.cores} cores: loop {result['ratio']['loop']:.3g} times the particle-steps "
                      f"per second; whole process for {steps[0]} steps {i['whole']:.3g} s against {k['whole']:.3g} s"]
    print("\n".join(lines))
    with open(os.path.join(out, "peer_comparison.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(out, "peer_comparison.yaml"), "w") as f:
        yaml.safe_dump(result, f, sort_keys=False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
