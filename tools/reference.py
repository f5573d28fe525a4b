#!/usr/bin/env python3
"""`make reference`: every GPU reference result that the GPUs present allow, resumable.

On one GPU: the CUDA tests, the benchmark cases (and DualSPHysics' own run of the same dam
breaks when $DSPH names its anchor folder, ../shared/anchors/dualsphysics), the force-loop and
skip micro-benchmarks, the search calibration, Figures 3 and 4, the CLL/VL table, the accuracy
sweep (with the float64 build) and the stability studies, into results/reference/<gpu>/. On
N >= 2 GPUs also Figures 5 to 9 (the multi-gpu experiment on 1, 2, ... N GPUs: the scaling runs)
and Figure 10, into results/reference/<gpu>-xN/. <gpu> is the first GPU's name from nvidia-smi
("NVIDIA H200" -> h200). Each folder gets its figures (figures/), the harness's provenance in
every CSV, and reference-state.json / reference-runs.md: what ran, with which binaries, when,
from which commit, in how many seconds.

It prints its plan and an estimate first. What is up to date is not run again: a `sphbench run`
or `sphbench stability` item is handed to the harness without --force, so the harness's own
freshness check (spec, binary, options, backend) decides; every item also has a stamp in
reference-state.json (the sha256 of its binaries, inputs and command), which is how the plan
knows beforehand, and how items that are not `sphbench run` (benchmarks, tests) are skipped.
A lease of a GPU machine is 10 minutes a command: REFERENCE_BUDGET_S=500 (or --budget) starts
no item whose estimate no longer fits in what is left (later, smaller ones still run; the
figures, about 30 s, are drawn at the end of every call outside the budget), and the next call
resumes. The state is written after every item, and, when $OUT is set (the run tool's
folder of files that come back) or --archive names a file, what this call wrote under
results/reference/<gpu>[-xN]/ is packed into one archive after every item (split in parts of
15 MiB where it is larger), so that a command stopped at its limit still brings back what it
finished. Unpack each call's archive here before the next call: the next call's tree replaces
the machine's results/reference/.

Needs only Python 3's standard library; the figures need numpy, pandas and matplotlib, and are
left for `make reference-figures` (here, after the results come back) where those are missing.
Binaries are taken from PATH (tools/gpu-run.sh exec puts .carry/bin there), else build/ and
build-f64/.

  tools/reference.py [--dry-run] [--budget S] [--only ITEM ...] [--skip ITEM ...] [--list]
  tools/reference.py --figures-only [--machine DIR ...]     draw the figures of committed results
  tools/reference.py --pack-dsph [SRC [DEST]]              DualSPHysics' anchor, recompressed, into .dsph/
Environment: PLAN=1 (= --dry-run), REFERENCE_BUDGET_S, REFERENCE_ONLY, REFERENCE_SKIP (items,
space or comma separated), REFERENCE_ARCHIVE, DSPH (DualSPHysics' anchor folder), REFERENCE_GPUS
and REFERENCE_GPU_NAME (what a dry run without a GPU plans for; default 1 x h200).
"""
import argparse
import datetime
import hashlib
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
STATE_NAME = "reference-state.json"
LOG_NAME = "reference-runs.md"

# The force loop's benchmark cases (issue 12), each `sphbench simulate` for 300 steps after 20;
# the first four are DualSPHysics' own dam break at its two resolutions and two cell sizes.
BENCHMARK_CASES = [
    "dsph-dambreak",
    "dsph-dambreak --set kernel=wendland --cells-per-support 2",
    "dsph-dambreak --set dp=0.0028",
    "dsph-dambreak --set dp=0.0028 --set kernel=wendland --cells-per-support 2",
    "dsph-dambreak --merge",
    "dsph-dambreak --set kernel=wendland --cells-per-support 2 --merge",
    "dsph-dambreak --set dp=0.0028 --merge",
    "dsph-dambreak --set dp=0.0028 --set kernel=wendland --cells-per-support 2 --merge",
    "armadillo --set particles=2980000",
    "armadillo --set particles=2980000 --merge --cells-per-support 2",
    # Verlet lists on half-size cells with a skin of 0.05 supports: the fastest setting measured
    # (docs/force-loop-notes.md, change 8); the claims table compares them with DualSPHysics too.
    "dsph-dambreak --verlet --cells-per-support 2 --skin 0.05",
    "dsph-dambreak --set kernel=wendland --verlet --cells-per-support 2 --skin 0.05",
    "dsph-dambreak --set dp=0.0028 --verlet --cells-per-support 2 --skin 0.05",
    "dsph-dambreak --set dp=0.0028 --set kernel=wendland --verlet --cells-per-support 2 --skin 0.05",
    "armadillo --set particles=2980000 --verlet --cells-per-support 2 --skin 0.05",
]
CALIBRATION_CASES = ["armadillo --set particles=2980000", "bunny --set particles=3049000", "dsph-dambreak"]
CUDA_TEST_FILTER = "*Forces.*:CudaBackend.*:*CudaTransports*:*CudaVariants*:*StencilFluidCells*"
STABILITY_STUDIES = ["stability-cfl", "stability-still-water", "stability-impact", "stability-armadillo"]


class Item:
    """One unit of the plan: it runs whole or not at all, and is up to date as a whole.

    scope: "single" (one GPU, into <gpu>/) or "multi" (every GPU, into <gpu>-xN/).
    estimate: seconds on an H200, from the committed results' wall_s plus the scenes' building;
    a measured time in the state file replaces it. bins: the programs it runs (their bytes are
    part of its stamp). inputs: files whose bytes are part of its stamp. outputs: what must exist
    afterwards (relative to the machine's folder) for it to count as done.
    """

    def __init__(self, name, what, scope, estimate, bins, run, inputs=(), outputs=(), needs=None):
        self.name, self.what, self.scope, self.estimate = name, what, scope, estimate
        self.bins, self.run, self.inputs, self.outputs, self.needs = list(bins), run, list(inputs), list(outputs), needs


# --------------------------------------------------------------------------------------------
# Running things


