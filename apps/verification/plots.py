"""Figures of the verification report (PNG, matplotlib without a display)."""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from cases import METHODS, MONITOR_LABELS, MONITORS  # noqa: E402

COLORS = {"explicit MPM": "tab:blue", "explicit GIMP": "tab:cyan", "implicit MPM": "tab:red",
          "implicit GIMP": "tab:orange", "FE Q4": "tab:green", "FE Q9": "tab:purple",
          "implicit MPM, consistent mass": "tab:brown"}
UNITS = {"ux_L": "m", "ux_half": "m", "sxx_half": "Pa", "w_mid": "m"}


def _save(fig, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _reference_run(runs):
    for m in ("implicit MPM", "explicit MPM") + tuple(METHODS):
        r = runs.get(m)
        if r is not None and r.ok:
            return r
    return None


def problem_overview(problem, plane, runs, modulus_text, path):
    """All methods of one problem and plane condition on one figure, one panel per monitor."""
    monitors = MONITORS[problem]
    fig, axes = plt.subplots(len(monitors), 1, figsize=(9, 2.8 * len(monitors) + 0.6), squeeze=False)
    ref = _reference_run(runs)
    for ax, mon in zip(axes[:, 0], monitors):
        for m in METHODS:
            r = runs.get(m)
            if r is None or not r.ok:
                continue
            ax.plot(r.history["time"], r.history[mon], color=COLORS[m], lw=1.0, label=m)
        if ref is not None:
            ax.plot(ref.history["time"], ref.history[mon + "_exact"], "k--", lw=1.2, label=f"exact ({modulus_text})")
        ax.set_ylabel(f"{MONITOR_LABELS[mon]} ({UNITS[mon]})")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("t (s)")
    axes[0, 0].legend(fontsize=7, ncol=4, loc="best")
    fig.suptitle(f"{'Problem 1 (bar)' if problem == 'bar' else 'Problem 2 (beam)'}, {plane.lower()}: all methods")
    fig.tight_layout()
    _save(fig, path)


def problem_per_method(problem, plane, runs, path):
    """One panel per method and monitor: computed against its own exact column."""
    monitors = MONITORS[problem]
    methods = [m for m in METHODS if m in runs]
    ncol = len(monitors) if len(monitors) > 1 else 2
    nrow = len(methods) if len(monitors) > 1 else math.ceil(len(methods) / 2)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 2.2 * nrow + 0.6), squeeze=False)
    for i, m in enumerate(methods):
        r = runs[m]
        for j, mon in enumerate(monitors):
            ax = axes[i, j] if len(monitors) > 1 else axes[i // 2, i % 2]
            if r.ok:
                ax.plot(r.history["time"], r.history[mon], color=COLORS[m], lw=1.0, label="computed")
                ax.plot(r.history["time"], r.history[mon + "_exact"], "k--", lw=0.9, label="exact")
            else:
                ax.text(0.5, 0.5, "run failed", ha="center", va="center", transform=ax.transAxes)
            ax.set_title(f"{m}: {MONITOR_LABELS[mon]}", fontsize=8)
            ax.tick_params(labelsize=7)
            ax.grid(alpha=0.3)
    if len(monitors) == 1 and len(methods) % 2:
        axes[-1, -1].axis("off")
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(f"{'Problem 1 (bar)' if problem == 'bar' else 'Problem 2 (beam)'}, {plane.lower()}: each method "
                 f"against the exact solution", fontsize=10)
    fig.tight_layout()
    _save(fig, path)


def refinement(study, table, path):
    """Relative L2 error against the refinement factor (log-log), one line per method and monitor."""
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for m, per_mon in table.items():
        for mon, errs in per_mon.items():
            f = np.array(study.factors, dtype=float)
            e = np.array(errs, dtype=float)
            ok = np.isfinite(e) & (e > 0)
            if ok.sum() < 1:
                continue
            ax.loglog(f[ok], e[ok], marker="o", color=COLORS.get(m, "k"), lw=1,
                      ls="-" if mon in ("ux_L", "w_mid") else (":" if mon == "ux_half" else "--"),
                      label=f"{m} {MONITOR_LABELS[mon]}")
    f = np.array(study.factors, dtype=float)
    ax.set_xlabel("grid refinement factor" if study.kind == "grid" else "dt divided by")
    ax.set_ylabel("relative L2 error against exact")
    ax.set_xticks(f)
    ax.set_xticklabels([str(int(v)) for v in f])
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=6, ncol=2)
    ax.set_title(f"{study.key}: {study.problem}, {study.plane.lower()}, t <= {study.t_end:g} s", fontsize=9)
    fig.tight_layout()
    _save(fig, path)


def self_convergence(study, diffs, path, reference=None):
    """Differences between successive halvings of dt, with the Newmark modal series for reference."""
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for (label, ref), ls in zip((reference or {}).items(), ("--", ":")):
        if isinstance(ref, str):
            continue
        ax.loglog(np.array(study.factors[1:], dtype=float), ref[0], color="k", ls=ls, marker="x", lw=1, label=label)
    for m, per_mon in diffs.items():
        for mon, d in per_mon.items():
            d = np.array(d, dtype=float)
            x = np.array(study.factors[1:], dtype=float)
            ok = np.isfinite(d) & (d > 0)
            if ok.sum() < 1:
                continue
            ax.loglog(x[ok], d[ok], marker="o", color=COLORS.get(m, "k"), lw=1, label=f"{m} {MONITOR_LABELS[mon]}")
    x = np.array(study.factors[1:], dtype=float)
    first = [v[0] for per in diffs.values() for v in per.values() if len(v) and np.isfinite(v[0])]
    if first:
        ax.loglog(x, max(first) * 2 * (x[0] / x) ** 2, color="gray", lw=1, label="slope 2")
    ax.set_xticks(x)
    ax.set_xticklabels([str(int(v)) for v in x])
    ax.minorticks_off()
    ax.set_xlabel("finer run of the pair: dt divided by")
    ax.set_ylabel("||w(dt) - w(dt/2)|| / ||w(dt/2)||")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=6)
    ax.set_title(f"{study.key}: self-convergence in dt", fontsize=9)
    fig.tight_layout()
    _save(fig, path)


def budget(method, b, labels, path):
    """The chain of computations of Problem 2's budget, w(x0, t), and the total error."""
    fig, axes = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    styles = ["k--", "k-", "tab:gray", "tab:brown", "tab:purple", "tab:pink", "tab:red"]
    for (name, v), st in zip(b["values"].items(), styles):
        kw = {"color": st} if not st.startswith("k") else {"color": "k", "ls": st[1:]}
        axes[0].plot(b["times"], v, lw=1, label=labels.get(name, name), **kw)
    axes[0].set_ylabel("w(L/2, t) (m)")
    axes[0].legend(fontsize=7, ncol=2, loc="upper left", framealpha=0.8)
    axes[0].grid(alpha=0.3)
    for r in b["rows"]:
        axes[1].plot(b["times"], r["d"], lw=1, label=r["effect"])
    axes[1].plot(b["times"], b["e_total"], "k-", lw=1.5, label="total: M - EB(E)")
    axes[1].set_ylabel("difference (m)")
    axes[1].set_xlabel("t (s)")
    axes[1].legend(fontsize=7, ncol=2)
    axes[1].grid(alpha=0.3)
    fig.suptitle(f"Problem 2 budget, {method}: each link of the chain", fontsize=10)
    fig.tight_layout()
    _save(fig, path)
