"""The claims table of docs/results.md, generated from the committed results (results/reference/) by the
declarations of plots/claims.toml: for each claim of the paper, our figure, the GPU and commit
that measured it, a verdict (holds / does not hold / differs in kind) and why. A result whose
commit is older than the last change under solver/ is marked STALE; where git's history cannot
tell (a shallow clone, no repository, a commit it lacks) the table says so.

Usage: python3 plots/claims.py          print the table (markdown)
       python3 plots/claims.py --write  put it into docs/results.md between the markers (make claims)
       python3 plots/claims.py --check  exit 1 when docs/results.md's table differs (make test)
"""
import argparse
import re
import subprocess
import sys
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

import numpy as np

import sphplot
from sphplot import pd

REPO = sphplot.REPO
SPEC = REPO / "plots" / "claims.toml"
REFERENCE = REPO / "results" / "reference"
DOC = REPO / "docs" / "results.md"  # the page that holds the table, between BEGIN and END
BEGIN, END = "<!-- claims:begin -->", "<!-- claims:end -->"
VERDICTS = ("holds", "does not hold", "differs in kind")
HEADER = ["where", "the paper says", "ours", "measured on", "commit", "current?", "verdict", "why"]
FRESH_COLUMN = HEADER.index("current?")


# No commit in the mark: the commit that changes solver/ cannot name itself in the page it carries.
STALE = "**STALE**: solver/ changed after it"
UNCOMMITTED = "uncommitted changes under solver/"


class Missing(Exception):
    """The folder lacks what a metric reads: try the next one."""


# --------------------------------------------------------------------------------------------
# Metrics: each takes a results folder (and the claim's args) and returns named values, plus the
# provenance (metadata of the CSV it read, or None) under "_meta".


def _runs(folder):
    if not (folder / "runs.csv").is_file():
        raise Missing(folder)
    return sphplot.load_runs(folder)


def _span(values):
    v = [float(x) for x in values if np.isfinite(x)]
    if not v:
        raise Missing("no finite values")
    return min(v), max(v)


def cll_vs_vl(folder):
    import table_vl
    runs, meta = _runs(folder)
    t = table_vl.compare(runs)
    speed_lo, speed_hi = _span(1.0 / t.update_ratio)
    step_lo, step_hi = _span(1.0 / t.step_ratio)
    mem_lo, mem_hi = _span(t.mem_ratio)
    vl_lo, vl_hi = _span(t.bytes_per_particle_vl)
    return dict(speed_lo=speed_lo, speed_hi=speed_hi, step_lo=step_lo, step_hi=step_hi, mem_lo=mem_lo, mem_hi=mem_hi,
                vl_lo=vl_lo, vl_hi=vl_hi, cll_bytes=float(t.bytes_per_particle_cll.median()), scenes=len(t), _meta=meta)


def _fig3(folder):
    import fig3
    runs, meta = _runs(folder)
    table = fig3.single_gpu_cll(runs)
    sp = fig3.speedups(table)
    if not sp:
        raise Missing("no CLL run")
    return table, sp, meta


def fig3_speedup(folder, n, merge):
    import fig3
    _, sp, meta = _fig3(folder)
    name = fig3.VARIANTS[(n, merge)]
    lo, hi = _span(s[name] for _, s in sp.values())
    return dict(lo=lo, hi=hi, scenes=len(sp), _meta=meta)


def fig3_best(folder):
    import fig3
    table, sp, meta = _fig3(folder)
    both, alone, merged = fig3.VARIANTS[(2, True)], fig3.VARIANTS[(2, False)], fig3.VARIANTS[(1, True)]
    wins = sum(1 for _, s in sp.values() if s[both] > max(s[alone], s[merged]))
    lo, hi = _span(s[both] for _, s in sp.values())
    bests = []
    for _, g in table.groupby("group", sort=False):
        r = g.loc[g["T"].idxmin()]
        bests.append(f"n = {int(r.n)}{' merged' if r.merging else ''}")
    best = bests[0] if len(set(bests)) == 1 else ", ".join(sorted(set(bests)))
    return dict(lo=lo, hi=hi, wins=wins, scenes=len(sp), best=best + (" in every scene" if len(set(bests)) == 1 else ""),
                _meta=meta)