class Context:
    def __init__(self, args, tools, gpus):
        self.args, self.tools, self.gpus = args, tools, gpus
        self.log_lines = []
        self.harness_skipped = False  # sphbench said "up to date" (its own freshness check)

    def sh(self, argv, log=None, cwd=REPO, check=True, env=None):
        """Runs argv, echoing its output (and appending it to `log`); returns the exit code."""
        shown = " ".join(shlex.quote(shown_arg(a, i)) for i, a in enumerate(argv))
        print(f"  $ {shown}", flush=True)
        self.log_lines.append(shown)
        out = open(log, "a", encoding="utf-8") if log else None
        try:
            if out:
                out.write(f"== {shown}\n")
                out.flush()
            p = subprocess.Popen([str(a) for a in argv], cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                 text=True, errors="replace", env=env)
            for line in p.stdout:
                sys.stdout.write("    " + line)
                if ": up to date (use --force" in line:
                    self.harness_skipped = True
                if out:
                    out.write(line)
            sys.stdout.flush()
            rc = p.wait()
        finally:
            if out:
                out.close()
        if check and rc != 0:
            raise ItemFailed(f"{Path(str(argv[0])).name} exited with {rc}")
        return rc


class ItemFailed(Exception):
    pass


def shown_arg(a, i):
    """A program by its name, a path inside the repository relative to it: the log reads the same
    on every machine."""
    a = str(a)
    if i == 0 and "/" in a:
        return Path(a).name
    if a.startswith(str(REPO) + "/"):
        return os.path.relpath(a, REPO)
    return a


def tool(ctx, name):
    return ctx.tools[name]


def run_cuda_tests(ctx, d):
    log = d / "cuda_tests.log"
    log.unlink(missing_ok=True)
    rc = ctx.sh([tool(ctx, "sph_tests"), f"--gtest_filter={CUDA_TEST_FILTER}"], log=log, check=False)
    lines = [ln for ln in log.read_text(errors="replace").splitlines()
             if re.search(r"cuda |forces against|OK \]|FAILED|PASSED", ln)]
    (d / "cuda_tests.txt").write_text("\n".join(lines) + "\n")
    if rc != 0:
        raise ItemFailed("the CUDA tests failed (cuda_tests.log)")


def run_benchmarks(ctx, d):
    out = d / "benchmarks"
    scratch = out / "scratch"
    shutil.rmtree(out, ignore_errors=True)
    scratch.mkdir(parents=True)
    log = out / "benchmarks.txt"
    for case in BENCHMARK_CASES:
        ctx.sh([tool(ctx, "sphbench"), "simulate", *case.split(), "--steps", "300", "--warmup", "20",
                "--backend", "cuda", "--quiet", "--out", scratch], log=log)
        scene = case.split()[0]  # the step file is named after the scene: keep one per case
        shutil.move(scratch / f"{scene}_steps.csv", out / (re.sub(r"[ =]", "_", case) + "_steps.csv"))
    shutil.rmtree(scratch)


def pack_dualsphysics(src, dest):
    """A copy of DualSPHysics' anchor folder with its .gz files recompressed as .xz (37 MB -> about
    16 MB), so that it travels with the working tree within the run tool's 64 MiB."""
    import gzip
    import lzma
    src, dest = Path(src), Path(dest)
    if not (src / "run.sh").is_file():
        print(f"reference: {src} holds no run.sh, so it is not DualSPHysics' anchor folder.", file=sys.stderr)
        return 2
    shutil.rmtree(dest, ignore_errors=True)
    shutil.copytree(src, dest)
    for f in [dest, *dest.rglob("*")]:
        f.chmod(f.stat().st_mode | 0o200)  # the shared copy is read-only
    for gz in sorted(dest.rglob("*.gz")):
        with gzip.open(gz, "rb") as i, lzma.open(gz.with_suffix(".xz"), "wb", preset=6) as o:
            shutil.copyfileobj(i, o, 1 << 20)
        gz.unlink()
        print(f"  {gz.relative_to(dest)} -> {gz.with_suffix('.xz').name}", flush=True)
    print(f"reference: {dest} ready; carry it and set DSPH=$PWD/{os.path.relpath(dest, REPO)} on the GPU machine")
    return 0


def unpack_xz(anchor):
    """What pack_dualsphysics packed, unpacked where DualSPHysics' run.sh looks (an executable
    beside it, CaseDambreak.bi4 in a case folder)."""
    import lzma
    for xz in sorted(anchor.rglob("*.xz")):
        target = xz.with_suffix("")
        if target.exists() or (target.with_suffix(target.suffix + ".gz")).exists():
            continue
        with lzma.open(xz, "rb") as i, open(target, "wb") as o:
            shutil.copyfileobj(i, o, 1 << 20)
        if target.name.startswith("DualSPHysics"):
            target.chmod(0o755)


def run_dualsphysics(ctx, d):
    anchor = Path(os.environ["DSPH"])
    unpack_xz(anchor)
    work = Path(tempfile.mkdtemp(prefix="dsph-logs-"))
    try:
        ctx.sh(["bash", anchor / "run.sh", work], log=None)
        out = d / "dualsphysics"
        shutil.rmtree(out, ignore_errors=True)
        out.mkdir(parents=True)
        for name in ("summary.txt", "summary.tsv", "env.txt"):
            if (work / name).is_file():
                shutil.copy(work / name, out / name)
        for f in work.glob("*.Run.out"):  # DualSPHysics' own report of each case
            shutil.copy(f, out / f.name)
    finally:
        shutil.rmtree(work, ignore_errors=True)


SPHERIC2_SPACINGS = ("0.02", "0.01", "0.0075")  # experiments/spheric2.toml's
# Simulated seconds per spacing: to 6 s where it fits in a lease, as experiments/spheric2.toml's runs.
SPHERIC2_END_S = {"0.02": "6.0", "0.01": "6.0", "0.0075": "2.0"}


def run_spheric2(ctx, d):
    ctx.sh([tool(ctx, "sphbench"), "run", "experiments/spheric2.toml", "--backend", "cuda", "--float64-binary",
            tool(ctx, "sphbench-f64"), "--out", d, "--quiet"], log=d / "spheric2.log")


def run_spheric2_dualsphysics(ctx, d):
    """DualSPHysics on SPHERIC Test 2 at our spacings, to SPHERIC2_END_S (its spheric2/make_case.sh, GenCase on
    the CPU): run time per simulated second and the water heights of its gauges at H1-H4."""
    anchor = Path(os.environ["DSPH"])
    unpack_xz(anchor)
    work = Path(tempfile.mkdtemp(prefix="dsph-spheric2-"))
    try:
        # make_case.sh unpacks GenCase from gencase/GenCase_linux64.gz into $TMPDIR/gencase_v5.0.232
        # unless it is there; a packed anchor (.xz, unpacked above) has no .gz: put it there.
        gencase = anchor / "gencase" / "GenCase_linux64"
        if gencase.is_file():
            target = work / "gencase_v5.0.232" / "GenCase_linux64"
            target.parent.mkdir(parents=True)
            shutil.copy(gencase, target)
            target.chmod(0o755)
        cases = work / "cases"
        for dp in SPHERIC2_SPACINGS:
            ctx.sh(["bash", anchor / "spheric2" / "make_case.sh", dp, SPHERIC2_END_S[dp], cases / f"dp{dp}"], log=None,
                   env=dict(os.environ, TMPDIR=str(work)))
        logs = work / "logs"
        env = dict(os.environ, DSPH_CASES=str(cases), DSPH_WORK=str(work / "scratch"))
        ctx.sh(["bash", anchor / "run.sh", logs, *[f"dp{dp}" for dp in SPHERIC2_SPACINGS]], log=None, env=env)
        out = d / "spheric2-dualsphysics"
        shutil.rmtree(out, ignore_errors=True)
        out.mkdir(parents=True)
        for f in logs.iterdir():
            if f.name in ("summary.txt", "summary.tsv", "env.txt") or f.name.endswith((".Run.out", ".csv")):
                shutil.copy(f, out / f.name)
    finally:
        shutil.rmtree(work, ignore_errors=True)


