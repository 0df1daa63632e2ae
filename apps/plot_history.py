#!/usr/bin/python3
"""Plot an impm run's monitored history against the exact solution.

Usage: /usr/bin/python3 apps/plot_history.py OUTDIR [--title TITLE]

Reads OUTDIR/history.csv (header row; first column `time`; each monitored quantity `q` may be
followed by `q_exact`) and writes OUTDIR/plot.png: one subplot per quantity on a shared time
axis, computed solid and exact dashed, then one panel with the kinetic, strain and total energy,
one with the linear momentum when history.csv has them, and one per grid condition with its
reaction components (`<name>_reaction_<x|y|z>`). Exits non-zero with one message on stderr if the CSV is
missing or malformed.
"""
import argparse
import csv
import math
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")  # no display on the build/CI machines
import matplotlib.pyplot as plt  # noqa: E402


class HistoryError(Exception):
    pass


ENERGY = ("kinetic_energy", "strain_energy", "total_energy")
MOMENTUM = ("momentum_x", "momentum_y", "momentum_z")


def read_history(path):
    """Return (names, columns) where columns maps each header name to a list of floats."""
    try:
        with open(path, newline="") as f:
            reader = csv.reader(f)  # keep file line numbers for the error messages
            rows = [(reader.line_num, r) for r in reader if any(c.strip() for c in r)]
    except OSError as e:
        raise HistoryError(f"cannot read {path}: {e.strerror}")
    if not rows:
        raise HistoryError(f"{path} is empty")
    names = [c.strip() for c in rows[0][1]]
    if names[0] != "time":
        raise HistoryError(f"{path}: first column must be 'time', found '{names[0]}'")
    if len(names) < 2:
        raise HistoryError(f"{path}: no monitored quantity after 'time'")
    if len(set(names)) != len(names):
        raise HistoryError(f"{path}: duplicate column names in header")
    if len(rows) < 2:
        raise HistoryError(f"{path}: header but no data rows")
    columns = {n: [] for n in names}
    for lineno, row in rows[1:]:
        if len(row) != len(names):
            raise HistoryError(f"{path}: line {lineno} has {len(row)} fields, header has {len(names)}")
        for n, cell in zip(names, row):
            try:
                columns[n].append(float(cell))
            except ValueError:
                raise HistoryError(f"{path}: line {lineno}, column '{n}': not a number: '{cell}'")
    return names, columns


def plot(names, columns, title, out_png):
    # A quantity is every non-time column that is not itself someone's `_exact` partner; the
    # energy and momentum columns (Output/Energy And Momentum) share one panel each.
    groups = [g for g in (ENERGY, MOMENTUM) if all(c in columns for c in g)]
    # Each grid condition's reaction components share a panel.
    reactions = {}
    for n in names[1:]:
        head, sep, axis = n.rpartition("_reaction_")
        if sep and axis in ("x", "y", "z"):
            reactions.setdefault(head, []).append(n)
    groups += [tuple(cols) for cols in reactions.values()]
    grouped = {c for g in groups for c in g}
    quantities = [n for n in names[1:]
                  if not (n.endswith("_exact") and n[: -len("_exact")] in columns) and n not in grouped]
    t = columns["time"]
    panels = len(quantities) + len(groups)
    fig, axes = plt.subplots(panels, 1, sharex=True, squeeze=False, figsize=(8, 2.6 * panels + 0.8))
    for ax, g in zip(axes[len(quantities):, 0], groups):
        for c in g:
            ax.plot(t, columns[c], "-", label=c)
        ax.set_ylabel("energy" if g is ENERGY else "momentum" if g is MOMENTUM
                      else g[0].rpartition("_reaction_")[0] + " reaction (N)")
        ax.grid(True, alpha=0.3)
        ax.ticklabel_format(axis="both", style="sci", scilimits=(-3, 3))
        ax.legend(loc="best", fontsize="small")
    for ax, q in zip(axes[:, 0], quantities):
        ax.plot(t, columns[q], "-", label=f"{q} (computed)")
        exact = q + "_exact"
        if exact in columns:
            ax.plot(t, columns[exact], "--", label=f"{q} (exact)")
        ax.set_ylabel(q)
        ax.grid(True, alpha=0.3)
        ax.ticklabel_format(axis="both", style="sci", scilimits=(-3, 3))
        ax.legend(loc="best", fontsize="small")
    axes[-1, 0].set_xlabel("time")
    fig.suptitle(title)
    fig.tight_layout()
    # Write beside the target and rename: a reader never sees a half-written plot.png.
    fd, tmp = tempfile.mkstemp(prefix=".plot-", suffix=".png", dir=os.path.dirname(out_png) or ".")
    try:
        with os.fdopen(fd, "wb") as f:
            fig.savefig(f, format="png", dpi=120)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give plot.png ordinary permissions
        os.replace(tmp, out_png)
    except BaseException:
        os.unlink(tmp)
        raise
    finally:
        plt.close(fig)


def main(argv=None):
    p = argparse.ArgumentParser(description="Plot OUTDIR/history.csv to OUTDIR/plot.png.")
    p.add_argument("outdir")
    p.add_argument("--title", default=None, help="plot title (default: the directory name)")
    args = p.parse_args(argv)
    outdir = args.outdir
    title = args.title if args.title is not None else os.path.basename(os.path.normpath(os.path.abspath(outdir)))
    try:
        names, columns = read_history(os.path.join(outdir, "history.csv"))
        if any(not math.isfinite(v) for v in columns["time"]):
            raise HistoryError(f"{os.path.join(outdir, 'history.csv')}: non-finite time value")
        plot(names, columns, title, os.path.join(outdir, "plot.png"))
    except HistoryError as e:
        print(f"plot_history: error: {e}", file=sys.stderr)
        return 1
    except OSError as e:
        print(f"plot_history: error: cannot write plot in {outdir}: {e.strerror}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
