"""The tables of measured figures in docs/results.md (all but the claims table, which plots/claims.py
writes), generated from the committed results under results/reference/ by the declarations of
plots/results_tables.toml: one function per table, reusing the plot scripts' own functions. Each
table lies between <!-- table:NAME:begin --> and <!-- table:NAME:end -->, with a caption naming the
folder, GPU and commit it read and whether that commit is current (STALE where solver/ changed
after it: claims.py's history and freshness). A measurement whose results were never committed, or
whose folder is gone, is said so in its block instead of a table.

Usage: python3 plots/results_tables.py          print every block
       python3 plots/results_tables.py --write  put them into docs/results.md (make claims)
       python3 plots/results_tables.py --check  exit 1 when a block of docs/results.md differs (make test)
"""
import argparse
import json
import re
import sys
from pathlib import Path

import numpy as np

import claims
import sphplot
from claims import Missing, tomllib
from sphplot import pd

REPO = sphplot.REPO
SPEC = REPO / "plots" / "results_tables.toml"
REFERENCE = claims.REFERENCE
DOC = claims.DOC
MARK = re.compile(r"<!-- table:([A-Za-z0-9_-]+):begin -->\n(.*?)<!-- table:\1:end -->\n?", re.S)
FRESH = re.compile(r"(current\?: ).*$", re.M)


def begin(name):
    return f"<!-- table:{name}:begin -->"


def end(name):
    return f"<!-- table:{name}:end -->"


class Table:
    """What a table function returns: header, rows, the sources it read and notes under the table."""

    def __init__(self, header, rows, sources, notes=()):
        self.header, self.rows, self.sources, self.notes = header, rows, sources, list(notes)


class Source:
    """One folder or file read: its path under results/reference/, the GPU and the commit."""

    def __init__(self, path, gpu, commit, dirty=None):
        self.path, self.gpu, self.commit, self.dirty = path, gpu or "unknown", commit or "unknown", dirty


# --------------------------------------------------------------------------------------------
# Provenance


def rel(path):
    """The path under results/reference/ (or under the folder named `reference` that --reference gave)."""
    parts = Path(path).parts
    if "reference" in parts:
        i = len(parts) - 1 - parts[::-1].index("reference")
        return "/".join(parts[i + 1:]) or "."
    return str(path)


def machine_of(folder):
    """results/reference/<machine>: the folder that holds gpu.txt and reference-state.json."""
    folder = Path(folder)
    for d in [folder, *folder.parents]:
        if d.parent == REFERENCE or d.parent.name == "reference":
            return d
    return folder


def from_meta(folder, meta):
    return Source(rel(folder), claims.gpu_of(Path(folder), meta), meta.get("git_commit"), meta.get("git_dirty"))


def from_item(folder, item):
    """Provenance of a text result that `make reference` wrote: its item in reference-state.json."""
    machine = machine_of(folder)
    meta = claims.recorded(machine, item)
    if meta is None:
        raise Missing(f"{rel(machine)}/reference-state.json has no item {item}")
    return Source(rel(folder), claims.gpu_of(machine, None), meta["git_commit"], meta["git_dirty"])


def from_text(folder, path, gpu=None):
    """Provenance written in a text file's header ('commit 8f24845', 'build a76d41d')."""
    m = re.search(r"\b(?:commit|build) ([0-9a-f]{7,40})\b", Path(path).read_text())
    return Source(rel(folder), gpu or claims.gpu_of(Path(folder), None), m.group(1) if m else None)


def need(path):
    if not Path(path).exists():
        raise Missing(f"`results/reference/{rel(path)}` is not there")
    return Path(path)


# --------------------------------------------------------------------------------------------
# Parsers of the text that sphbench and the lease scripts print


def sphbench_summaries(text):
    """[{case, particles, median, q1, q3, mean, update, rebuilds, recorded, bytes}] per '== ' block of
    `sphbench simulate` output (benchmarks.txt, long.txt, overlap.txt)."""
    out, cur = [], None
    for line in text.splitlines():
        if line.startswith("== "):
            cur = {"case": line[3:].strip()}
            out.append(cur)
            continue
        if cur is None:
            continue
        m = re.match(r"scene \S+ on .*?: (\d+) particles", line)
        if m:
            cur["particles"] = int(m.group(1))
        m = re.match(r"(\d+) steps recorded after", line)
        if m:
            cur["recorded"] = int(m.group(1))
        m = re.match(r"time per step(?: in the window)?: median ([0-9.]+) ms \(quartiles ([0-9.]+) to ([0-9.]+)\)"
                     r"(?:, mean ([0-9.]+) ms)?; update \(forces \+ integration\) ([0-9.]+) ms", line)
        if m:
            cur.update(median=float(m.group(1)), q1=float(m.group(2)), q3=float(m.group(3)),
                       mean=float(m.group(4)) if m.group(4) else np.nan, update=float(m.group(5)))
        m = re.match(r"Verlet lists: rebuilt in (\d+) of the (\d+) recorded steps", line)
        if m:
            cur["rebuilds"] = int(m.group(1))
        m = re.match(r"memory: (\d+) bytes per particle", line)
        if m:
            cur["bytes"] = int(m.group(1))
    return out


def case_of(header):
    """'sphbench simulate dsph-dambreak --set dp=0.0028 --steps 300 ...' -> 'dsph-dambreak --set dp=0.0028'."""
    m = re.match(r"(?:rep \d+ )?(\S+) (?:simulate |\d+ steps )?(.*?)(?: --steps .*)?$", header)
    return m.group(2).strip() if m else header


def whole_run_line(text):
    """The lease's printed summary of a whole-run run (when its runs.csv did not come back)."""
    m = re.search(r"\] (\S+): (\d+) particles on .*?, (\d+) steps to t = ([0-9.]+) s .*?, ([0-9.]+) s, "
                  r"([0-9.]+) s per simulated second", text)
    v = re.search(r"Verlet lists: (\d+) rebuilds in (\d+) steps; rebuild step ([0-9.]+) ms, listed step ([0-9.]+) ms",
                  text)
    if not m:
        raise Missing("no run summary line")
    return {"run_id": m.group(1), "particles": int(m.group(2)), "steps": int(m.group(3)),
            "sim_time": float(m.group(4)), "wall_s": float(m.group(5)), "s_per_sim_s": float(m.group(6)),
            "list_rebuilds": int(v.group(1)) if v else np.nan, "rebuild_step_ms": float(v.group(3)) if v else np.nan,
            "listed_step_ms": float(v.group(4)) if v else np.nan, "list_bytes_per_particle": np.nan}


# --------------------------------------------------------------------------------------------
# Formatting


def f(v, spec=".3f", none="-"):
    try:
        v = float(v)
    except (TypeError, ValueError):
        return none
    return format(v, spec) if np.isfinite(v) else none


def thousands(v):
    return f(v, ",.0f")


