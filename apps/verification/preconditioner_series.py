#!/usr/bin/python3
"""Preconditioners under grid refinement: the seed beam (Problem 2, implicit MPM, JFNK) at
40 x 4, 80 x 8, 160 x 16 and 320 x 32 cells (4 x 4 particles per cell) with each preconditioner.

Starts from apps/beam_implicit_mpm_plane_strain.yaml (Jacobian-Free Newton-Krylov, linear tolerance
1e-8, preconditioner refreshed every 10 steps) and changes only the grid and the preconditioner:

  MUELU    smoothed-aggregation AMG (impm's defaults, the rigid-body modes as near-null space)
  MUELU2   the same on 2 ranks (uncoupled aggregation within each rank, SCHWARZ coarse solve)
  SCHWARZ  Ifpack2 additive Schwarz, overlap 1, Amesos2 (KLU2) subdomain solve; on one rank that is
           the exact LU of P, so it runs on --schwarz-ranks ranks (default 2)
  RILUK    Ifpack2 ILU(k), the deck's level of fill 4
  AMESOS2  sparse LU of P (the reference: exact P^-1)

Reads Newton iterations per step, GMRES iterations per Newton iteration and wall time per step from
each run's summary.yaml, w(L/2) at the last step from history.csv, and writes a markdown table and
a PNG (iterations and time per step against the number of unknowns) into --out.
Iterations are deterministic; times are what this machine gave (label them when it is shared).

  /usr/bin/python3 apps/verification/preconditioner_series.py --steps 20
  /usr/bin/python3 apps/verification/preconditioner_series.py --sizes 40,80 --preconditioners MUELU,AMESOS2
  /usr/bin/python3 apps/verification/preconditioner_series.py --sizes 160 --preconditioners MUELU \\
      --intervals 1,5,20 --steps 40        # the lag: Preconditioner Refresh Interval
"""
import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import decks  # noqa: E402
import runner  # noqa: E402

REPO = os.path.dirname(os.path.dirname(HERE))
BASE = os.path.join(REPO, "apps", "beam_implicit_mpm_plane_strain.yaml")

PRECONDITIONERS = {
    "MUELU": {"Implicit Solver/Preconditioner": "MUELU", "Implicit Solver/Ifpack2": decks.DELETE},
    "MUELU2": {"Implicit Solver/Preconditioner": "MUELU", "Implicit Solver/Ifpack2": decks.DELETE},
    "SCHWARZ": {"Implicit Solver/Preconditioner": "SCHWARZ",
                "Implicit Solver/Ifpack2": {"schwarz: overlap level": 1, "subdomain solver name": "AMESOS2"}},
    "RILUK": {},
    "AMESOS2": {"Implicit Solver/Preconditioner": "AMESOS2", "Implicit Solver/Ifpack2": decks.DELETE},
}


def beam_deck(base, nx, steps, precond, interval, out):
    """The beam on nx x nx/10 cells (the body fills the grid: 10 m x 0.5 m)."""
    ny = nx // 10
    ov = {"Grid/Cells X": nx, "Grid/Cells Y": ny, "Grid/Cell Size X": 10.0 / nx, "Grid/Cell Size Y": 0.5 / ny,
          "Integrator/Number of Steps": steps, "Problem/Output Directory": out, "Output/Plot": False,
          "Output/VTK Interval": 0, "Output/Progress": False}
    if interval:
        ov["Integrator/Implicit/Preconditioner Refresh Interval"] = interval
    ov.update(PRECONDITIONERS[precond])
    return decks.apply(base, ov)


