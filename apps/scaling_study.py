#!/usr/bin/python3
"""Strong and weak scaling of an impm deck over OpenMP threads and MPI ranks.

Runs the deck (outputs off) once per configuration and reads each run's summary.yaml:
particle-steps per second, wall time per step, parallel efficiency against the first
configuration, peak resident memory per particle (summary.yaml, summed over the ranks), and the rank grid
with its worst load imbalance (max / mean particles per rank, summary.yaml Decomposition). Writes a
markdown table and a PNG into --out.

  strong scaling: the same deck at every (ranks, threads) of --ranks x --threads
  weak scaling:   --weak: the grid and the body grow along x with the number of workers
                  (ranks x threads), so that the particles per worker stay fixed

Sample runs (a quiet machine; threads x ranks <= cores, or the figures measure contention):
  /usr/bin/python3 apps/scaling_study.py apps/bar_explicit_mpm_plane_strain.yaml --steps 2000
  /usr/bin/python3 apps/scaling_study.py DECK --threads 1,2 --ranks 1,2 --weak --out output/scaling
"""
import argparse
import os
import subprocess
import sys
import tempfile

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "verification"))
import decks  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def grown_along_x(deck, factor):
    """The deck with its grid and every Rectangle body stretched `factor` times along x (weak
    scaling: the same cells and particles per cell, factor times as many of them)."""
    grid = deck["impm"]["Grid"]
    ov = {"Grid/Cells X": int(grid["Cells X"]) * factor}
    x0 = float(grid.get("Origin X", 0.0))
    stretch = lambda x: x0 + (float(x) - x0) * factor  # noqa: E731
    if "Body" in deck["impm"]:
        for key in ("X Min", "X Max"):
            if key in deck["impm"]["Body"]:
                ov[f"Body/{key}"] = stretch(deck["impm"]["Body"][key])
    for name, body in deck["impm"].get("Bodies", {}).items():
        if body.get("Shape", "Rectangle") != "Rectangle":
            raise SystemExit(f"--weak stretches Rectangle bodies only; 'Bodies/{name}' is not one")
        for key in ("X Min", "X Max"):
            if key in body:
                ov[f"Bodies/{name}/{key}"] = stretch(body[key])
    return decks.apply(deck, ov)