def fig4_change(folder, scene, bound):
    import fig4
    if not (folder / "runs.csv").is_file():
        raise Missing(folder)
    runs, meta, steps = sphplot.load_experiment(folder)
    rows = runs[runs.scene == scene]
    if rows.empty:
        raise Missing(f"no {scene} run")
    k, pct, _ = fig4.relative_change(steps[rows.iloc[0]["run_id"]])
    return dict(largest=float(pct.max()), at=int(k[pct.argmax()]), p99=float(np.percentile(pct, 99)),
                within=int((pct <= bound).sum()), changes=len(pct), bound=bound, _meta=meta)


def _multi(folder):
    import multigpu
    if not (folder / "runs.csv").is_file():
        raise Missing(folder)
    table, _, meta, _, gpus = multigpu.load(folder)
    return table, meta, gpus


def _widest(t):
    """The rows of the largest device count that had a GPU each."""
    t = t[t.note.isna() & (t.devices > 1)]
    if t.empty:
        raise Missing("no run on several GPUs")
    n = int(t.devices.max())
    return t[t.devices == n], n


def balance(folder, balancer):
    table, meta, _ = _multi(folder)
    t, n = _widest(table[table.balancer == balancer])
    lo, hi = _span(t.real_ms / t.ideal_ms)
    return dict(lo=lo, hi=hi, devices=n, scenes=len(t), _meta=meta)


def speedup(folder, balancer):
    table, meta, _ = _multi(folder)
    t, n = _widest(table[table.balancer == balancer])
    lo, hi = _span(t.speedup)
    eq7_lo, eq7_hi = _span(t.ideal_eq7)
    return dict(lo=lo, hi=hi, eq7_lo=eq7_lo, eq7_hi=eq7_hi, devices=n, scenes=len(t), _meta=meta)


def speedup_by_size(folder, balancer, scene):
    table, meta, _ = _multi(folder)
    t, n = _widest(table[(table.balancer == balancer) & (table.scene == scene)])
    t = t.sort_values("size")
    values = list(t.speedup)
    series = " -> ".join(f"{v:.2f} ({sphplot.size_label(s)})" for v, s in zip(values, t["size"]))
    growing = all(b >= a - 0.005 for a, b in zip(values, values[1:])) and values[-1] > values[0]
    return dict(series=series, growing=growing, devices=n, _meta=meta)


def threshold_gain(folder):
    table, meta, _ = _multi(folder)
    simple, n = _widest(table[table.balancer == "simple"])
    threshold = table[(table.balancer == "threshold") & (table.devices == n)]
    m = simple.merge(threshold, on=["group", "devices"], suffixes=("_s", "_t"))
    lo, hi = _span(m.real_ms_s / m.real_ms_t)
    return dict(lo=lo, hi=hi, devices=n, _meta=meta)


def transports(folder):
    import multigpu
    import transports as transport_plot
    if not (folder / "runs.csv").is_file():
        raise Missing(folder)
    runs, meta, steps = sphplot.load_experiment(folder)
    t = transport_plot.with_speedups(transport_plot.per_run(runs, steps, len(multigpu.gpu_names(meta, runs))))
    t, n = _widest(t)
    out = dict(devices=n, _meta=meta)
    for tr in ("staged", "peer", "nccl"):
        out[f"{tr}_lo"], out[f"{tr}_hi"] = _span(t[t.transport == tr].speedup) if (t.transport == tr).any() else (np.nan, np.nan)
    return out


# DualSPHysics' cases (its run.sh) and our benchmark case for each.
DSPH_CASES = {"dp0045_cubic": "dsph-dambreak", "dp0045_wendland_half": "dsph-dambreak --set kernel=wendland --cells-per-support 2",
              "dp0028_cubic": "dsph-dambreak --set dp=0.0028",
              "dp0028_wendland_half": "dsph-dambreak --set dp=0.0028 --set kernel=wendland --cells-per-support 2"}
