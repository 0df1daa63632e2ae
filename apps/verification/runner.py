"""Runs impm and impm_beam_exact, one process at a time, and loads what they write.

A run lives in <root>/runs/<case>/ (history.csv, summary.yaml, impm.log, deck.sha256); its deck
is <root>/decks/<case>.yaml. A run is reused when its summary.yaml exists and the deck's hash
matches deck.sha256 (so a rerun of the report is cheap); --force reruns everything.
"""
import csv
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field

import numpy as np
import yaml

import decks


@dataclass
class Run:
    case: object
    directory: str
    ok: bool
    message: str = ""
    summary: dict = field(default_factory=dict)
    history: dict = field(default_factory=dict)  # column name -> numpy array
    reused: bool = False
    wall: float = 0.0  # s, impm's own Wall Time (0 if it failed)
    provenance: str = ""  # source commit and impm build time when the run was made (run.info)

    def monitor_position(self, monitor):
        """Reference (x, y) of the monitored particle: summary.yaml's Monitors/<name>, else the lattice."""
        m = (self.summary.get("Monitors") or {}).get(monitor)
        if m and "X" in m:
            return float(m["X"]), float(m["Y"])
        return decks.monitor_position(self.case.deck, monitor)


def read_history(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r]
    names = [c.strip() for c in rows[0]]
    data = np.array([[float(c) for c in r] for r in rows[1:]], dtype=float).reshape(-1, len(names))
    return {n: data[:, i] for i, n in enumerate(names)}


def read_summary(path):
    with open(path) as f:
        return (yaml.safe_load(f) or {}).get("summary", {})