def pct(v, spec="+.2f"):
    return f(100.0 * float(v), spec) + "%" if np.isfinite(float(v)) else "-"


# --------------------------------------------------------------------------------------------
# The tables: each takes the folders of its `results` and returns a Table (or raises Missing).


def whole_run(folder):
    folder = need(folder)
    rows, sources = [], {}
    seen = set()
    for p in sorted(folder.glob("*.runs.csv")):
        runs, meta = sphplot.read_csv_with_metadata(p)
        commit = str(meta.get("git_commit"))[:7]
        for r in runs.to_dict("records"):
            seen.add(r["run_id"])
            rows.append((r, p.name, commit))
        sources.setdefault(commit, from_meta(folder, meta))
    for p in sorted(folder.glob("*.txt")):
        if p.name.endswith(".runs.txt") or not re.match(r"(dambreak|armadillo|bunny)", p.name):
            continue
        try:
            r = whole_run_line(p.read_text())
        except Missing:
            continue
        if r["run_id"] not in seen:
            s = from_text(folder, p)
            rows.append((r, p.name + " (the printed summary: its runs.csv did not come back)", str(s.commit)[:7]))
            sources.setdefault(str(s.commit)[:7], s)
    if not rows:
        raise Missing(f"no run in `results/reference/{rel(folder)}`")
    theirs, dsph_source = whole_run_dualsphysics(folder)
    # A folder that `make reference` refilled in part holds runs of several builds: each row names its own.
    mixed = len(sources) > 1
    out = []
    for r, src, commit in rows:
        reb = r.get("list_rebuilds")
        every = r["steps"] / reb if reb and np.isfinite(reb) and reb > 0 else np.nan
        row = [r["run_id"], thousands(r["particles"]), f(r["sim_time"], ".3g") + " s", thousands(r["steps"]),
               thousands(reb) + (f" (every {every:.1f})" if np.isfinite(every) else ""),
               f(r.get("rebuild_step_ms")), f(r.get("listed_step_ms")), f(r["wall_s"], ".1f"),
               "**" + f(r["s_per_sim_s"], ".2f") + "**", f(r.get("list_bytes_per_particle"), ",.0f"),
               f(r.get("bytes_per_particle"), ",.0f"), f(pairs_per_s(r), ".1f")]
        if theirs:
            case = claims.WHOLE_RUN_DSPH_CASE.get(re.sub(r"-(lists|cells)$", "", r["run_id"]))
            t = theirs.get(case)
            row += [f"{t['runtime_per_phys_s']:.2f} ({case})" if t else "-",
                    f"{t['runtime_per_phys_s'] / r['s_per_sim_s']:.2f}x" if t else "-"]
        out.append(row + [f"`{src}`" + (f" at {commit}" if mixed else "")])
    header = ["run", "particles", "simulated", "steps", "list rebuilds (every n steps)", "rebuild step ms (mean)",
              "listed step ms (mean)", "wall s", "s per simulated second", "list bytes per particle",
              "all bytes per particle", "neighbour pairs a second (G)"]
    pairs_note = ("Neighbour pairs a second: the pairs inside the support at the run's last step (the work counters "
                  "count one step) times its steps, over its wall time.")
    if theirs:
        header += ["DualSPHysics s per simulated second (its case)", "DualSPHysics over ours"]
        notes = [f"DualSPHysics v5.4 from `results/reference/{dsph_source.path}` (its Run.out's \"Runtime per physical "
                 "second\", on the same GPU as ours: `make reference`'s items whole-run-dualsphysics-1.04M and -4.04M, "
                 "on the machine that ran ours, in the same lease); its settings are the case named (its defaults: cubic on "
                 "cells of the support; Wendland on half cells), beside both of our searches. Its GPU memory: "
                 + ", ".join(f"{c} {t['bytes_per_particle']:.0f} bytes a particle" for c, t in sorted(theirs.items()))
                 + " (the resume's \"GPU Memory\" over its particles)."]
        sources.setdefault("dsph", dsph_source)
    else:
        notes = ["DualSPHysics' seconds per simulated second on these events are no committed result "
                 f"(`results/reference/{rel(folder)}/README.md` quotes them from issue 25's measurement at 196b2a0, "
                 "whose Run.out files were not committed), so no ratio to DualSPHysics is generated here."]
    return Table(header + ["from"], out, list(sources.values()), notes + [pairs_note])


def pairs_per_s(r):
    """Neighbour pairs a second of wall time, in billions (the last step's pairs times the steps)."""
    try:
        return float(r["neighbours_per_step"]) * float(r["steps"]) / float(r["wall_s"]) / 1e9
    except (KeyError, TypeError, ValueError, ZeroDivisionError):
        return np.nan


def whole_run_dualsphysics(folder):
    """DualSPHysics' whole events beside a whole-run folder ({case: its summary row}, claims.py reads
    them), and their provenance: the item in reference-state.json that made them."""
    d = Path(folder).parent / "whole-run-dualsphysics"
    theirs = claims.dualsphysics_whole_runs(Path(folder).parent)
    if not theirs:
        return {}, None
    for item in ("whole-run-dualsphysics-1.04M", "whole-run-dualsphysics-4.04M"):
        try:
            return theirs, from_item(d, item)
        except Missing:
            continue
    return theirs, Source(rel(d), claims.gpu_of(machine_of(d), None), None)  # not made by make reference


def whole_run_windows(folder):
    path = need(Path(folder) / "windows.csv")
    w = pd.read_csv(path)
    csvs = sorted(Path(folder).glob("*.runs.csv"))
    if not csvs:
        raise Missing("no runs.csv beside windows.csv")
    _, meta = sphplot.read_csv_with_metadata(csvs[0])
    rows = [[r.run, r.window_s + " s", thousands(r.steps), thousands(r.rebuilds), f(r.steps_per_rebuild, ".1f"),
             f(r.rebuild_step_ms), f(r.list_phase_ms), f(r.listed_step_ms),
             f((r.rebuild_step_ms - r.listed_step_ms) / r.listed_step_ms, ".1f"), f(r.s_per_sim_s, ".2f")]
            for r in w.itertuples()]
    header = ["run", "simulated window", "steps", "rebuilds", "steps per rebuild", "rebuild step ms",
              "of it the list phase ms", "listed step ms", "a rebuild's extra cost, in listed steps",
              "s per simulated second"]
    src = from_meta(folder, meta)
    src.path = rel(path)
    return Table(header, rows, [src], ["The windows are cut from the runs' step files (not committed, 7 MB each) by "
                                       "`bench/lease/step_windows.py` in the same lease (the folder's README says which "
                                       "version and any relabelling)."])