# The same cases with Verlet lists (tools/reference.py's benchmark cases): the physics of each
# DualSPHysics case, our fastest search.
VERLET = "--verlet --cells-per-support 2 --skin 0.05"
DSPH_CASES_VERLET = {"dp0045_cubic": f"dsph-dambreak {VERLET}",
                     "dp0045_wendland_half": f"dsph-dambreak --set kernel=wendland {VERLET}",
                     "dp0028_cubic": f"dsph-dambreak --set dp=0.0028 {VERLET}",
                     "dp0028_wendland_half": f"dsph-dambreak --set dp=0.0028 --set kernel=wendland {VERLET}"}


def _first_file(folder, names):
    for n in names:
        if (folder / n).is_file():
            return folder / n
    raise Missing(f"none of {names} in {folder}")


def ours_per_step(text):
    """{case: median ms per step} of `sphbench simulate` in a benchmarks.txt (the last of each)."""
    out, case = {}, None
    for line in text.splitlines():
        m = re.match(r"== (\S+) simulate (.*?)(?: --steps .*| \(repetition \d+\))?$", line)
        if m:
            case = m.group(2).strip() if m.group(1) == "sphbench" else None
            continue
        # "time per step in the window:" since the summary leads with the whole run (issue 25)
        m = re.match(r"time per step(?: in the window)?: median ([0-9.]+) ms", line)
        if m and case is not None:
            out[case] = float(m.group(1))
    return out


def dualsphysics(folder, search="cells"):
    """DualSPHysics' time per step over ours, per case: ours with its search (cells) or with Verlet lists."""
    cases = DSPH_CASES_VERLET if search == "verlet" else DSPH_CASES
    ours = ours_per_step(_first_file(folder, ["benchmarks/benchmarks.txt", "benchmarks.txt"]).read_text())
    summary = _first_file(folder, ["dualsphysics/summary.txt", "dualsphysics-summary.txt"]).read_text().splitlines()
    cols = summary[0].split()
    theirs = {}
    for line in summary[1:]:
        cells = line.split()
        if len(cells) == len(cols) and cells[cols.index("rc")] == "0":
            theirs[cells[0]] = float(cells[cols.index("ms_per_step")])
    ratios = [(c, theirs[c] / ours[o]) for c, o in cases.items() if c in theirs and o in ours]
    if not ratios:
        raise Missing("no case measured by both")
    lo, hi = _span(r for _, r in ratios)
    cases = ", ".join(f"{c} {r:.2f}x" for c, r in ratios)
    return dict(lo=lo, hi=hi, cases=cases, faster=sum(r > 1.0 for _, r in ratios), twice=sum(r >= 2.0 for _, r in ratios), n=len(ratios), _meta=None,
                _item="benchmarks")


def skip_bench(folder, does, skips):
    """How much of `does` (a Google Benchmark name under skip/) skipping the work saves: medians."""
    import json
    path = _first_file(folder, ["skip_bench.json"])
    medians, gpu = {}, None
    for b in json.loads(path.read_text()).get("benchmarks", []):
        if b.get("aggregate_name") == "median":
            name = b["name"].removesuffix("/manual_time_median").removeprefix("skip/")
            medians[name], gpu = float(b["real_time"]), b.get("label", gpu)
    if does not in medians or skips not in medians:
        raise Missing(f"{path} lacks {does} or {skips}")
    t_does, t_skips = medians[does], medians[skips]
    gpu = re.sub(r" \(GPU \d+\)$", "", gpu or "")
    return dict(does=t_does, skips=t_skips, saved=100.0 * (1.0 - t_skips / t_does), _meta=None, _gpu=gpu or None,
                _item="skip-bench")