def unknowns(nx):
    """Free dofs: every node of the (nx + 1) x (ny + 1) grid carries mass; the supports fix 3."""
    return 2 * (nx + 1) * (nx // 10 + 1) - 3


def run_one(impm, deck, ranks, workdir, tag):
    out = decks.get(deck, "Problem/Output Directory")
    path = os.path.join(workdir, tag + ".yaml")
    with open(path, "w") as f:
        f.write(decks.dump(deck))
    env = dict(os.environ)
    env.setdefault("OMP_NUM_THREADS", "1")
    env.setdefault("OMP_PROC_BIND", "false")
    env.setdefault("OMP_WAIT_POLICY", "passive")
    cmd = [impm, path]
    if ranks > 1:
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-np", str(ranks),
               "-x", "OMP_NUM_THREADS", "-x", "OMP_PROC_BIND", "-x", "OMP_WAIT_POLICY"] + cmd
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        return {"error": f"exit {r.returncode}: {(r.stderr or r.stdout).strip().splitlines()[-1:]}"}
    s = runner.read_summary(os.path.join(out, "summary.yaml"))
    h = runner.read_history(os.path.join(out, "history.csv"))
    solver = s.get("Solver", {})
    return {"newton": float(solver["Newton Iterations Mean"]),
            "gmres": float(solver["Krylov Iterations Per Newton Mean"]),
            "gmres_max": int(solver["Krylov Iterations Per Newton Max"]),
            "ms_per_step": 1e3 * float(s["Wall Time"]) / int(s["Steps"]),
            # The Newton solves alone (P's assembly, the preconditioner set-up, GMRES): what the
            # preconditioner changes, without the particle work and the run's set-up.
            "solve_ms_per_step": 1e3 * float(solver.get("Seconds Newton Solve", "nan")) / int(s["Steps"]),
            "w_mid": float(h["w_mid"][-1]) if "w_mid" in h else float("nan")}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--impm", default=os.path.join(REPO, "build", "apps", "impm"))
    ap.add_argument("--sizes", default="40,80,160,320", help="cells along the span (depth: a tenth)")
    ap.add_argument("--preconditioners", default="MUELU,SCHWARZ,RILUK,AMESOS2")
    ap.add_argument("--steps", type=int, default=20, help="time steps per run (the deck has 1000)")
    ap.add_argument("--intervals", default="", help="Preconditioner Refresh Interval values (default: the deck's 10)")
    ap.add_argument("--schwarz-ranks", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(REPO, "output", "preconditioner_series"))
    args = ap.parse_args()

    base = decks.load(BASE)
    sizes = [int(n) for n in args.sizes.split(",")]
    precs = args.preconditioners.split(",")
    intervals = [int(i) for i in args.intervals.split(",")] if args.intervals else [0]
    os.makedirs(os.path.join(args.out, "runs"), exist_ok=True)
    rows = []
    for nx in sizes:
        for p in precs:
            for interval in intervals:
                tag = f"{p.lower()}_{nx}x{nx // 10}" + (f"_every{interval}" if interval else "")
                ranks = args.schwarz_ranks if p == "SCHWARZ" else 2 if p == "MUELU2" else 1
                deck = beam_deck(base, nx, args.steps, p, interval, os.path.join(args.out, "runs", tag))
                r = run_one(args.impm, deck, ranks, args.out, tag)
                r.update(nx=nx, ny=nx // 10, precond=p, ranks=ranks, unknowns=unknowns(nx),
                         interval=interval or decks.get(base, "Integrator/Implicit/Preconditioner Refresh Interval", 1))
                rows.append(r)
                if "error" in r:
                    print(f"{tag}: FAILED {r['error']}", flush=True)
                else:
                    print(f"{tag}: {r['newton']:.2f} Newton/step, {r['gmres']:.2f} GMRES/Newton (max {r['gmres_max']}), "
                          f"{r['ms_per_step']:.0f} ms/step ({r['solve_ms_per_step']:.0f} in Newton), w(L/2) = {r['w_mid']:.6e}", flush=True)

    ref = {(r["nx"], r["interval"]): r["w_mid"] for r in rows if r["precond"] == "AMESOS2" and "error" not in r}
    threads = os.environ.get("OMP_NUM_THREADS", "1")
    lines = [f"# Preconditioners under refinement: the seed beam, JFNK, {args.steps} steps", "",
             f"`{' '.join(sys.argv)}`; {threads} OpenMP thread(s) per rank. Iterations are deterministic; "
             "ms per step is wall time on this machine (a loaded, shared machine unless stated). "
             "dw: |w(L/2) - w_AMESOS2(L/2)| / |w_AMESOS2(L/2)| at the last step.", "",
             "| cells | unknowns | preconditioner | ranks | refresh interval | Newton / step | GMRES / Newton (max) "
             "| ms / step | Newton solve ms / step | dw vs AMESOS2 |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        head = f"| {r['nx']} x {r['ny']} | {r['unknowns']} | {r['precond']} | {r['ranks']} | {r['interval']} |"
        if "error" in r:
            lines.append(head + f" failed: {r['error']} | | | | |")
            continue
        w0 = ref.get((r["nx"], r["interval"]))
        dw = f"{abs(r['w_mid'] - w0) / abs(w0):.1e}" if w0 else "-"
        lines.append(head + f" {r['newton']:.2f} | {r['gmres']:.2f} ({r['gmres_max']}) | {r['ms_per_step']:.0f} | {r['solve_ms_per_step']:.0f} | {dw} |")
    table = os.path.join(args.out, "preconditioner_series.md")
    with open(table, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines[4:]))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
    for p in precs:
        for interval in sorted({r["interval"] for r in rows}):
            pts = [r for r in rows if r["precond"] == p and r["interval"] == interval and "error" not in r]
            if not pts:
                continue
            label = p + (f" (refresh {interval})" if len(intervals) > 1 else "")
            a1.plot([r["unknowns"] for r in pts], [r["gmres"] for r in pts], "o-", label=label)
            a2.plot([r["unknowns"] for r in pts], [r["solve_ms_per_step"] for r in pts], "o-", label=label)
    n = [unknowns(nx) for nx in sizes]
    if len(n) > 1 and rows and "error" not in rows[0]:
        import math
        t0 = min(r["solve_ms_per_step"] for r in rows if r["nx"] == sizes[0] and "error" not in r)
        a2.plot(n, [t0 * k * math.log(k) / (n[0] * math.log(n[0])) for k in n], "k--", lw=0.8, label="~ N log N")
    a1.axhline(10, color="gray", lw=0.8)
    for a in (a1, a2):
        a.set_xscale("log")
        a.set_xlabel("unknowns")
        a.legend(fontsize=8)
    a1.set_ylabel("GMRES iterations per Newton iteration")
    a2.set_yscale("log")
    a2.set_ylabel("Newton solve time per step [ms]")
    a1.set_title("beam, JFNK: Krylov iterations")
    a2.set_title("time per step")
    fig.tight_layout()
    png = os.path.join(args.out, "preconditioner_series.png")
    fig.savefig(png, dpi=100)
    print(f"\nwrote {table} and {png}")


if __name__ == "__main__":
    main()