# DualSPHysics' dam breaks over the whole events of experiments/whole-run.toml, one item an event:
# both events together (~450 s on an H200) do not fit one command of 10 minutes on an H100.
# name: (simulated seconds, its cases, estimate in seconds on an H200)
WHOLE_RUN_DSPH = {"whole-run-dualsphysics-1.04M": ("1.0", ["dp0045_cubic", "dp0045_wendland_half"], 220),
                  "whole-run-dualsphysics-4.04M": ("0.3", ["dp0028_cubic", "dp0028_wendland_half"], 330)}


def needs_dsph(*path):
    """An item's `needs`: DualSPHysics' anchor folder ($DSPH) with the file its runs start from."""
    def needs(_tools):
        if os.environ.get("DSPH") and Path(os.environ["DSPH"], *path).is_file():
            return None
        return f"DSPH (DualSPHysics' anchor folder with {'/'.join(path)}) is not set"
    return needs


def run_whole_run_dualsphysics(tmax, cases):
    """DualSPHysics' CASES to TMAX simulated seconds: its "Runtime per physical second" beside
    ours from the same lease, into whole-run-dualsphysics/ (summary-tmax-TMAX.tsv, the Run.out's)."""
    def run(ctx, d):
        anchor = Path(os.environ["DSPH"])
        unpack_xz(anchor)
        work = Path(tempfile.mkdtemp(prefix="dsph-whole-run-"))
        try:
            out = d / "whole-run-dualsphysics"
            out.mkdir(parents=True, exist_ok=True)
            for c in cases:
                (out / f"{c}.Run.out").unlink(missing_ok=True)
            logs = work / f"tmax-{tmax}"
            env = dict(os.environ, DSPH_EXTRA=f"-tmax:{tmax}", DSPH_WORK=str(work / "scratch"))
            ctx.sh(["bash", anchor / "run.sh", logs, *cases], log=None, env=env)
            shutil.copy(logs / "summary.tsv", out / f"summary-tmax-{tmax}.tsv")
            for f in logs.glob("*.Run.out"):
                shutil.copy(f, out / f.name)
        finally:
            shutil.rmtree(work, ignore_errors=True)
    return run


def run_force_loop_bench(ctx, d):
    ctx.sh([tool(ctx, "sph_bench"), "--benchmark_format=json", f"--benchmark_out={d / 'force_loop_bench.json'}",
            "--benchmark_min_time=0.5"], log=d / "force_loop_bench.txt")


def run_skip_bench(ctx, d):
    ctx.sh([tool(ctx, "sph_skip_bench"), "--benchmark_repetitions=5", "--benchmark_report_aggregates_only=true",
            f"--benchmark_out={d / 'skip_bench.json'}", "--benchmark_out_format=json"], log=d / "skip_bench.txt")


def run_calibration(ctx, d):
    log = d / "calibration.txt"
    log.unlink(missing_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix="calibration-"))
    try:
        for case in CALIBRATION_CASES:
            ctx.sh([tool(ctx, "sphbench"), "simulate", *case.split(), "--auto-search", "--steps", "100", "--warmup", "10",
                    "--backend", "cuda", "--quiet", "--out", scratch], log=log)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def sphbench_run(spec, extra=None):
    def run(ctx, d):
        ctx.sh([tool(ctx, "sphbench"), "run", f"experiments/{spec}.toml", "--backend", "cuda", "--out", d, "--quiet",
                *(extra(ctx) if extra else [])], log=d / f"{spec}.log")
    return run


# experiments/whole-run.toml's runs in groups that each fit one command of 10 minutes (all nine
# took 579 s on an H200 at 674606d): one item a group, one `sphbench run --only` a run.
WHOLE_RUN_GROUPS = {
    # Each size in two items, the lists (beside DualSPHysics' event of that size, whole-run-dualsphysics-*,
    # they fit one command) and the cell search with the armadillo. name: (runs, estimate in seconds
    # on an H200).
    "whole-run-1.04M": (["dambreak-1.04M-wendland-lists", "dambreak-1.04M-cubic-lists"], 95),
    "whole-run-1.04M-cells": (["dambreak-1.04M-wendland-cells", "dambreak-1.04M-cubic-cells", "armadillo-2980K-lists",
                               "armadillo-2980K-cells"], 200),
    "whole-run-4.04M": (["dambreak-4.04M-wendland-lists", "dambreak-4.04M-cubic-lists"], 180),
    "whole-run-4.04M-cells": (["dambreak-4.04M-wendland-cells", "dambreak-4.04M-cubic-cells"], 250),
}


def run_whole_run(run_ids):
    """Each run into whole-run/ as the tables read it: RUN.runs.csv (its runs.csv), RUN.txt (what it
    printed), and for a dam break its rows of windows.csv (bench/lease/step_windows.py over its steps
    CSV, which is not kept: 7 MB a run)."""
    def run(ctx, d):
        out = d / "whole-run"
        out.mkdir(exist_ok=True)
        for rid in run_ids:
            work = Path(tempfile.mkdtemp(prefix="whole-run-"))
            try:
                (out / f"{rid}.txt").unlink(missing_ok=True)
                ctx.sh([tool(ctx, "sphbench"), "run", "experiments/whole-run.toml", "--backend", "cuda", "--only", rid,
                        "--out", work], log=out / f"{rid}.txt")
                shutil.copy(work / "whole-run" / "runs.csv", out / f"{rid}.runs.csv")
                steps = work / "whole-run" / f"{rid}_steps.csv"
                if rid.startswith("dambreak") and steps.is_file():
                    merge_windows(out / "windows.csv", rid, steps)
            finally:
                shutil.rmtree(work, ignore_errors=True)
    return run