def whole_run(folder):
    """DualSPHysics' dam break 1.04M over its whole event with our fastest path (Verlet lists), per
    kernel: seconds per simulated second, bytes a particle, a rebuild step in listed steps
    (results of `make reference`'s whole-run-1.04M and whole-run-4.04M items, or bench/lease/whole-run.sh's)."""
    runs = {}
    for path in sorted(folder.glob("dambreak-1.04M-*-lists.runs.csv")):
        df, meta = sphplot.read_csv_with_metadata(path)
        r = df.iloc[0]
        runs[str(r["set.kernel"]) if "set.kernel" in df.columns else path.stem] = (r, meta)
    if not runs:
        raise Missing(f"no dambreak-1.04M-*-lists.runs.csv in {folder}")
    s = [float(r["s_per_sim_s"]) for r, _ in runs.values()]
    b = [float(r["bytes_per_particle"]) for r, _ in runs.values()]
    q = [float(r["rebuild_step_ms"]) / float(r["listed_step_ms"]) for r, _ in runs.values()]
    listed = [float(r["listed_step_ms"]) for r, _ in runs.values()]
    steps = [float(r["steps"]) / float(r["sim_time"]) for r, _ in runs.values()]
    every = [float(r["steps"]) / max(float(r["list_rebuilds"]), 1.0) for r, _ in runs.values()]
    cases = ", ".join(f"{k} {float(r['s_per_sim_s']):.1f} s" for k, (r, _) in sorted(runs.items()))
    return dict(lo=min(s), hi=max(s), cases=cases, bytes_lo=min(b), bytes_hi=max(b), ratio_lo=min(q), ratio_hi=max(q),
                listed_lo=min(listed), budget=20e3 / max(steps), steps=max(steps), every_lo=min(every),
                every_hi=max(every), n=len(runs), _meta=next(iter(runs.values()))[1])


# Our whole-run runs (without their search) and DualSPHysics' case of the same event.
WHOLE_RUN_DSPH_CASE = {"dambreak-1.04M-cubic": "dp0045_cubic", "dambreak-1.04M-wendland": "dp0045_wendland_half",
                       "dambreak-4.04M-cubic": "dp0028_cubic", "dambreak-4.04M-wendland": "dp0028_wendland_half"}


def dualsphysics_whole_runs(machine):
    """DualSPHysics' whole events that ran (rc 0) in MACHINE/whole-run-dualsphysics/summary-tmax-*.tsv
    (make reference's whole-run-dualsphysics-* items): {case: its summary row, with
    runtime_per_phys_s and bytes_per_particle (the resume's GPU memory over its particles)}."""
    theirs = {}
    for path in sorted((Path(machine) / "whole-run-dualsphysics").glob("summary-tmax-*.tsv")):
        cols, *lines = path.read_text().splitlines()
        cols = cols.split("\t")
        for line in lines:
            row = dict(zip(cols, line.split("\t")))
            if len(row) != len(cols) or row["rc"] != "0":
                continue
            theirs[row["case"]] = {"runtime_per_phys_s": float(row["runtime_per_phys_s"]),
                                   "bytes_per_particle": float(row["gpu_mem_mib"]) * 2**20 / float(row["np"])}
    return theirs


def whole_run_vs_dualsphysics(folder, size="1.04M", tmax="1.0"):
    """Our whole event with Verlet lists against DualSPHysics' on the same GPU, per kernel: its
    "Runtime per physical second" over our seconds per simulated second
    (whole-run/dambreak-SIZE-KERNEL-lists.runs.csv); vs_fastest: DualSPHysics' fastest setting of
    that size over our slowest kernel (issue 25's target). tmax names the event's summary file."""
    theirs = dualsphysics_whole_runs(folder)
    if not (Path(folder) / "whole-run-dualsphysics" / f"summary-tmax-{tmax}.tsv").is_file():
        raise Missing(f"no DualSPHysics summary to {tmax} s in {folder}")
    ours, meta = {}, None
    for kernel in ("cubic", "wendland"):
        case = WHOLE_RUN_DSPH_CASE[f"dambreak-{size}-{kernel}"]
        path = Path(folder) / "whole-run" / f"dambreak-{size}-{kernel}-lists.runs.csv"
        if path.is_file() and case in theirs:
            df, meta = sphplot.read_csv_with_metadata(path)
            ours[kernel] = (float(df.iloc[0]["s_per_sim_s"]), theirs[case]["runtime_per_phys_s"], case)
    if not ours:
        raise Missing(f"no kernel run by both codes in {folder}")
    sized = [t["runtime_per_phys_s"] for c, t in theirs.items() if c in {WHOLE_RUN_DSPH_CASE[f"dambreak-{size}-{k}"]
                                                                          for k in ("cubic", "wendland")}]
    ratios = [t / o for o, t, _ in ours.values()]
    vs_fastest = min(sized) / max(o for o, _, _ in ours.values())
    cases = ", ".join(f"{k} {o:.1f} s against {c} {t:.1f} s: {t / o:.2f}x" for k, (o, t, c) in sorted(ours.items()))
    return dict(lo=min(ratios), hi=max(ratios), vs_fastest=vs_fastest, fastest=min(sized), cases=cases,
                n=len(ours), _meta=meta)