DSPH_CASES = {"dp0045_cubic": ("dam break 1.04M, cubic, cells of the support", "dsph-dambreak"),
              "dp0045_wendland_half": ("dam break 1.04M, Wendland, half cells",
                                       "dsph-dambreak --set kernel=wendland --cells-per-support 2"),
              "dp0028_cubic": ("dam break 4.04M, cubic, cells of the support", "dsph-dambreak --set dp=0.0028"),
              "dp0028_wendland_half": ("dam break 4.04M, Wendland, half cells",
                                       "dsph-dambreak --set dp=0.0028 --set kernel=wendland --cells-per-support 2"),
              None: ("armadillo 2,980K", "armadillo --set particles=2980000")}


def _lists(case):
    """Our Verlet-list case for a cell-search case (tools/reference.py's benchmark cases)."""
    base = case.replace(" --cells-per-support 2", "")
    return f"{base} {claims.VERLET}"


def _merged(case):
    if "armadillo" in case:
        return f"{case} --merge --cells-per-support 2"
    return f"{case} --merge"


def dualsphysics(machine):
    machine = Path(machine)
    bench = claims._first_file(machine, ["benchmarks/benchmarks.txt", "benchmarks.txt"])
    ours = {case_of(s["case"]): s for s in sphbench_summaries(bench.read_text()) if "median" in s}
    summary = claims._first_file(machine, ["dualsphysics/summary.txt", "dualsphysics-summary.txt"]).read_text()
    lines = summary.splitlines()
    cols = lines[0].split()
    theirs = {}
    for line in lines[1:]:
        c = line.split()
        if len(c) == len(cols) and c[cols.index("rc")] == "0":
            theirs[c[0]] = dict(zip(cols, c))
    rows = []
    for key, (label, case) in DSPH_CASES.items():
        cells, merged, lists = ours.get(case), ours.get(_merged(case)), ours.get(_lists(case))
        if cells is None and lists is None:
            continue
        d = theirs.get(key)
        ms = float(d["ms_per_step"]) if d else np.nan
        dsph_bytes = float(d["gpu_mem_mib"]) * 2 ** 20 / float(d["np"]) if d else np.nan

        def ratio(s, field="median"):
            return f(ms / s[field], ".2f") + "x" if s and np.isfinite(ms) and np.isfinite(s.get(field, np.nan)) else "-"

        rows.append([label, thousands((cells or lists).get("particles")),
                     f(cells and cells["median"]), f(merged and merged["median"]),
                     f(lists and lists["median"]) + (f" ({f(lists['mean'])})" if lists else ""),
                     f"{lists.get('rebuilds', 0)} of {lists.get('recorded', '?')}" if lists else "-",
                     f(ms, ".3f"), ratio(cells), ratio(lists), ratio(lists, "mean"),
                     f"{f(cells and cells.get('bytes'), '.0f')} / {f(merged and merged.get('bytes'), '.0f')} / "
                     f"{f(lists and lists.get('bytes'), ',.0f')} / {f(dsph_bytes, '.0f')}"])
    if not rows:
        raise Missing(f"no case in {rel(bench)}")
    header = ["case", "particles", "ours, cells: median ms a step", "cells, merged (n = 2 on the armadillo)",
              f"lists (`{claims.VERLET}`): median (mean) ms", "steps with a list rebuild",
              "DualSPHysics ms a step", "DualSPHysics / ours, cells", "DualSPHysics / ours, lists (median)",
              "lists by the mean", "bytes a particle: cells / merged / lists / DualSPHysics"]
    sources = [from_item(bench.parent, "benchmarks"), from_item(machine / "dualsphysics", "dualsphysics")]
    return Table(header, rows, sources, [
        "Ours: `sphbench simulate`, 300 recorded steps after 20 of warm-up, median (and mean) time per step, all "
        "phases. DualSPHysics: its simulation runtime over its steps (`ms_per_step` of its summary), and its "
        "reported GPU memory (`gpu_mem_mib`) over its particles."])


def long_window(folder):
    path = need(Path(folder) / "long.txt")
    rows = []
    for s in sphbench_summaries(path.read_text()):
        if "median" not in s:
            continue
        m = re.match(r"(\S+) (\d+) steps (.*)", s["case"])
        build, steps, flags = (m.group(1), m.group(2), m.group(3)) if m else (s["case"], "?", "")
        rows.append([f"`{build}`", f"`{flags}`", steps, f(s["median"]), f(s["mean"]),
                     f"{s['rebuilds']} of {s['recorded']}" if "rebuilds" in s else "-", f(s.get("bytes"), ",.0f")])
    if not rows:
        raise Missing(f"no run summary in {rel(path)}")
    src = Source(rel(folder), claims.gpu_of(Path(folder), None), None)
    notes = ["The file records no commit; force-loop-notes.md (change 13) names the build it measured "
             "(`sphbench` the change, `sphbench-plain` the build before it)."]
    return Table(["build", "search", "steps recorded", "median ms a step", "mean ms a step", "steps with a rebuild",
                  "bytes a particle"], rows, [src], notes)


def cuda_vs_host(machine):
    path = claims._first_file(Path(machine), ["cuda_tests.txt"])
    rows = []
    for line in path.read_text().splitlines():
        m = re.match(r"cuda(.*?) vs host, (.*?)(\d+) steps: largest position difference ([0-9.e+-]+) dp", line)
        if m:
            what = (m.group(1) + " " + m.group(2)).strip().rstrip(",")
            row = [what or "one subdomain", m.group(3), m.group(4)]
            if row not in rows:
                rows.append(row)
    if not rows:
        raise Missing(f"no 'cuda vs host' line in {rel(path)}")
    return Table(["run (n: cells per support; merge; verlet: lists)", "steps", "largest position difference, dp"],
                 rows, [from_item(path.parent, "cuda-tests")], [f"From `{rel(path)}`, the `CudaBackend.*` tests."])


def fig4(folder):
    import fig4 as fig
    folder = need(folder)
    runs, meta, steps = sphplot.load_experiment(folder)
    rows = []
    for r in runs.itertuples():
        k, p, _ = fig.relative_change(steps[r.run_id])
        bound = fig.PAPER_BOUND_PCT.get(r.scene, np.nan)
        s = steps[r.run_id]
        sim = float(s["time"].max()) if "time" in s.columns else np.nan
        dt = pd.to_numeric(sphplot.column(s, "dt", np.nan), errors="coerce").median()
        rows.append([r.run_id, thousands(len(s)), f(sim, ".4f") + " s", f(dt, ".2e") + " s", f(p.max(), ".2f") + "%",
                     str(int(k[p.argmax()])), f(np.percentile(p, 99), ".2f") + "%", f(bound, "g") + "%",
                     f"{int((p <= bound).sum())} of {len(p)}"])
    return Table(["run", "steps recorded", "simulated time at the last", "time step (median)",
                  "largest change of the update time", "at step", "99th percentile", "paper's bound",
                  "changes within it"], rows, [from_meta(folder, meta)])