def merge_windows(path, rid, steps):
    """windows.csv with run rid's rows replaced by those of its steps CSV."""
    p = subprocess.run([sys.executable, str(REPO / "bench" / "lease" / "step_windows.py"), f"{rid}={steps}"],
                       capture_output=True, text=True)
    if p.returncode != 0:  # step_windows.py needs pandas, which a GPU machine may lack
        last = (p.stderr.strip().splitlines() or ["no output"])[-1]
        print(f"reference: windows.csv keeps no rows of {rid}: step_windows.py failed ({last})")
        return
    header, *rows = p.stdout.strip().splitlines()
    kept = []
    if path.is_file():
        old = path.read_text().strip().splitlines()
        kept = [r for r in old[1:] if not r.startswith(f"{rid},")]
    path.write_text("\n".join([header, *kept, *rows]) + "\n")


def run_accuracy(ctx, d):
    ctx.sh([tool(ctx, "sphbench"), "run", "experiments/accuracy.toml", "--backend", "cuda", "--float64-binary",
            tool(ctx, "sphbench-f64"), "--out", d, "--quiet"], log=d / "accuracy.log")


def sphbench_stability(study):
    def run(ctx, d):
        (d / "stability").mkdir(exist_ok=True)
        ctx.sh([tool(ctx, "sphbench"), "stability", f"experiments/{study}.toml", "--backend", "cuda",
                "--out", d / "stability", "--quiet"], log=d / "stability" / f"{study}.log")
    return run


def multi_gpu_only(ctx):
    """--only for the multi-gpu runs on at most as many subdomains as there are GPUs (a run of 4
    subdomains on 2 GPUs shares them and gives no speedup)."""
    ids = spec_run_ids(ctx, "multi-gpu")
    keep = [i for i in ids if int(re.search(r"devices-(\d+)", i).group(1)) <= ctx.gpus]
    if len(keep) == len(ids):
        return []
    return [a for i in keep for a in ("--only", i)]


def spec_run_ids(ctx, spec):
    p = subprocess.run([str(tool(ctx, "sphbench")), "run", f"experiments/{spec}.toml", "--backend", "cuda", "--dry-run"],
                       cwd=REPO, capture_output=True, text=True)
    ids = [ln.split()[0] for ln in p.stdout.splitlines() if re.match(r"\S+_devices-\d+\s", ln)]
    if p.returncode != 0 or not ids:
        raise ItemFailed(f"`sphbench run experiments/{spec}.toml --dry-run` listed no runs: {p.stderr.strip()}")
    return ids


FIGURES_SINGLE = [  # (script, results folder under the machine's, what it needs there)
    ("fig3.py", "fig3", "fig3/runs.csv"),
    ("fig4.py", "fig4", "fig4/runs.csv"),
    ("table_vl.py", "cll-vs-vl", "cll-vs-vl/runs.csv"),
    ("accuracy.py", "accuracy", "accuracy/runs.csv"),
    ("spheric2.py", "spheric2", "spheric2/runs.csv"),
    ("stability.py", "stability", [f"stability/{s}/summary.csv" for s in STABILITY_STUDIES]),  # all four
]
FIGURES_MULTI = [("fig5.py", "multi-gpu", "multi-gpu/runs.csv"), ("fig6.py", "multi-gpu", "multi-gpu/runs.csv"),
                 ("fig7.py", "multi-gpu", "multi-gpu/runs.csv"), ("fig8.py", "multi-gpu", "multi-gpu/runs.csv"),
                 ("fig9.py", "multi-gpu", "multi-gpu/runs.csv"), ("fig10.py", "fig10", "fig10/runs.csv")]


def plotting_available():
    try:
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
        import pandas  # noqa: F401
    except ImportError as e:
        return str(e)
    return None


def draw_figures(ctx, d, scope):
    missing = plotting_available()
    if missing:
        print(f"  figures not drawn here ({missing}): run `make reference-figures` where matplotlib is", flush=True)
        return "not drawn"
    drawn, failed = 0, []
    for script, results, needs in FIGURES_SINGLE if scope == "single" else FIGURES_MULTI:
        if not all((d / n).exists() for n in ([needs] if isinstance(needs, str) else needs)):
            continue
        rc = ctx.sh([sys.executable, REPO / "plots" / script, "--results", d / results, "--out", d / "figures"],
                    log=d / "figures.log", check=False)
        drawn += rc == 0
        failed += [script] if rc else []
    if failed:
        raise ItemFailed(f"{drawn} figures drawn; {', '.join(failed)} failed (figures.log)")
    return f"{drawn} figures"


# --------------------------------------------------------------------------------------------
# The plan