def _spheric2(folder):
    import spheric2
    if not (folder / "spheric2" / "runs.csv").is_file():
        raise Missing(folder)
    dsph = folder / "spheric2-dualsphysics"
    data, _, _, meta = spheric2.table(folder / "spheric2", dsph if dsph.is_dir() else None,
                                      spheric2.read_measured(spheric2.MEASURED))
    return spheric2, data, meta


def spheric2_heights(folder):
    """Per spacing both codes ran: our fastest run against DualSPHysics' on the water heights' RMS."""
    module, data, meta = _spheric2(folder)
    cmp = module.comparisons(data)
    if not cmp:
        raise Missing("no spacing run by both codes")
    cases = "; ".join(f"dp {c['dp']:g}: H RMS {100 * c['ours']['H_rms_mean']:.1f}% in {c['ours']['s_per_sim_s']:.1f} "
                      f"s/sim-s vs {100 * c['dsph']['H_rms_mean']:.1f}% in {c['dsph']['s_per_sim_s']:.1f}" for c in cmp)
    return dict(cases=cases, n=len(cmp), met=sum(c["closer"] and c["faster"] for c in cmp),
                closer=sum(c["closer"] for c in cmp), faster=sum(c["faster"] for c in cmp), _meta=meta)


def spheric2_p1(folder):
    """P1's first impact at our finest spacing against the measured peak: the finest run of
    spheric2/, spheric2-p1-sampling/ and spheric2-p1-finest/ (the impact alone, to 0.55-0.6 s, at
    spacings whose 2 s would not fit a command) where those folders are there."""
    module, data, meta = _spheric2(folder)
    candidates = []
    r = module.finest_p1(data)
    if r is not None:
        candidates.append((r, meta))
    for impact_only in ("spheric2-p1-sampling", "spheric2-p1-finest"):
        sampling = folder / impact_only
        if (sampling / "runs.csv").is_file():
            rows, _, _, sampling_meta = module.our_runs(sampling, module.read_measured(module.MEASURED))
            r = module.finest_p1(module.pd.DataFrame(rows))
            if r is not None:
                candidates.append((r, sampling_meta))
    if not candidates:
        raise Missing("no P1 series")
    r, meta = min(candidates, key=lambda c: (float(c[0]["dp"]), float(c[0]["s_per_sim_s"])))
    return dict(dp=float(r["dp"]), run=r["run"], kpa=float(r["P1_peak_kpa"]), err=100 * float(r["P1_peak_err"]),
                dt=float(r["P1_peak_dt_ms"]), _meta=meta)


METRICS = {f.__name__: f for f in (cll_vs_vl, fig3_speedup, fig3_best, fig4_change, balance, speedup, speedup_by_size,
                                   threshold_gain, transports, dualsphysics, skip_bench, whole_run, whole_run_vs_dualsphysics,
                                   spheric2_heights, spheric2_p1)}


# --------------------------------------------------------------------------------------------
# Provenance and staleness


def git(*args, repo=REPO):
    try:
        p = subprocess.run(["git", "-C", str(repo), *args], capture_output=True, text=True)
    except OSError:
        return None
    return p.stdout.strip() if p.returncode == 0 else None


def history(repo=REPO):
    """(last commit that changed solver/, None) or (None, why the history cannot tell)."""
    shallow = git("rev-parse", "--is-shallow-repository", repo=repo)
    if shallow is None:
        return None, "no git history"
    if shallow == "true":
        return None, "shallow clone"
    if git("status", "--porcelain", "--", "solver/", repo=repo):
        return UNCOMMITTED, None  # a change being made: every result is older than it
    last = git("log", "-1", "--format=%H", "--", "solver/", repo=repo)
    return (last, None) if last else (None, "no commit touches solver/")