def fig3(folder):
    import fig3 as fig
    folder = need(folder)
    runs, meta = sphplot.load_runs(folder)
    table = fig.single_gpu_cll(runs)
    sp = fig.speedups(table)
    if not sp:
        raise Missing("no CLL run")
    rows = []
    for group, (base, s) in sp.items():
        g = table[table.group == group]
        best = g.loc[g["T"].idxmin()]

        def counted(n, merge, col):
            v = g[(g.n == n) & (g.merging == merge)][col]
            return v.iloc[0] if len(v) else np.nan

        rows.append([group, f(base)] + [f(s[v], ".2f") + "x" for v in fig.VARIANTS.values()] +
                    [f"n = {int(best.n)}{' merged' if best.merging else ''} ({f(base / best['T'], '.2f')}x)",
                     f(counted(1, False, "cand"), ".0f"), f(counted(2, False, "cand"), ".0f"),
                     f(counted(4, True, "cand"), ".0f"), f(counted(1, False, "neigh"), ".0f")])
    header = (["scene", "CLL update ms (median)"] + [f"{v}: speedup" for v in fig.VARIANTS.values()] +
              ["fastest of the n = 1..4 sweep", "candidates a particle, CLL", "n = 2", "n = 4 merged",
               "neighbours a particle"])
    return Table(header, rows, [from_meta(folder, meta)],
                 ["Speedup: CLL's update time (forces + integration) over the variant's, as `plots/fig3.py` computes "
                  "it; candidates and neighbours per particle per step from the runs' counters."])


def _vl_comparisons(folders):
    """(folder, its source, table_vl.compare of its runs) for each folder that is there."""
    import table_vl
    for folder in folders:
        if Path(folder).is_dir():
            runs, meta = sphplot.load_runs(folder)
            yield folder, from_meta(folder, meta), table_vl.compare(runs)


def cll_vs_vl(*folders):
    rows, sources = [], []
    for folder, src, t in _vl_comparisons(folders):
        sources.append(src)
        for r in t.itertuples():
            rows.append([r.group, src.gpu, f"{r.skin} / {r.rebuild_every}", f(r.update_ms_median_cll),
                         f(r.update_ms_median_vl), f(1 / r.update_ratio, ".2f") + "x", f(r.step_ms_median_cll),
                         f(r.step_ms_median_vl), f(1 / r.step_ratio, ".2f") + "x", f(r.bytes_per_particle_cll, ".0f"),
                         f(r.bytes_per_particle_vl, ",.0f"), f(r.mem_ratio, ".1f") + "x",
                         f(80e9 / r.bytes_per_particle_cll / 1e6, ".0f") + "M / " +
                         f(80e9 / r.bytes_per_particle_vl / 1e6, ".0f") + "M"])
    if not rows:
        raise Missing("none of " + ", ".join(f"`results/reference/{rel(x)}`" for x in folders) + " is there")
    header = ["scene", "GPU", "lists' skin / rebuild every", "CLL update ms", "lists' update ms (no builds)",
              "lists' update speed / CLL's", "CLL step ms", "lists' step ms (with builds)", "step speed / CLL's",
              "CLL bytes a particle", "lists' bytes a particle", "memory lists / CLL",
              "particles in 80 GB, CLL / lists (estimate, not a run)"]
    return Table(header, rows, sources, ["Medians over the recorded steps (`plots/table_vl.py`'s `compare`); "
                                         "rebuild every 0: when particles may have moved half the skin."])


def cll_vs_vl_history(*folders):
    rows, sources = [], []
    for folder, src, t in _vl_comparisons(folders):
        sources.append(src)
        sp = 1 / t.update_ratio
        rows.append([f"`{rel(folder)}`", src.gpu, src.commit[:7], str(len(t)),
                     f"{f(sp.min(), '.2f')}-{f(sp.max(), '.2f')}x",
                     f"{f(t.bytes_per_particle_cll.min(), '.0f')}-{f(t.bytes_per_particle_cll.max(), '.0f')}"])
    if not rows:
        raise Missing("no folder of the history is there")
    return Table(["results", "GPU", "commit", "scenes", "lists' update speed / CLL's", "CLL bytes a particle"],
                 rows, sources)


def multi_gpu(*folders):
    import multigpu
    rows, sources = [], []
    for folder in folders:
        if not Path(folder).is_dir():
            continue
        table, _, meta, _, gpus = multigpu.load(folder)
        src = from_meta(folder, meta)
        sources.append(src)
        for r in table[table.devices > 1].itertuples():
            rows.append([f"`{rel(folder)}`", r.group, r.balancer, str(r.devices), f(r.T1), f(r.real_ms), f(r.ideal_ms),
                         f(r.real_ms / r.ideal_ms, ".3f"), f(r.speedup, ".2f"), f(r.ideal_eq7, ".2f"),
                         f(r.step_ms), f(r.per100, ".1f")])
    if not rows:
        raise Missing("none of " + ", ".join(f"`results/reference/{rel(x)}`" for x in folders) + " is there")
    header = ["results", "scene", "balancer", "GPUs", "update ms on 1 GPU", "real update ms (slowest GPU)",
              "ideal update ms (mean)", "real / ideal", "update speedup", "ideal speedup (equation 7)",
              "whole step ms", "slices moved per 100 steps"]
    return Table(header, rows, sources, ["Means over the recorded steps, as `plots/multigpu.py` computes them for "
                                         "Figures 5 to 9."])


def transports(folder):
    import multigpu
    import transports as tr
    folder = need(folder)
    runs, meta, steps = sphplot.load_experiment(folder)
    t = tr.with_speedups(tr.per_run(runs, steps, len(multigpu.gpu_names(meta, runs))))
    rows = [[r.group, str(r.devices), r.transport, f(r.W1), f(r.wall_ms), f(r.speedup, ".2f"), f(r.update_speedup, ".2f"),
             f(r.exchange_ms)] for r in t.itertuples()]
    return Table(["scene", "GPUs", "transport", "whole step ms on 1 GPU", "whole step ms", "whole-step speedup",
                  "update speedup", "exchange ms a step"], rows, [from_meta(folder, meta)],
                 ["Means over the recorded steps, as `plots/transports.py` computes them; threshold balancer."])