def items(gpus=1):
    single = [
        Item("cuda-tests", "CUDA backend against the host, forces against float64 (sph_tests)", "single", 90,
             ["sph_tests"], run_cuda_tests, outputs=["cuda_tests.txt"]),
        Item("benchmarks", f"{len(BENCHMARK_CASES)} benchmark cases, sphbench simulate 300 steps", "single", 120,
             ["sphbench"], run_benchmarks, outputs=["benchmarks/benchmarks.txt"]),
        # sphbench is part of its stamp though it does not run it: DualSPHysics reruns beside every
        # new build of ours, so that the comparison is always of one lease (issue 12).
        Item("dualsphysics", "DualSPHysics v5.4 on the same dam breaks ($DSPH/run.sh)", "single", 90, ["sphbench"],
             run_dualsphysics, outputs=["dualsphysics/summary.txt"],
             needs=needs_dsph("run.sh")),
        Item("force-loop-bench", "force loop per search strategy (sph_bench)", "single", 60, ["sph_bench"],
             run_force_loop_bench, outputs=["force_loop_bench.json"]),
        Item("skip-bench", "what skipping unneeded work saves (sph_skip_bench)", "single", 60, ["sph_skip_bench"],
             run_skip_bench, outputs=["skip_bench.json"]),
        Item("calibration", "search calibration (--auto-search) on three scenes", "single", 75, ["sphbench"],
             run_calibration, outputs=["calibration.txt"]),
        Item("fig4", "Figure 4 (experiments/fig4.toml)", "single", 50, ["sphbench"], sphbench_run("fig4"),
             inputs=["experiments/fig4.toml"], outputs=["fig4/runs.csv"]),
        Item("fig3", "Figure 3 (experiments/fig3.toml)", "single", 200, ["sphbench"], sphbench_run("fig3"),
             inputs=["experiments/fig3.toml"], outputs=["fig3/runs.csv"]),
        Item("cll-vs-vl", "CLL against Verlet lists, section 4.1 (experiments/cll-vs-vl.toml)", "single", 40,
             ["sphbench"], sphbench_run("cll-vs-vl"), inputs=["experiments/cll-vs-vl.toml"],
             outputs=["cll-vs-vl/runs.csv"]),
        Item("accuracy", "accuracy against run time (experiments/accuracy.toml, float64 build too)", "single", 190,
             ["sphbench", "sphbench-f64"], run_accuracy, inputs=["experiments/accuracy.toml"],
             outputs=["accuracy/runs.csv"]),
        *[Item(group, f"whole events of experiments/whole-run.toml: {', '.join(ids)}", "single",
               estimate, ["sphbench"], run_whole_run(ids),
               inputs=["experiments/whole-run.toml"], outputs=[f"whole-run/{i}.runs.csv" for i in ids])
          for group, (ids, estimate) in WHOLE_RUN_GROUPS.items()],
        *[Item(name, f"DualSPHysics v5.4 on the dam break {name.rsplit('-', 1)[1]}'s whole event (0 to {tmax} s)",
               "single", estimate, ["sphbench"],
               run_whole_run_dualsphysics(tmax, cases), outputs=[f"whole-run-dualsphysics/summary-tmax-{tmax}.tsv"],
               needs=needs_dsph("run.sh"))
          for name, (tmax, cases, estimate) in WHOLE_RUN_DSPH.items()],
        Item("spheric2", "SPHERIC Test 2 at three spacings, to 6 s at dp 0.02 and 0.01 (experiments/spheric2.toml, "
             "float64 build too)", "single", 420, ["sphbench", "sphbench-f64"], run_spheric2,
             inputs=["experiments/spheric2.toml", "experiments/cases/spheric-test2.toml"],
             outputs=["spheric2/runs.csv"]),
        Item("spheric2-p1-sampling", "SPHERIC Test 2's first impact on P1-P4 sampled at every step, four spacings "
             "to 0.6 s (experiments/spheric2-p1-sampling.toml)", "single", 300, ["sphbench"],
             sphbench_run("spheric2-p1-sampling"),
             inputs=["experiments/spheric2-p1-sampling.toml", "experiments/cases/spheric-test2.toml"],
             outputs=["spheric2-p1-sampling/runs.csv"]),
        Item("spheric2-p1-finest", "SPHERIC Test 2's first impact on P1-P4 at dp 0.004 (11.5M particles) to 0.55 s "
             "(experiments/spheric2-p1-finest.toml)", "single", 450, ["sphbench"], sphbench_run("spheric2-p1-finest"),
             inputs=["experiments/spheric2-p1-finest.toml", "experiments/cases/spheric-test2.toml"],
             outputs=["spheric2-p1-finest/runs.csv"]),
        Item("spheric2-p1-diffusion-walls", "SPHERIC Test 2's first impact on P1-P4 at dp 0.004 with DensityDT 3 "
             "to 0.55 s (experiments/spheric2-p1-diffusion-walls.toml)", "single", 470, ["sphbench"],
             sphbench_run("spheric2-p1-diffusion-walls"),
             inputs=["experiments/spheric2-p1-diffusion-walls.toml", "experiments/cases/spheric-test2.toml"],
             outputs=["spheric2-p1-diffusion-walls/runs.csv"]),
        Item("spheric2-diffusion-walls", "SPHERIC Test 2 to 2 s at dp 0.02 and 0.01 with DualSPHysics' DensityDT 2 "
             "and 3 (experiments/spheric2-diffusion-walls.toml)", "single", 110, ["sphbench"],
             sphbench_run("spheric2-diffusion-walls"),
             inputs=["experiments/spheric2-diffusion-walls.toml", "experiments/cases/spheric-test2.toml"],
             outputs=["spheric2-diffusion-walls/runs.csv"]),
        # sphbench in its stamp, as the dam breaks': DualSPHysics reruns beside every new build of ours.
        Item("spheric2-dualsphysics", "DualSPHysics v5.4 on SPHERIC Test 2 at the same spacings, to 6 s at dp 0.02 "
             "and 0.01, 2 s at 0.0075", "single", 420, ["sphbench"], run_spheric2_dualsphysics,
             outputs=["spheric2-dualsphysics/summary.tsv"],
             needs=needs_dsph("spheric2", "make_case.sh")),
    ]
    estimates = {"stability-cfl": 45, "stability-still-water": 75, "stability-impact": 45, "stability-armadillo": 210}
    for s in STABILITY_STUDIES:
        single.append(Item(s, f"stability study (experiments/{s}.toml)", "single", estimates[s], ["sphbench"],
                           sphbench_stability(s), inputs=[f"experiments/{s}.toml"],
                           outputs=[f"stability/{s}/summary.csv"]))
    multi = [
        Item("multi-gpu", "Figures 5-9 and the scaling runs: experiments/multi-gpu.toml on 1..N GPUs", "multi",
             240 if gpus <= 2 else 340,
             ["sphbench"], sphbench_run("multi-gpu", multi_gpu_only), inputs=["experiments/multi-gpu.toml"],
             outputs=["multi-gpu/runs.csv"]),
        Item("fig10", "Figure 10, the step per transport on 1 and 2 GPUs (experiments/fig10.toml)", "multi", 150,
             ["sphbench"], sphbench_run("fig10"), inputs=["experiments/fig10.toml"], outputs=["fig10/runs.csv"]),
    ]
    figures = [
        Item("figures", "the figures of results/reference/<gpu>/", "single", 40, [],
             lambda ctx, d: draw_figures(ctx, d, "single"), outputs=[]),
        Item("figures-multi", "the figures of results/reference/<gpu>-xN/", "multi", 30, [],
             lambda ctx, d: draw_figures(ctx, d, "multi"), outputs=[]),
    ]
    return single + multi + figures


# --------------------------------------------------------------------------------------------
# Machines, binaries, state


def gpu_short_name(name):
    """'NVIDIA H200' -> 'h200', 'NVIDIA H100 80GB HBM3' -> 'h100', 'NVIDIA A100-SXM4-80GB' -> 'a100'."""
    words = [w for w in re.split(r"\s+", name.strip()) if w and w.lower() not in ("nvidia", "tesla", "geforce")]
    first = words[0] if words else "gpu"
    return re.sub(r"[^a-z0-9]", "", first.split("-")[0].lower()) or "gpu"