def freshness(commit, hist, repo=REPO):
    """The 'current?' cell: 'yes', a visible STALE mark, or why it cannot be told."""
    last, why = hist
    if last is None:
        return f"unknown ({why})"
    if last == UNCOMMITTED:
        return STALE
    full = git("rev-parse", "--verify", "--quiet", f"{commit}^{{commit}}", repo=repo) if commit else None
    if not full:
        return "unknown (commit not in history)"
    if git("merge-base", "--is-ancestor", last, full, repo=repo) is not None:
        return "yes"
    return STALE


def recorded(folder, item):
    """For results without CSV provenance: the commit that `make reference` recorded for the item
    (reference-state.json of the machine's folder)."""
    import json
    if not item:
        return None
    try:
        s = json.loads((folder / "reference-state.json").read_text())["items"][item]
    except (OSError, ValueError, KeyError):
        return None
    return {"git_commit": s.get("commit", "unknown"), "git_dirty": s.get("dirty", "unknown")}


def gpu_of(folder, meta):
    if meta:
        text = (meta.get("devices") or meta.get("cuda") or "").split(" | ")[0]
        names = [n.strip() for n in text.split(";") if n.strip()]
        if names and names[0] not in ("host", "none"):
            return names[0] if len(names) == 1 else f"{len(names)} x {names[0]}"
    gpu = next((d / "gpu.txt" for d in [folder, *folder.parents] if (d / "gpu.txt").is_file()), None)
    if gpu is not None:
        rows = [ln.split(",")[0].strip() for ln in gpu.read_text().splitlines()[1:] if ln.strip()]
        if rows:
            return rows[0] if len(rows) == 1 else f"{len(rows)} x {rows[0]}"
    return "unknown"


# --------------------------------------------------------------------------------------------
# The table


def load_spec(path=SPEC):
    spec = tomllib.loads(Path(path).read_text())
    for c in spec["claim"]:
        for key in ("id", "where", "paper", "results", "metric", "shown", "rule"):
            if key not in c:
                raise SystemExit(f"claims: {path}: claim {c.get('id', '?')} lacks '{key}'.")
        if c["metric"] not in METRICS:
            raise SystemExit(f"claims: {path}: claim {c['id']}: no metric '{c['metric']}' in plots/claims.py.")
        for r in c["rule"]:
            if r.get("verdict") not in VERDICTS:
                raise SystemExit(f"claims: {path}: claim {c['id']}: verdict '{r.get('verdict')}' is not one of {VERDICTS}.")
    return spec["claim"]


def judge(claim, values):
    env = {k: v for k, v in values.items() if not k.startswith("_")}
    for r in claim["rule"]:
        if eval(r["when"], {"__builtins__": {}, "min": min, "max": max, "abs": abs, "True": True}, env):  # noqa: S307
            return r["verdict"], r["why"].format(**env)
    raise SystemExit(f"claims: claim {claim['id']}: no rule matched {env}.")


def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def current_first(rows):
    """Of one claim's rows, one folder each in the claim's order: the first whose result is current,
    or the first when none is (a stale H200 result must not hide a current one of another GPU)."""
    return next((r for r in rows if r[5] == "yes"), rows[0])


def rows_of(claim, reference, hist):
    rows = []
    for src in claim["results"]:
        src = {"path": src} if isinstance(src, str) else src
        folder = reference / src["path"]
        try:
            values = METRICS[claim["metric"]](folder, **claim.get("args", {}))
        except (Missing, sphplot.ResultsError):
            continue
        meta = values.get("_meta") or recorded(folder, values.get("_item")) or {}
        commit = src.get("commit") or meta.get("git_commit", "unknown")
        dirty = " (dirty)" if meta.get("git_dirty") == "dirty" else ""
        gpu = src.get("gpu") or values.get("_gpu") or gpu_of(folder, values.get("_meta"))
        verdict, why = judge(claim, values)
        shown = claim["shown"].format(**{k: v for k, v in values.items() if not k.startswith("_")})
        rows.append([claim["where"], claim["paper"], shown, f"{gpu}, `results/reference/{src['path']}`",
                     f"{commit[:7]}{dirty}", freshness(commit, hist), f"**{verdict}**", why])
        if not claim.get("all_results") and rows[-1][5] == "yes":
            break  # the row current_first() takes: the folders after it need not be read
    if rows and not claim.get("all_results"):
        rows = [current_first(rows)]
    if not rows:
        rows.append([claim["where"], claim["paper"], "no result yet", "-", "-", "-", "-",
                     "none of " + ", ".join(s if isinstance(s, str) else s["path"] for s in claim["results"])])
    return rows