class Runner:
    def __init__(self, repo, build_dir, root, force=False, threads=None, out=sys.stdout):
        self.repo = repo
        self.build_dir = build_dir
        self.root = root
        self.force = force
        self.out = out
        self.env = dict(os.environ)
        self.env.setdefault("OMP_NUM_THREADS", str(threads or 2))
        self.env.setdefault("OMP_PROC_BIND", "false")
        self.runs = {}
        self.seconds_run = 0.0  # wall time of the impm processes started by this invocation

    def binary(self, name):
        return os.path.join(self.build_dir, "apps", name)

    def help_text(self):
        try:
            return subprocess.run([self.binary("impm"), "--help"], capture_output=True, text=True,
                                  env=self.env, timeout=60).stdout
        except OSError:
            return ""

    def provenance(self):
        """'commit abc1234[+changes], impm built YYYY-mm-dd HH:MM' of the binary about to run."""
        def git(*a):
            try:
                return subprocess.run(["git", "-C", self.repo, *a], capture_output=True, text=True).stdout.strip()
            except OSError:
                return ""
        commit = git("rev-parse", "--short", "HEAD") or "unknown"
        # (The report's own pages under doc/ do not count: a rerun rewrites them.)
        dirty = "+changes" if git("status", "--porcelain", "--untracked-files=no", "--", ".", ":!doc") else ""
        built = time.strftime("%Y-%m-%d %H:%M", time.gmtime(os.path.getmtime(self.binary("impm"))))
        return f"commit {commit}{dirty}, impm built {built} UTC"

    def log(self, text):
        print(text, file=self.out, flush=True)

    def run(self, case, index=None, total=None):
        """Run a case (or reuse its earlier run); never two impm processes at once."""
        if case.name in self.runs:
            return self.runs[case.name]
        deck_dir = os.path.join(self.root, "decks")
        run_dir = os.path.join(self.root, "runs", case.name)
        os.makedirs(deck_dir, exist_ok=True)
        deck_path = os.path.join(deck_dir, case.name + ".yaml")
        text = decks.dump(case.deck)
        digest = decks.text_hash(text)
        with open(deck_path, "w") as f:
            f.write(text)
        stamp = os.path.join(run_dir, "deck.sha256")
        summary_path = os.path.join(run_dir, "summary.yaml")
        prefix = f"[{index}/{total}] " if index else ""
        reused = False
        if (not self.force and os.path.exists(summary_path) and os.path.exists(stamp)
                and open(stamp).read().strip() == digest):
            reused = True
            ok, message = True, ""
        else:
            if os.path.isdir(run_dir):
                shutil.rmtree(run_dir)
            os.makedirs(run_dir)
            self.log(f"{prefix}{case.name}: running {case.steps} steps ...")
            t0 = time.monotonic()
            with open(os.path.join(run_dir, "impm.log"), "w") as logf:
                p = subprocess.run([self.binary("impm"), deck_path, "--output", run_dir], stdout=logf,
                                   stderr=subprocess.PIPE, text=True, env=self.env)
                logf.write(p.stderr)
            elapsed = time.monotonic() - t0
            self.seconds_run += elapsed
            ok = p.returncode == 0 and os.path.exists(summary_path)
            lines = [l for l in p.stderr.splitlines() if l.strip()]
            message = "" if ok else (lines[-1] if lines else f"exit status {p.returncode}")
            if ok:
                with open(stamp, "w") as f:
                    f.write(digest + "\n")
                with open(os.path.join(run_dir, "run.info"), "w") as f:
                    f.write(self.provenance() + "\n")
        run = Run(case=case, directory=run_dir, ok=ok, message=message, reused=reused)
        info = os.path.join(run_dir, "run.info")
        if os.path.exists(info):
            run.provenance = open(info).read().strip()
        if ok:
            run.summary = read_summary(summary_path)
            run.history = read_history(os.path.join(run_dir, "history.csv"))
            run.wall = float(run.summary.get("Wall Time", 0.0))
            status = run.summary.get("Status", "completed")
            if status != "completed":
                run.ok, run.message = False, f"Status: {status}"
        tag = "reused" if reused else f"{run.wall:.1f} s"
        self.log(f"{prefix}{case.name}: {'ok' if run.ok else 'FAILED: ' + run.message} ({tag})"
                 if (not reused or not run.ok) else f"{prefix}{case.name}: reused")
        self.runs[case.name] = run
        return run

    def beam_exact(self, deck_path, x):
        """impm_beam_exact DECK --x X: (columns, first-mode frequencies {column: rad/s}) or raises."""
        p = subprocess.run([self.binary("impm_beam_exact"), deck_path, "--x", repr(float(x))],
                           capture_output=True, text=True, env=self.env)
        if p.returncode != 0:
            raise RuntimeError(f"impm_beam_exact failed: {p.stderr.strip() or p.returncode}")
        lines = p.stdout.splitlines()
        comments = [l for l in lines if l.startswith("#")]
        body = [l for l in lines if l and not l.startswith("#")]
        names = body[0].split(",")
        data = np.array([[float(c) for c in l.split(",")] for l in body[1:]])
        cols = {n: data[:, i] for i, n in enumerate(names)}
        # "# omega_1 (rad/s): eb_E 72.1, eb_Eprime 75.6, timo_Eprime 75.3, newmark (2/dt)atan(omega dt/2)
        #  of eb_Eprime 75.6, of timo_Eprime 75.3; timo_E 71.8; plane strain, x = 5, ..."
        num = r"(-?[0-9][0-9.]*(?:[eE][-+]?[0-9]+)?)"
        patterns = {"eb_E": r"\beb_E\s+", "eb_Eprime": r"[:,]\s*eb_Eprime\s+", "timo_Eprime": r"[:,]\s*timo_Eprime\s+",
                    "eb_Eprime_newmark": r"of eb_Eprime\s+", "timo_Eprime_newmark": r"of timo_Eprime\s+",
                    "timo_E": r"\btimo_E\s+"}
        freqs = {}
        for c in comments:
            if "omega_1" not in c:
                continue
            for key, pat in patterns.items():
                m = re.search(pat + num, c)
                if m:
                    freqs[key] = float(m.group(1))
        return cols, freqs, comments