def run(impm, deck, ranks, threads, workdir, tag):
    out = os.path.join(workdir, tag)
    deck = decks.apply(deck, {"Problem/Output Directory": out, "Output/Plot": False, "Output/Progress": False,
                              "Output/VTK Interval": 0})
    path = os.path.join(workdir, tag + ".yaml")
    with open(path, "w") as f:
        f.write(decks.dump(deck))
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false")
    cmd = [impm, path]
    if ranks > 1:
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-np", str(ranks),
               "-x", "OMP_NUM_THREADS", "-x", "OMP_PROC_BIND"] + cmd
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        raise SystemExit(f"{tag}: impm exited {r.returncode}:\n{r.stderr[-2000:]}")
    with open(os.path.join(out, "summary.yaml")) as f:
        s = yaml.safe_load(f)["summary"]
    decomposition = s.get("Decomposition", {})
    return {"ranks": ranks, "threads": threads, "particles": int(s["Particles"]), "steps": int(s["Steps"]),
            "wall": float(s["Wall Time"]), "rate": float(s["Particle Steps Per Second"]),
            "bytes_per_particle": float(s["Peak Resident Bytes Total"]) / max(1, int(s["Particles"])),
            "rank_grid": str(decomposition.get("Rank Grid", "1 x 1")),
            "imbalance": float(decomposition.get("Load Imbalance Max", 1.0))}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("deck")
    ap.add_argument("--impm", default=os.path.join(REPO, "build", "apps", "impm"))
    ap.add_argument("--threads", default="1,2", help="OpenMP thread counts (comma separated)")
    ap.add_argument("--ranks", default="1,2", help="MPI rank counts (comma separated)")
    ap.add_argument("--steps", type=int, default=0, help="number of steps (default: the deck's)")
    ap.add_argument("--weak", action="store_true", help="weak scaling (grow the problem with the workers)")
    ap.add_argument("--repeat", type=int, default=3, help="runs per configuration; the fastest counts")
    ap.add_argument("--out", default="output/scaling")
    ap.add_argument("--max-workers", type=int, default=os.cpu_count(),
                    help="skip configurations with more ranks x threads than this (default: the cores); "
                         "oversubscribed, Kokkos' spinning threads measure contention, not scaling")
    args = ap.parse_args()

    base = decks.load(args.deck)
    if args.steps:
        base = decks.apply(base, {"Integrator/Number of Steps": args.steps})
    configs = [(int(r), int(t)) for r in args.ranks.split(",") for t in args.threads.split(",")]
    skipped = [c for c in configs if c[0] * c[1] > args.max_workers]
    configs = [c for c in configs if c[0] * c[1] <= args.max_workers]
    for r, t in skipped:
        print(f"skipped ranks {r} x threads {t}: more workers than --max-workers = {args.max_workers}")
    os.makedirs(args.out, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for ranks, threads in configs:
            workers = ranks * threads
            deck = grown_along_x(base, workers) if args.weak else base
            best = None
            for k in range(args.repeat):
                r = run(args.impm, deck, ranks, threads, work, f"r{ranks}_t{threads}_{k}")
                if best is None or r["wall"] < best["wall"]:
                    best = r
            rows.append(best)
            print(f"ranks {ranks} x threads {threads}: {best['particles']} particles, {best['rate'] / 1e6:.2f} M "
                  f"particle-steps/s, {1e3 * best['wall'] / best['steps']:.3f} ms/step", flush=True)

    first = rows[0]
    first_workers = first["ranks"] * first["threads"]
    kind = "weak" if args.weak else "strong"
    lines = [f"# {kind.capitalize()} scaling of `{os.path.relpath(args.deck, REPO)}`", "",
             f"`{' '.join(sys.argv)}`; fastest of {args.repeat} runs per configuration. Efficiency against the first "
             f"row: strong = speed-up / (workers ratio), weak = rate per worker ratio. Memory: the ranks' peak resident "
             f"sets summed, over the particles (with each process's Kokkos/Trilinos/MPI baseline of 50-60 MB, "
             f"so it falls as the problem grows).", "",
             "| ranks (grid) | threads | particles | M particle-steps/s | ms per step | speed-up | efficiency | bytes/particle "
             "| imbalance |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        workers = r["ranks"] * r["threads"]
        speedup = r["rate"] / first["rate"]
        eff = speedup / (workers / first_workers)
        lines.append(f"| {r['ranks']} ({r['rank_grid']}) | {r['threads']} | {r['particles']} | {r['rate'] / 1e6:.2f} | "
                     f"{1e3 * r['wall'] / r['steps']:.3f} | {speedup:.2f} | {eff:.2f} | {r['bytes_per_particle']:.0f} | "
                     f"{r['imbalance']:.2f} |")
    table = os.path.join(args.out, f"{kind}_scaling.md")
    with open(table, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines[4:]))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    labels = [f"{r['ranks']}x{r['threads']}" for r in rows]
    a1.bar(labels, [r["rate"] / 1e6 for r in rows])
    a1.set_xlabel("ranks x threads")
    a1.set_ylabel("M particle-steps / s")
    a1.set_title(f"{kind} scaling: throughput")
    a2.plot(labels, [r["rate"] / first["rate"] / (r["ranks"] * r["threads"] / first_workers) for r in rows], "o-")
    a2.axhline(1.0, color="gray", lw=0.8)
    a2.set_ylim(0, 1.2)
    a2.set_xlabel("ranks x threads")
    a2.set_ylabel("parallel efficiency")
    a2.set_title(os.path.basename(args.deck))
    fig.tight_layout()
    png = os.path.join(args.out, f"{kind}_scaling.png")
    fig.savefig(png, dpi=100)
    print(f"\nwrote {table} and {png}")


if __name__ == "__main__":
    main()