def table(reference=REFERENCE, spec=SPEC, repo=REPO):
    hist = history(repo)
    lines = ["| " + " | ".join(HEADER) + " |", "|" + " --- |" * len(HEADER)]
    for claim in load_spec(spec):
        for r in rows_of(claim, reference, hist):
            lines.append("| " + " | ".join(cell(c) for c in r) + " |")
    note = ("Generated by `make claims` (plots/claims.py from plots/claims.toml and results/reference/); "
            "do not edit by hand. _current?_: STALE where solver/ changed after the result's commit.")
    return note + "\n\n" + "\n".join(lines) + "\n", hist


def doc_block(text, name=DOC.name):
    if BEGIN not in text or END not in text:
        raise SystemExit(f"claims: {name} lacks the markers {BEGIN} and {END}.")
    return text.split(BEGIN, 1)[1].split(END, 1)[0].strip("\n") + "\n"


def masked(block):
    """The table with the 'current?' column blanked: what can be compared without git history."""
    out = []
    for line in block.splitlines():
        if line.startswith("| ") and not line.startswith("| where"):
            cells = re.split(r"(?<!\\) \| ", line[2:-2])
            if len(cells) == len(HEADER):
                cells[FRESH_COLUMN] = "?"
                line = "| " + " | ".join(cells) + " |"
        out.append(line)
    return "\n".join(out)


def check(doc, generated, hist, name="docs/results.md"):
    """(ok, message) for the text `doc` of the page `name`."""
    have = doc_block(doc, name)
    if have == generated:
        return True, f"claims: {name}'s table matches the committed results."
    if hist[0] is None and masked(have) == masked(generated):
        return True, (f"claims: {name}'s table matches the committed results; whether they are current "
                      f"is not checked here ({hist[1]}).")
    import difflib
    diff = "\n".join(difflib.unified_diff(have.splitlines(), generated.splitlines(), name, "generated",
                                          lineterm="", n=0))
    return False, (f"claims: {name}'s claims table differs from what plots/claims.py makes of results/reference/; "
                   f"run `make claims` and commit {name}.\n" + diff)


def shown(path):
    """The page's path as a reader names it: relative to the repository where it lies inside."""
    try:
        return str(path.resolve().relative_to(REPO))
    except ValueError:
        return str(path)


def main(argv=None):
    p = argparse.ArgumentParser(prog="claims.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--write", action="store_true", help="write the table into the page (--doc) between the markers")
    p.add_argument("--check", action="store_true", help="exit 1 when the page's table differs")
    p.add_argument("--doc", type=Path, default=DOC, help="the page that holds the table (default: docs/results.md)")
    p.add_argument("--reference", type=Path, default=REFERENCE)
    args = p.parse_args(argv)
    generated, hist = table(args.reference)
    if args.check:
        ok, message = check(args.doc.read_text(), generated, hist, shown(args.doc))
        print(message)
        return 0 if ok else 1
    if args.write:
        text = args.doc.read_text()
        doc_block(text, shown(args.doc))  # the markers must be there
        head, rest = text.split(BEGIN, 1)
        new = head + BEGIN + "\n" + generated + END + rest.split(END, 1)[1]
        if new != text:
            args.doc.write_text(new)
            print(f"claims: wrote the table into {shown(args.doc)}")
        else:
            print(f"claims: {shown(args.doc)} is up to date")
        return 0
    sys.stdout.write(generated)
    return 0


if __name__ == "__main__":
    sys.exit(main())