def detect_gpus():
    """([(name, driver, memory)], None) from nvidia-smi, or ([], why not)."""
    smi = shutil.which("nvidia-smi")
    if not smi:
        return [], "nvidia-smi is not on PATH"
    p = subprocess.run([smi, "--query-gpu=name,driver_version,memory.total", "--format=csv,noheader"],
                       capture_output=True, text=True)
    rows = [[c.strip() for c in ln.split(",")] for ln in p.stdout.splitlines() if ln.strip()]
    if p.returncode != 0 or not rows:
        return [], f"nvidia-smi lists no GPU ({(p.stderr or p.stdout).strip() or 'exit ' + str(p.returncode)})"
    return rows, None


def machine_dirs(root, short, n):
    """{'single': <root>/<gpu>, 'multi': <root>/<gpu>-xN or None}."""
    return {"single": root / short, "multi": root / f"{short}-x{n}" if n > 1 else None}


TOOL_FALLBACKS = {"sphbench": "build/harness/sphbench", "sph_tests": "build/tests/sph_tests",
                  "sph_bench": "build/bench/sph_bench", "sph_skip_bench": "build/bench/sph_skip_bench",
                  "sphbench-f64": "build-f64/harness/sphbench"}


def find_tools():
    found = {}
    for name, fallback in TOOL_FALLBACKS.items():
        p = shutil.which(name)
        if p is None and os.access(REPO / fallback, os.X_OK):
            p = str(REPO / fallback)
        found[name] = Path(p) if p else None
    return found


_digests = {}


def digest(path):
    path = Path(path)
    if path not in _digests:
        h = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        _digests[path] = h.hexdigest()
    return _digests[path]


def stamp(item, tools, gpus):
    h = hashlib.sha256(f"{item.name}\n{item.what}\n{gpus if item.scope == 'multi' else 1}\n".encode())
    for b in item.bins:
        h.update(f"{b}={digest(tools[b])}\n".encode())
    for f in item.inputs:
        h.update(f"{f}={digest(REPO / f)}\n".encode())
    if item.name == "benchmarks":
        h.update("\n".join(BENCHMARK_CASES).encode())
    if item.name in ("dualsphysics", "spheric2-dualsphysics", *WHOLE_RUN_DSPH):
        h.update(digest(Path(os.environ["DSPH"]) / "run.sh").encode())
    if item.name == "spheric2-dualsphysics":
        h.update(digest(Path(os.environ["DSPH"]) / "spheric2" / "make_case.sh").encode())
        h.update(digest(Path(os.environ["DSPH"]) / "spheric2" / "SphericTest2_Def.xml.in").encode())
    if item.name.startswith("figures"):
        for f in sorted((REPO / "plots").glob("*.py")):
            h.update(f"{f.name}={digest(f)}\n".encode())
    return h.hexdigest()[:16]


def inputs_digest(item):
    """What the item runs (its specs): a run of other specs says nothing of this one's time."""
    h = hashlib.sha256()
    for f in item.inputs:
        h.update(f"{f}={digest(REPO / f)}\n".encode())
    return h.hexdigest()[:16]


def results_digest(d):
    """What the figures are drawn from: every CSV under the folder except the figures' own."""
    h = hashlib.sha256()
    for f in sorted(d.rglob("*.csv")):
        if "figures" not in f.relative_to(d).parts:
            h.update(f"{f.relative_to(d)}={digest(f)}\n".encode())
    return h.hexdigest()[:16]


def load_state(d):
    try:
        return json.loads((d / STATE_NAME).read_text())
    except (OSError, ValueError):
        return {"items": {}}


def save_state(d, state):
    d.mkdir(parents=True, exist_ok=True)
    tmp = d / f".{STATE_NAME}.tmp"
    tmp.write_text(json.dumps(state, indent=1, sort_keys=True) + "\n")
    os.replace(tmp, d / STATE_NAME)
    write_log(d, state)


def write_log(d, state):
    """reference-runs.md: the folder's provenance in one table, rewritten from the state."""
    rows = ["# What `make reference` ran into this folder", "",
            "Written by `tools/reference.py` after every item; every CSV also carries the harness's own provenance.", "",
            "| item | what | commit | date (UTC) | seconds | result | command |", "| --- | --- | --- | --- | --- | --- | --- |"]
    for name, s in sorted(state["items"].items(), key=lambda kv: kv[1].get("date", "")):
        cmds = "; ".join(f"`{c}`" for c in s.get("commands", [])[:3]) + (" ..." if len(s.get("commands", [])) > 3 else "")
        rows.append(f"| {name} | {s.get('what', '')} | {s.get('commit', '')[:7]}{' (dirty)' if s.get('dirty') == 'dirty' else ''}"
                    f" | {s.get('date', '')} | {s.get('seconds', 0):.0f} | {s.get('result', '')} | {cmds} |")
    (d / LOG_NAME).write_text("\n".join(rows) + "\n")