def stability(folder):
    import stability as st
    folder = need(folder)
    cfl, meta = st.load(folder, st.STUDIES[0], True)
    rows = []
    for r in cfl.itertuples():
        rows.append([f"largest stable CFL: {r.run_id} ({thousands(r.particles)} particles with walls)",
                     f"{f(r.cfl_stable, '.3f')} (x{f(r.cfl_stable / st.DEFAULT_CFL, '.1f')} the default "
                     f"{st.DEFAULT_CFL:g}); {f(r.cfl_unstable, '.3f')} blows up ({r.unstable_quantity}, step "
                     f"{r.unstable_failed_step})"])
    for study in st.STUDIES[1:]:
        table, _ = st.load(folder, study, False)
        if table is None:
            rows.append([study, "no result"])
            continue
        for r in table.itertuples():
            stable = sphplot.as_bool(pd.Series([r.stable])).iloc[0]
            head = (f"{study.removeprefix('stability-')}: {r.run_id} ({thousands(r.fluid)} fluid, "
                    f"{thousands(r.particles)} with walls), CFL {r.cfl:g}")
            if stable:
                text = f"stable for {thousands(r.steps)} steps (t = {r.time:.3g} s)"
            else:
                text = (f"blew up at step {thousands(r.failed_step)} (t = {r.time:.3g} s, {r.quantity}); "
                        "last good state written")
            text += f"; energy {pct(r.total_drift, '+.2f')}"
            if study == "stability-still-water":
                text += f", free surface {f(r.free_surface_drift / r.dp, '+.3f')} dp"
            rows.append([head, text])
    return Table(["study", "result"], rows, [from_meta(folder / st.STUDIES[0], meta)],
                 ["Energy: total (kinetic, potential, elastic) drift at the end, in percent of the energy scale "
                  "(`plots/stability.py`)."])


def skip_bench(machine):
    path = claims._first_file(Path(machine), ["skip_bench.json"])
    rows = []
    for b in json.loads(path.read_text()).get("benchmarks", []):
        if b.get("aggregate_name") == "median":
            name = b["name"].removesuffix("/manual_time_median").removeprefix("skip/")
            phase, variant = name.split("/", 1)
            rows.append([phase, variant, f(b["real_time"], ".4f")])
    if not rows:
        raise Missing(f"no median in {rel(path)}")
    return Table(["phase timed", "variant", "median ms (5 repetitions, CUDA events)"], rows,
                 [from_item(path.parent, "skip-bench")], [f"From `{rel(path)}` (`sph_skip_bench`)."])


def accuracy(folder):
    import accuracy as acc
    folder = need(folder)
    runs, meta = sphplot.load_runs(folder)
    data = acc.table(runs)
    d = data.set_index(["scene", "variant"])
    tank_pa = runs.set_index("run_id")["hydro_bottom_pa_final"] if "hydro_bottom_pa_final" in runs.columns else {}
    variants = list(dict.fromkeys(data.variant))
    rows = []
    for v in variants:
        cells = [v]
        if ("dambreak", v) in d.index:
            r = d.loc[("dambreak", v)]
            cells += [f(r.error, ".3f") + f" ({f(r.secondary, '.3f')})", f(r.run_time_s, ".1f")]
        else:
            cells += ["-", "-"]
        if ("tank", v) in d.index:
            r = d.loc[("tank", v)]
            pa = tank_pa.get(f"tank-{v}", np.nan) if len(tank_pa) else np.nan
            cells += [f(100 * r.error, ".2f") + "%", f(pa, "+.0f") + " Pa", f(r.run_time_s, ".1f")]
        else:
            cells += ["-", "-", "-"]
        rows.append(cells)
    return Table(["run", "dam break: front RMS vs Martin-Moyce (vs Koshizuka-Oka)", "run time s",
                  "tank: pressure rel. RMS", "bottom pressure above rho0 g H", "run time s"], rows,
                 [from_meta(folder, meta)],
                 ["Run time: wall time less the metric's evaluation (`plots/accuracy.py`); baseline: Wendland, CFL 0.2, "
                  "diffusion 0.1, CLL, float32; each other run changes one of those."])


def spheric2_sources(folder, meta, dsph):
    """Where a SPHERIC Test 2 table reads from: our runs, and DualSPHysics' folder where there is one."""
    sources = [from_meta(folder, meta)]
    if dsph is not None:
        try:
            sources.append(from_item(dsph, "spheric2-dualsphysics"))
        except Missing:  # copied in by hand, not by `make reference`: no commit to name
            sources.append(Source(rel(dsph), claims.gpu_of(machine_of(dsph), None), None))
    return sources


def spheric2(folder, dsph_folder):
    """SPHERIC Test 2: each run of ours and of DualSPHysics, its water-height errors, P1's first
    peak and its run time (plots/spheric2.py's table)."""
    import spheric2 as sp2
    folder = need(folder)
    runs, meta = sphplot.load_runs(folder)
    dsph = Path(dsph_folder) if Path(dsph_folder).is_dir() else None
    data, _, _, _ = sp2.table(folder, dsph, sp2.read_measured(sp2.MEASURED))
    sources = spheric2_sources(folder, meta, dsph)
    rows = []
    for _, r in data.sort_values(["code", "dp", "s_per_sim_s"], ascending=[False, False, True]).iterrows():
        p1 = (f"{r['P1_peak_kpa']:.2f} ({100 * r['P1_peak_err']:+.0f}%, {r['P1_peak_dt_ms']:+.0f} ms)"
              if np.isfinite(r.get("P1_peak_kpa", np.nan)) else "-")
        impulse = (f"{r['P1_impulse']:.0f} ({100 * r['P1_impulse_err']:+.1f}%, arrival {r['P1_arrival_dt_ms']:+.0f} ms)"
                   if np.isfinite(r.get("P1_impulse", np.nan)) else "-")
        rows.append([r["code"], r["run"], thousands(r["particles"]), f(r["s_per_sim_s"], ".2f")]
                    + [f(100 * r[f"{p}_rms"], ".1f") for p in sp2.PROBES]
                    + [f"**{f(100 * r['H_rms_mean'], '.1f')}**", f(100 * r.get("H_rms_mean_6s", np.nan), ".1f"), p1, impulse,
                       "yes" if r["pareto"] else ("blew up" if r["blew_up"] else "")])
    return Table(["code", "run", "particles", "s per simulated second"] + [f"{p} RMS %" for p in sp2.PROBES]
                 + ["mean %", "mean % to 6 s", "P1 first peak kPa (vs measured)", "P1 impulse Pa s (vs measured)",
                    "Pareto front"],
                 rows, sources,
                 ["Water heights: RMS over 0-2 s against the MARIN measurements, relative to 0.55 m (the measured "
                  "file's H1 and H3 swapped back); for the runs to 6 s also the mean over 0-6 s ('-': a run to 2 s). P1: the centred 5 ms mean (the integral over each window) on ours and the measurement alike, the "
                  "largest value in 0.3-0.8 s; its impulse, the integral over 100 ms from the arrival (a fifth of the "
                  "first peak). `plots/spheric2.py` says how each error is computed."])


def spheric2_box_load(folder, dsph_folder):
    """SPHERIC Test 2: the water's load on the box, ours and DualSPHysics' (their force gauges) and
    the measurement's estimate from P1-P4 (plots/spheric2.py's box_loads)."""
    import spheric2 as sp2
    folder = need(folder)
    _, meta = sphplot.load_runs(folder)
    dsph = Path(dsph_folder) if Path(dsph_folder).is_dir() else None
    data = sp2.box_loads(folder, dsph, sp2.read_measured(sp2.MEASURED))
    sources = spheric2_sources(folder, meta, dsph)
    order = {"ours": 0, "DualSPHysics": 1, "measured (estimate)": 2}
    data = data.assign(_o=data["code"].map(order), _dp=-data["dp"].fillna(-1)).sort_values(["_o", "_dp"])
    rows = [[r["code"], r["run"], f(r["arrival_s"], ".3f"), f(r["peak_n"], ".0f"), f(r["impulse_ns"], ".1f"),
             f(r["mean_after_n"], ".1f")] for _, r in data.iterrows()]
    return Table(["code", "run", "arrival s", "largest load N (0.3-0.8 s)",
                  f"impulse N s ({sp2.IMPULSE_S * 1e3:g} ms from the arrival)", "mean net load N (0.8-2 s)"],
                 rows, sources,
                 ["The load: minus the x force of the water on the box (ours: the force gauge `box`, every 5 ms; "
                  "DualSPHysics: its GaugesForce_Box, every 5 ms). The measurement has no force: its row is the mean "
                  "of P1-P4 (their centred 5 ms means) times the face's area (0.403 x 0.161 m), taking the centre line's "
                  "pressure for the face's whole width, and only the face toward the reservoir (so no mean after "
                  "0.8 s, when water presses on the back face too). The arrival: the first time the load passes a "
                  "fifth of its largest value (`plots/spheric2.py`)."])


def spheric2_sound_speed(folder):
    """SPHERIC Test 2's first impact on P1 at two sound speeds (experiments/spheric2-sound-speed.toml,
    host, dp 0.02): the unfiltered first peak, the ringing's period after it, the 5 ms peak and the
    impulse against the measurement, the arrival (plots/spheric2.py's errors)."""
    import spheric2 as sp2
    folder = need(folder)
    rows, _, runs, meta = sp2.our_runs(folder, sp2.read_measured(sp2.MEASURED))
    c0 = dict(zip(runs["run_id"], runs["set.c0_factor"]))
    out = []
    for r in sorted(rows, key=lambda r: -float(c0[r["run"]])):
        out.append([r["run"], f(float(c0[r["run"]]), ".0f"), thousands(r["particles"]), f(r["P1_raw_peak_kpa"], ".1f"),
                    f(r["P1_ringing_ms"], ".1f"), f"{f(r['P1_peak_kpa'], '.1f')} ({100 * r['P1_peak_err']:+.0f}%)",
                    f"{r['P1_impulse']:.0f} ({100 * r['P1_impulse_err']:+.1f}%)", f"{r['P1_arrival_dt_ms']:+.0f}"])
    source = from_meta(folder, meta)
    source.gpu = "host backend (no GPU)"
    return Table(["run", "c0 / sqrt(g 0.55)", "particles", "P1 unfiltered first peak kPa", "ringing period ms",
                  "P1 5 ms peak kPa (vs measured)", "P1 impulse Pa s (vs measured)", "arrival ms (vs measured)"],
                 out, [source],
                 ["Full scale on the host backend, one process, Wendland with Verlet lists, from rest to 0.6 s. The "
                  "ringing period: the strongest frequency of the unfiltered gauge over the 40 ms after its peak. The 5 "
                  "ms peak, the impulse (100 ms from the arrival) and the arrival as in the table above "
                  "(`plots/spheric2.py`)."])


def spheric2_p1_sampling(folder, *more_folders):
    """SPHERIC Test 2's first impact on P1 read from a gauge sampled at every step
    (experiments/spheric2-p1-sampling.toml; more_folders: the same gauges at the finest spacing and
    with another diffusion form, each where it has been run) and from the same run's 1 ms point
    samples (what the spheric2 spec's gauge reads): the unfiltered peak, the 5 ms mean's peak and the
    impulse each way, against the measurement filtered alike (plots/spheric2.py)."""
    import numpy as np
    import spheric2 as sp2
    folder = need(folder)
    measured = sp2.read_measured(sp2.MEASURED)
    folders = [folder] + [Path(f) for f in more_folders if Path(f, "runs.csv").is_file()]
    loaded = [(f, *sphplot.load_runs(f)) for f in folders]
    sources = [from_meta(f, meta) for f, _, meta in loaded]
    grid_m, meas = sp2.smoothed(measured["time"], measured["P1"], 0.8)
    mpeak, mwhen = sp2.first_peak(grid_m, meas)
    mimpulse, _ = sp2.first_impulse(grid_m, meas)
    rows = []
    every_run = [(f, run) for f, runs, _ in loaded for _, run in runs.iterrows()]
    for run_folder, run in sorted(every_run, key=lambda fr: -float(fr[1]["dp"])):
        path = Path(run_folder) / f"{run['run_id']}_gauges.csv"
        t, p = sp2.read_our_gauges(path)["P1"]
        cells = [run["run_id"], thousands(int(run["particles"])), f"{1e6 * float(np.median(np.diff(t))):.0f}"]
        for series in ((t, p), sp2.point_sampled(t, p)):
            raw_peak, period = sp2.first_ringing(*series)
            grid, smooth = sp2.smoothed(*series, min(float(run["sim_time"]), 0.8))
            peak, when = sp2.first_peak(grid, smooth)
            impulse, _ = sp2.first_impulse(grid, smooth)
            cells += [f(raw_peak / 1e3, ".1f"), f(period * 1e3, ".1f"),
                      f"{f(peak / 1e3, '.1f')} ({100 * (peak - mpeak) / mpeak:+.0f}%, {1e3 * (when - mwhen):+.0f} ms)",
                      f"{impulse:.0f} ({100 * (impulse - mimpulse) / mimpulse:+.1f}%)"]
        rows.append(cells)
    rows.append(["measured", "-", "~1,000"] + ["-", "-", f"{mpeak / 1e3:.1f}", f"{mimpulse:.0f}"] * 2)
    return Table(["run", "particles", "P1 sampled every (us, median)",
                  "every step: unfiltered peak kPa", "ringing period ms", "5 ms mean peak kPa (vs measured)",
                  "impulse Pa s (vs measured)",
                  "every 1 ms: unfiltered peak kPa", "ringing period ms", "5 ms mean peak kPa (vs measured)",
                  "impulse Pa s (vs measured)"],
                 rows, sources,
                 ["Wendland with Verlet lists (skin 0.1), from rest to 0.6 s (dp 0.004: to 0.55 s, "
                  "experiments/spheric2-p1-finest.toml; a run labelled fourtakas-full: DensityDT 3, "
                  "experiments/spheric2-p1-diffusion-walls.toml, the others DensityDT 2), "
                  "P1 (0.015 m off the box's face at z = 0.021) sampled at every step. The 1 ms columns read the same run's series as a gauge "
                  "sampled every 1 ms would (the first step at or after each ms: `point_sampled`). The 5 ms mean: "
                  "the integral of the linearly interpolated series over each centred 5 ms window, the same "
                  "filter on the measurement (`plots/spheric2.py`); the peak in 0.3-0.8 s, the impulse over 100 "
                  "ms from the arrival; the ringing period: the strongest frequency over the 40 ms after the "
                  "unfiltered peak."])