def build_commit():
    commit, dirty = os.environ.get("SPH_GIT_COMMIT"), os.environ.get("SPH_GIT_DIRTY")
    if not commit:
        p = subprocess.run(["git", "-C", str(REPO), "rev-parse", "HEAD"], capture_output=True, text=True)
        commit = p.stdout.strip() if p.returncode == 0 else "unknown"
        q = subprocess.run(["git", "-C", str(REPO), "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True)
        dirty = dirty or ("unknown" if q.returncode else ("dirty" if q.stdout.strip() else "clean"))
    return commit, dirty or "unknown"


ARCHIVE_PART_BYTES = 15 * 2 ** 20  # the run tool brings back no file over 16 MiB


def archive(dirs, target, since=None):
    """The machine folders' files in one .tar.gz (the run tool brings back at most 8 files): only
    those written since `since` (a time.time(); this call's start) when it is given, so that an
    archive holds this call's results and stays small (unpack each call's in order). An archive
    over ARCHIVE_PART_BYTES is split into NAME.part01, NAME.part02 ... (`cat NAME.part* | tar -xz`)."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_name(f".{target.name}.tmp")
    with tarfile.open(tmp, "w:gz") as tar:
        for d in dirs:
            if not d.is_dir():
                continue
            base = d.resolve().parent.relative_to(REPO) if d.resolve().is_relative_to(REPO) else Path()
            for f in sorted(p for p in d.rglob("*") if p.is_file()):
                if since is None or f.stat().st_mtime >= since:
                    tar.add(f, arcname=str(base / f.resolve().relative_to(d.resolve().parent)))
    for old in target.parent.glob(f"{target.name}.part*"):
        old.unlink()
    if tmp.stat().st_size <= ARCHIVE_PART_BYTES:
        os.replace(tmp, target)
        return
    target.unlink(missing_ok=True)
    with open(tmp, "rb") as whole:
        for k, chunk in enumerate(iter(lambda: whole.read(ARCHIVE_PART_BYTES), b""), start=1):
            target.with_name(f"{target.name}.part{k:02d}").write_bytes(chunk)
    tmp.unlink()
    print(f"reference: {target.name} is over {ARCHIVE_PART_BYTES / 2 ** 20:g} MiB: split into "
          f"{target.name}.part01..{k:02d}; here: cat {target.name}.part* | tar -xz")


# --------------------------------------------------------------------------------------------


# What --help ends with: the lease loop on a borrowed GPU machine (docs/gpu-machines.md has it all).
LEASE_STEPS = """On a borrowed GPU machine (commands of at most 10 minutes, 64 MiB carried, few files back):
  here, once:         F64=1 tools/gpu-run.sh pack            (.carry/: binaries, libraries, meshes)
                      python3 tools/reference.py --pack-dsph (.dsph/: DualSPHysics' anchor, xz)
  there, per command: DSPH=$PWD/.dsph REFERENCE_BUDGET_S=480 \\
                        tools/gpu-run.sh exec python3 tools/reference.py   (carry .carry and .dsph)
  here, after each:   tar -xzf <what came back>/reference.tar.gz   (this call's results, over the tree;
                      before the next call, whose tree replaces the machine's results/reference/)
Repeat until it prints "nothing left to run"; then `make claims` and commit results/reference/ with
docs/results.md. Too large to carry together? Run REFERENCE_ONLY=dualsphysics in a call of its own
carrying .dsph alone. On several GPUs, REFERENCE_ONLY="multi-gpu fig10 figures-multi".
PLAN=1 (or --dry-run) prints the plan and its estimate anywhere; --list names the items."""


def parse_args(argv):
    env_list = lambda v: [x for x in re.split(r"[\s,]+", os.environ.get(v, "")) if x]  # noqa: E731
    p = argparse.ArgumentParser(prog="tools/reference.py", description=__doc__.split("\n\n")[0],
                                epilog=LEASE_STEPS, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--dry-run", action="store_true", default=os.environ.get("PLAN", "") not in ("", "0"),
                   help="print the plan and its estimate; run nothing (PLAN=1)")
    budget = os.environ.get("REFERENCE_BUDGET_S")
    p.add_argument("--budget", type=float, default=float(budget) if budget else None,
                   help="seconds: start no item whose estimate exceeds what is left (REFERENCE_BUDGET_S)")
    p.add_argument("--only", nargs="+", default=env_list("REFERENCE_ONLY"), help="run only these items")
    p.add_argument("--skip", nargs="+", default=env_list("REFERENCE_SKIP"), help="leave these items out")
    p.add_argument("--force", action="store_true", help="run items even when their stamp says up to date "
                   "(sphbench's own check still skips unchanged experiments; delete their runs.csv to rerun)")
    p.add_argument("--root", type=Path, default=REPO / "results" / "reference", help="default: results/reference")
    out = os.environ.get("OUT")
    p.add_argument("--archive", type=Path, default=os.environ.get("REFERENCE_ARCHIVE") or
                   (Path(out) / "reference.tar.gz" if out else None),
                   help="pack the machine folders into this .tar.gz after every item (default: $OUT/reference.tar.gz "
                        "when $OUT is set)")
    p.add_argument("--list", action="store_true", help="list the items and exit")
    p.add_argument("--figures-only", action="store_true",
                   help="draw the figures of the machine folders under --root (or --machine) and exit")
    p.add_argument("--machine", nargs="+", default=[], help="with --figures-only: folders such as h200 h200-x2")
    p.add_argument("--pack-dsph", nargs="*", metavar=("SRC", "DEST"),
                   help="copy DualSPHysics' anchor (default ../shared/anchors/dualsphysics) to DEST (default .dsph), "
                        "recompressed to travel within the run tool's 64 MiB, and exit")
    return p.parse_args(argv)


def figures_only(args):
    if plotting_available():
        print(f"reference: cannot draw figures here ({plotting_available()}).", file=sys.stderr)
        return 2
    ctx = Context(args, {}, 1)
    # By default the folders that `make reference` wrote; --machine names others (h100, say).
    dirs = [args.root / m for m in args.machine] if args.machine else sorted(
        p for p in args.root.iterdir() if (p / STATE_NAME).is_file())
    if not dirs:
        print(f"reference: no folder under {args.root} was written by `make reference`; name some with --machine.")
    for d in dirs:
        scope = "multi" if re.search(r"-x\d+$", d.name) else "single"
        print(f"{d}: {draw_figures(ctx, d, scope)}")
    return 0


def main(argv=None):
    call_start = time.time()
    args = parse_args(argv)
    all_items = items(int(os.environ.get("REFERENCE_GPUS", "1")))
    if args.list:
        for it in all_items:
            print(f"{it.name:22} {'1 GPU' if it.scope == 'single' else '2+ GPUs':8} ~{it.estimate:4.0f} s  {it.what}")
        return 0
    if args.figures_only:
        return figures_only(args)
    if args.pack_dsph is not None:
        src = args.pack_dsph[0] if args.pack_dsph else REPO.parent / "shared" / "anchors" / "dualsphysics"
        return pack_dualsphysics(src, args.pack_dsph[1] if len(args.pack_dsph) > 1 else REPO / ".dsph")
    names = {it.name for it in all_items}
    for n in args.only + args.skip:
        if n not in names:
            print(f"reference: there is no item '{n}' (tools/reference.py --list names them).", file=sys.stderr)
            return 2

    gpus, why = detect_gpus()
    assumed = False
    if not gpus:
        if not args.dry_run:
            print(f"reference: no GPU here ({why}), so nothing was run; run `make reference` on a GPU machine, "
                  f"or `make reference PLAN=1` for its plan.", file=sys.stderr)
            return 2
        n = int(os.environ.get("REFERENCE_GPUS", "1"))
        gpus = [[f"NVIDIA {os.environ.get('REFERENCE_GPU_NAME', 'H200')}", "?", "?"]] * n
        assumed = True
    n_gpus = len(gpus)
    all_items = items(n_gpus)
    short = gpu_short_name(gpus[0][0])
    if len({g[0] for g in gpus}) > 1:
        print(f"reference: the GPUs differ ({', '.join(g[0] for g in gpus)}); naming the folder after the first.")
    dirs = machine_dirs(args.root, short, n_gpus)
    tools = find_tools()
    commit, dirty = build_commit()

    # The plan: every item with its state.
    states = {scope: load_state(d) for scope, d in dirs.items() if d is not None}
    plan, total = [], 0.0
    for it in all_items:
        d = dirs[it.scope]
        status, est = "run", it.estimate
        if d is None:
            status = f"skipped: needs 2 or more GPUs ({n_gpus} here)"
        elif args.only and it.name not in args.only or it.name in args.skip:
            status = "not asked for"
        elif (missing := [b for b in it.bins if tools.get(b) is None]) and not assumed:
            status = f"skipped: {', '.join(missing)} not found (PATH, build/, build-f64/)"
        elif it.needs and (reason := it.needs(tools)):
            status = f"skipped: {reason}"
        elif missing:  # a dry run without a GPU: plan it as the GPU machine would
            status = "run"
        else:
            prev = states[it.scope]["items"].get(it.name, {})
            est = prev.get("estimate_s", it.estimate)
            if prev.get("inputs", inputs_digest(it)) != inputs_digest(it):
                est = max(est, it.estimate)  # its specs changed since it was timed (runs made longer)
            st = stamp(it, tools, n_gpus)
            if it.name.startswith("figures"):
                st += results_digest(d) if d.is_dir() else ""
            it.stamp = st
            done = prev.get("stamp") == st and prev.get("result") not in (None, "failed", "not drawn")
            if done and all((d / o).exists() for o in it.outputs) and not args.force:
                status, est = "up to date", 0.0
        plan.append([it, status, est])
    # Figures are drawn again when anything of their folder runs now.
    for entry in plan:
        it = entry[0]
        if it.name.startswith("figures") and entry[1] == "up to date" and any(
                s == "run" and o.scope == it.scope and not o.name.startswith("figures") for o, s, _ in plan):
            entry[1], entry[2] = "run", it.estimate
    total = sum(est for _, s, est in plan if s == "run")

    where = ", ".join(str(d.relative_to(REPO) if d.is_relative_to(REPO) else d) for d in dirs.values() if d)
    print(f"reference: {n_gpus} x {gpus[0][0]}{' (assumed: no GPU here)' if assumed else ''} -> {where}; "
          f"build {commit[:7]} ({dirty})")
    budget = args.budget
    print(f"{'item':22} {'estimate':>9}  status / what")
    planned = 0.0
    for it, status, est in plan:
        shown = f"{est:7.0f} s" if status == "run" else " " * 9
        if status == "run":
            fits = budget is None or planned + est <= budget or it.name.startswith("figures")
            planned += est if fits else 0
            status = "to run" if fits else "to run in a later call (over the budget)"
        print(f"{it.name:22} {shown}  {status}: {it.what}")
    print(f"estimate: {total:.0f} s ({total / 60:.1f} min) for {sum(s == 'run' for _, s, _ in plan)} items"
          + (f"; budget {budget:.0f} s: items that no longer fit are left for the next call" if budget else ""),
          flush=True)
    if args.dry_run:
        return 0

    # Run.
    os.environ.setdefault("NCCL_NVLS_ENABLE", "0")  # never NVLink multicast on shared machines
    ctx = Context(args, tools, n_gpus)
    for d in dirs.values():
        if d is not None:
            d.mkdir(parents=True, exist_ok=True)
            smi = subprocess.run(["nvidia-smi", "--query-gpu=name,driver_version,memory.total", "--format=csv"],
                                 capture_output=True, text=True).stdout
            (d / "gpu.txt").write_text(smi)
    if dirs["multi"] is not None:
        topo = subprocess.run(["nvidia-smi", "topo", "-m"], capture_output=True, text=True).stdout
        (dirs["multi"] / "topology.txt").write_text(topo)
    start, left_out, failed, ran = time.monotonic(), [], [], []
    for it, status, est in plan:
        if status != "run":
            continue
        used = time.monotonic() - start
        if budget is not None and used + est > budget and not it.name.startswith("figures"):
            left_out.append(it.name)
            print(f"[{it.name}] left for the next call: about {est:.0f} s, {max(budget - used, 0):.0f} s of the budget left",
                  flush=True)
            continue
        d = dirs[it.scope]
        if it.name.startswith("figures") and not args.force:  # drawn already from these very results?
            prev = load_state(d)["items"].get(it.name, {})
            if prev.get("stamp") == stamp(it, tools, n_gpus) + results_digest(d) and prev.get("result", "").endswith("figures"):
                print(f"[{it.name}] up to date: the results did not change", flush=True)
                continue
        print(f"[{it.name}] {it.what} (about {est:.0f} s) -> {d.relative_to(REPO) if d.is_relative_to(REPO) else d}",
              flush=True)
        ctx.log_lines, ctx.harness_skipped = [], False
        t0 = time.monotonic()
        try:
            result = it.run(ctx, d) or "done"
        except ItemFailed as e:
            result = "failed"
            print(f"[{it.name}] FAILED: {e}", flush=True)
            failed.append(it.name)
        seconds = time.monotonic() - t0
        state = load_state(d)
        prev = state["items"].get(it.name, {})
        if ctx.harness_skipped and result == "done":
            result = "up to date (sphbench)"  # its time says nothing of a real run's
        timed = not (ctx.harness_skipped or result == "failed")  # a skipped or failed run timed nothing
        estimate = round(seconds, 1) if timed else prev.get("estimate_s", it.estimate)
        state["items"][it.name] = {"stamp": getattr(it, "stamp", ""), "seconds": round(seconds, 1), "result": result,
                                   "estimate_s": estimate,
                                   # the inputs the estimate was timed with: an untimed run keeps the old ones
                                   "inputs": inputs_digest(it) if timed else prev.get("inputs"),
                                   "what": it.what, "commit": commit, "dirty": dirty, "gpus": n_gpus,
                                   "gpu": gpus[0][0], "date": datetime.datetime.now(datetime.timezone.utc)
                                   .strftime("%Y-%m-%dT%H:%M:%SZ"), "commands": ctx.log_lines}
        if it.name.startswith("figures"):  # drawn from the results as they are now
            state["items"][it.name]["stamp"] = stamp(it, tools, n_gpus) + results_digest(d)
        save_state(d, state)
        ran.append(it.name)
        print(f"[{it.name}] {result} in {seconds:.0f} s", flush=True)
        if args.archive:
            archive([x for x in dirs.values() if x is not None], args.archive, since=call_start)
        if it.name == "cuda-tests" and result == "failed":
            print("reference: the CUDA tests failed, so no result of this build is worth recording; stopping.")
            break
    used = time.monotonic() - start
    print(f"reference: ran {len(ran)} items in {used:.0f} s"
          + (f"; FAILED: {', '.join(failed)}" if failed else "")
          + (f"; left for the next call: {', '.join(left_out)}" if left_out else "; nothing left to run")
          + (f"; archive {args.archive}" if args.archive else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