def front_offsets(folder):
    """The dam-break front by mass threshold against each data set: RMS (the particle front's),
    the fitted time offset and the RMS with it, the RMS with the published +0.175, the lead's slope."""
    import accuracy as acc
    folder = need(folder)
    runs, meta = sphplot.load_runs(folder)
    t = acc.offset_table(runs)
    if t.empty:
        raise Missing(f"`results/reference/{rel(folder)}` has no front offsets")
    keys = list(dict.fromkeys(t["data"]))
    rows = []
    for variant, d in t.groupby("variant", sort=False):
        cells = [variant]
        for key in keys:
            r = d[d["data"] == key]
            if r.empty:
                cells.append("-")
                continue
            r = r.iloc[0]
            cells.append(f"{f(r.rms)} ({f(r.rms_particle_front)}); dT {f(r.offset_T, '+.3f')}: {f(r.rms_offset)}; "
                         f"+0.175: {f(r.rms_published_offset)}; b {f(r.lead_slope, '+.2f')} ({r.trend})")
        rows.append(cells)
    source = from_meta(folder, meta)
    on_host = machine_of(folder).name == "host"
    if on_host:
        source.gpu = "host backend (no GPU)"
    scale = ("Host backend, reduced scale (the spec's [host]: 10 spacings across the column)." if on_host else
             "Full scale on the GPU, the runs of the accuracy table above (float32, and the float64 build's baseline).")
    return Table(["run"] + keys, rows, [source],
                 ["Per data set: RMS in Z of the mass-threshold front (of the particle front), the fitted offset dT in T "
                  "(> 0: ours leads) and the RMS with it, the RMS with the published +0.175, and the lead's slope b in T "
                  f"(`plots/accuracy.py`). {scale}"])


TG_TIMES = (0.1, 0.15, 0.2, 0.3, 0.5)


def taylor_green(path):
    path = need(path)
    rows = []
    for b in re.split(r"^== ", path.read_text(), flags=re.M)[1:]:
        title, _, body = b.partition("\n")
        series = [tuple(map(float, ln.split(",")[:2])) for ln in body.splitlines()
                  if re.match(r"[0-9.e+-]+,[0-9.e+-]+(,[0-9.e+-]+)?$", ln)]
        if not series:
            continue
        t = np.array([x for x, _ in series])
        e = np.array([y for _, y in series])
        rows.append([title.strip()] + [f"{100 * e[np.abs(t - want).argmin()]:.1f}%" for want in TG_TIMES])
    if not rows:
        raise Missing(f"no series in {rel(path)}")
    src = Source(rel(path), claims.gpu_of(path.parent, None), None)
    return Table(["run (relative L2 error of the velocity at t =)"] + [f"{x:g} s" for x in TG_TIMES], rows, [src],
                 ["The file records no commit, nor the resolution: it was written in the check of the Verlet "
                  "integration (`verlet-check/`); the error is read at the validation time nearest each column's."])


def shifting_cost(*paths):
    rows, sources = [], []
    for path in paths:
        if not Path(path).is_file():
            continue
        by = {}
        for s in sphbench_summaries(Path(path).read_text()):
            if "median" not in s:
                continue
            m = re.match(r"rep \d+ (\S+) (.*)", s["case"])
            if m:
                by.setdefault((m.group(2).strip(), m.group(1)), []).append(s["median"])
        for (case, build), v in by.items():
            rows.append([f"`{rel(path)}`", case, f"`{build}`", ", ".join(f(x) for x in v)])
        sources.append(Source(rel(path), claims.gpu_of(Path(path).parent, None), None))
    if not rows:
        raise Missing("no shifting measurement is there")
    return Table(["file", "case", "build", "median ms a step, per repetition"], rows, sources,
                 ["The files record no commit; `sphbench-prev` is the build before the change, `sphbench` the change "
                  "(in the force loop, then as a pass of its own)."])


def mpi_cuda(folder):
    path = need(Path(folder) / "summary.txt")
    text = path.read_text()
    rows = []
    for m in re.finditer(r"^(\S+): time per step: median ([0-9.]+) ms \(quartiles ([0-9.]+) to ([0-9.]+)\); "
                         r"update \(forces \+ integration\) ([0-9.]+) ms; rank_transport: ?(\S*)", text, re.M):
        rows.append([m.group(1), f(float(m.group(2))), f(float(m.group(5))), m.group(6) or "-"])
    eq = re.findall(r"^(equivalence-\S+): (.*?): (\d+) steps bitwise equal.*?; (\d+) slices moved, (\d+) particles "
                    r"migrated", text, re.M)
    notes = [f"`sph_mpi_equivalence` {name} ({what}): {steps} steps bitwise equal to one process; {sl} slices moved, "
             f"{pa} particles migrated." for name, what, steps, sl, pa in eq]
    if not rows:
        raise Missing(f"no timing in {rel(path)}")
    return Table(["run (2 subdomains, dam break dp 0.02)", "median ms a step", "update ms", "rank transport"], rows,
                 [from_text(folder, path)], notes)


def mpi_host(folder):
    folder = need(folder)
    labels = {"one1": "one process, 1 OpenMP thread", "one2": "one process, 2 OpenMP threads",
              "mpi": "mpirun -np 2, 1 OpenMP thread a rank"}
    rows, meta = [], None
    for sub in (2, 4):
        for key, label in labels.items():
            p = folder / f"{key}-{sub}sub_steps.csv"
            if not p.is_file():
                continue
            s, meta = sphplot.read_csv_with_metadata(p)
            rows.append([str(sub), label, f(s["wall_ms"].median(), ".1f"), f(s["step_ms"].median(), ".1f"),
                         f(s["update_ms"].median(), ".1f")])
    if not rows:
        raise Missing(f"no step file in {rel(folder)}")
    src = from_meta(folder, meta)
    src.gpu = "host CPU (2 cores, no GPU)"
    return Table(["subdomains", "run", "wall ms a step (median)", "step ms (phases, slowest subdomain)",
                  "update ms (slowest subdomain)"], rows, [src],
                 ["Medians over the step files' 100 recorded steps; the particles are bitwise those of one process "
                  "(the `mpi_*` ctests)."])


def overlap(folder):
    path = need(Path(folder) / "phases.txt")
    lines = path.read_text().splitlines()
    cols = lines[0].split()
    data = {ln.split()[0]: dict(zip(cols[1:], map(float, ln.split()[1:]))) for ln in lines[1:] if ln.strip()}
    rows = []
    for run, v in data.items():
        m = re.match(r"(\w+?)_d(\d+)(nooverlap)?$", run)
        if not m:
            continue
        scene = {"armadillo": "armadillo 2,980K", "dsphdambreak": "dam break 1.04M"}.get(m.group(1), m.group(1))
        rows.append([scene, m.group(2), "-" if m.group(2) == "1" else ("off" if m.group(3) else "on"), f(v["wall"]),
                     f(v["step"]), f(v["exchange"]), f(v["transfer"])])
    readme = Path(folder) / "README.md"
    src = from_text(folder, readme if readme.is_file() else path)
    return Table(["scene", "subdomains on the one GPU", "overlap", "wall ms a step", "step ms (sum of phases)",
                  "exchange ms", "transfer ms (CUDA events)"], rows, [src],
                 [f"Medians of the step files, from `{rel(path)}`."])


# --------------------------------------------------------------------------------------------
# The blocks


def load_spec(path=SPEC):
    spec = tomllib.loads(Path(path).read_text())["table"]
    names = set()
    for t in spec:
        if t.get("name") in names or "name" not in t:
            raise SystemExit(f"results_tables: {path}: a table without a name, or named twice: {t.get('name')}")
        names.add(t["name"])
        if "absent" not in t and (t.get("function") not in FUNCTIONS or "results" not in t):
            raise SystemExit(f"results_tables: {path}: table {t['name']}: no function '{t.get('function')}' in "
                             "plots/results_tables.py, or no results.")
    return spec


def markdown(header, rows):
    lines = ["| " + " | ".join(claims.cell(h) for h in header) + " |", "|" + " --- |" * len(header)]
    lines += ["| " + " | ".join(claims.cell(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def caption(sources, hist):
    out = []
    for s in sources:
        dirty = " (dirty)" if str(s.dirty).lower() in ("dirty", "yes", "true") else ""
        commit = s.commit[:7] if s.commit != "unknown" else "not recorded"
        fresh = claims.freshness(s.commit, hist) if s.commit != "unknown" else "unknown (no commit recorded)"
        out.append(f"- `results/reference/{s.path}`: {s.gpu}, commit {commit}{dirty}; current?: {fresh}")
    return "\n".join(out)


GENERATED = "Generated by `make claims` (plots/results_tables.py, table `{name}`); do not edit by hand."


def block(spec, reference, hist):
    name = spec["name"]
    head = GENERATED.format(name=name)
    if "absent" in spec:
        return (f"{head}\n\n**No committed result**: {spec['absent']}. The figures once typed here are in this "
                f"page's git history; to have them generated, run `{spec['rerun']}` and commit its results under "
                "`results/reference/`, with a function in plots/results_tables.py.\n")
    folders = [reference / p for p in spec["results"]]
    try:
        t = FUNCTIONS[spec["function"]](*folders)
    except (Missing, sphplot.ResultsError) as e:
        return (f"{head}\n\n**No result**: {e}; the table cannot be generated from results/reference/ "
                f"({', '.join(f'`{p}`' for p in spec['results'])}).\n")
    text = f"{head} Read from:\n{caption(t.sources, hist)}\n\n{markdown(t.header, t.rows)}\n"
    if t.notes:
        text += "\n" + "\n".join(t.notes) + "\n"
    return text


def blocks(reference=REFERENCE, spec=SPEC, repo=REPO):
    hist = claims.history(repo)
    return {t["name"]: block(t, Path(reference), hist) for t in load_spec(spec)}, hist


def doc_blocks(text):
    return {m.group(1): m.group(2) for m in MARK.finditer(text)}


def masked(text):
    return FRESH.sub(r"\1?", text)


def check(doc, generated, hist, name="docs/results.md"):
    """(ok, message): every declared table's block is in the page and is what the generator makes."""
    have = doc_blocks(doc)
    problems = []
    for tname, gen in generated.items():
        if tname not in have:
            problems.append(f"{name} lacks the markers {begin(tname)} and {end(tname)}")
            continue
        if have[tname] == gen or (hist[0] is None and masked(have[tname]) == masked(gen)):
            continue
        import difflib
        diff = "\n".join(difflib.unified_diff(have[tname].splitlines(), gen.splitlines(), f"{name} ({tname})",
                                              "generated", lineterm="", n=0))
        problems.append(f"table {tname} differs from what plots/results_tables.py makes of results/reference/:\n{diff}")
    for tname in have:
        if tname not in generated:
            problems.append(f"{name} has a block {tname} that plots/results_tables.toml does not declare")
    if problems:
        return False, ("results_tables: " + "\n".join(problems) + f"\nRun `make claims` and commit {name}.")
    extra = "" if hist[0] is not None else f"; whether they are current is not checked here ({hist[1]})"
    return True, f"results_tables: {name}'s {len(generated)} generated tables match the committed results{extra}."


def write(text, generated):
    have = doc_blocks(text)
    missing = [n for n in generated if n not in have]
    if missing:
        raise SystemExit("results_tables: the page lacks the markers of " + ", ".join(missing) +
                         f" ({begin(missing[0])} ... {end(missing[0])}).")
    return MARK.sub(lambda m: f"{begin(m.group(1))}\n{generated.get(m.group(1), m.group(2))}{end(m.group(1))}\n", text)


def main(argv=None):
    p = argparse.ArgumentParser(prog="results_tables.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--write", action="store_true", help="write the tables into the page between their markers")
    p.add_argument("--check", action="store_true", help="exit 1 when a table of the page differs")
    p.add_argument("--doc", type=Path, default=DOC)
    p.add_argument("--reference", type=Path, default=REFERENCE)
    args = p.parse_args(argv)
    generated, hist = blocks(args.reference)
    shown = claims.shown(args.doc)
    if args.check:
        ok, message = check(args.doc.read_text(), generated, hist, shown)
        print(message)
        return 0 if ok else 1
    if args.write:
        text = args.doc.read_text()
        new = write(text, generated)
        if new != text:
            args.doc.write_text(new)
            print(f"results_tables: wrote {len(generated)} tables into {shown}")
        else:
            print(f"results_tables: {shown} is up to date")
        return 0
    for name, text in generated.items():
        sys.stdout.write(f"{begin(name)}\n{text}{end(name)}\n\n")
    return 0


FUNCTIONS = {fn.__name__: fn for fn in (whole_run, whole_run_windows, dualsphysics, long_window, cuda_vs_host, fig4,
                                        fig3, cll_vs_vl, cll_vs_vl_history, multi_gpu, transports, stability,
                                        skip_bench, accuracy, taylor_green, shifting_cost, mpi_cuda, mpi_host,
                                        overlap, spheric2, spheric2_box_load, spheric2_sound_speed, spheric2_p1_sampling,
                                        front_offsets)}

if __name__ == "__main__":
    sys.exit(main())
