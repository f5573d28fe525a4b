#!/usr/bin/env python3
"""Machine-independent performance measures for CI, held against committed references.

CI has no GPU and its 2-core machines are too noisy for wall-clock times, so this holds two
measures that do not vary with machine load:
  * instructions executed by the host backend on small fixed scenes (valgrind's callgrind),
    counted in the solver's own functions only: the physics is one source for both backends,
    so work added per pair shows up here;
  * what the CUDA compiler made of each kernel (cuobjdump on the built binary): registers,
    stack frame and local memory (spills), shared memory, SASS size, and per kernel the
    instructions that matter for speed: IEEE division checks (FCHK), calls to the division and
    square-root slow paths (CALL.REL), MUFU, and local loads and stores (LDL/STL, spills).

Subcommands (exit codes as `sphbench compare`: 0 nothing regressed, 1 a regression, 2 usage or
setup error, 3 nothing comparable):
  measure  --build B --out DIR         both measures of build B into DIR/{instructions,kernels}.csv
  compare  BASELINE CANDIDATE          table of changes and verdicts
  check    --build B --reference REF   measure into --out, then compare with REF
  accept   --build B --reference REF   measure into REF (rewrites the references)
  instructions --subject S --function RE --out CSV -- CMD...   count one command (tests)
  kernels  --out CSV FILE...           kernel resources of objects, libraries or binaries (tests)
"""
import argparse
import csv
import glob
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

EXIT_OK, EXIT_REGRESSION, EXIT_SETUP, EXIT_NOTHING_COMPARABLE = 0, 1, 2, 3

# Instruction counts: with one OpenMP thread, 5 callgrind runs of one build (different
# environment sizes and working folders) gave identical counts; a host-only and a CUDA build of
# one commit differ by 1e-6. The tolerance is left for what one machine cannot show (glibc picks
# string functions by CPU, and the step calls some) and stays under what matters: one more
# division in the pair body is +0.9% to +1.2% of the force loop, 10% more pair work about +11%.
INSTRUCTION_TOLERANCE = 0.005
# SASS size: a few percent, so that reordering by a new compiler heuristic does not fail CI
# while a new code path (a slow-path call site, an unrolled loop) does.
SASS_SIZE_TOLERANCE = 0.03

# The fixed scenes of the host measure: a dam break small enough for callgrind (~1 min on one
# core), once with cell ranges and once with stored neighbour lists (a second pair loop).
HOST_SUBJECTS = [
    ("dambreak cells", ["simulate", "dambreak", "--set", "dp=0.05", "--cells-per-support", "2"]),
    ("dambreak verlet", ["simulate", "dambreak", "--set", "dp=0.05", "--verlet"]),
]
HOST_COMMON = ["--steps", "6", "--warmup", "0", "--backend", "host", "--fixed-dt", "1e-4", "--quiet"]
# metric -> the functions (regular expressions on callgrind's demangled names) whose inclusive
# instruction counts it adds up; none of them calls another. The step is held as well as the
# pair loops, so that added work outside the forces (sort, integration) is caught too.
HOST_METRICS = {
    "instructions_forces": [r"::compute_forces(_listed)?\(\)$"],
    "instructions_step": [r"^sph::Simulation::step\("],
}

# SASS instruction classes counted per kernel: metric -> regular expression on the opcode.
SASS_CLASSES = {
    "fchk": r"FCHK",               # one per IEEE float division (the slow path's guard)
    "slow_path_calls": r"CALL\.",  # calls to the division / sqrt / rcp slow-path subroutines
    "mufu": r"MUFU\.",             # special-function unit: rcp, rsq, sqrt, ex2, lg2, sin
    "ldl": r"LDL",                 # local-memory loads: spills and local arrays
    "stl": r"STL",                 # local-memory stores
}
EXACT_METRICS = ["registers", "stack", "local", "shared"] + list(SASS_CLASSES)
VERDICT_ORDER = ["SAME", "FASTER", "SLOWER", "AMBIGUOUS", "COUNTER CHANGED"]


class SetupError(Exception):
    """Something needed to measure is missing: exit code 2."""


# ---------------------------------------------------------------------------------------------
# Result files: CSV with columns subject, metric, value (text, so counts stay exact).

def write_rows(path, rows):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["subject", "metric", "value"])
        for subject, metric, value in rows:
            w.writerow([subject, metric, value])
    os.replace(tmp, path)


def read_rows(path):
    if not os.path.isfile(path):
        raise SetupError(f"'{path}' does not exist")
    with open(path, newline="") as f:
        r = csv.DictReader(f)
        if r.fieldnames is None or not {"subject", "metric", "value"} <= set(r.fieldnames):
            raise SetupError(f"'{path}' has no subject,metric,value header")
        return {(row["subject"], row["metric"]): row["value"] for row in r}


def read_result(path):
    """A result folder (instructions.csv and/or kernels.csv) or one CSV file."""
    if os.path.isdir(path):
        files = [os.path.join(path, n) for n in ("instructions.csv", "kernels.csv")]
        files = [f for f in files if os.path.isfile(f)]
        if not files:
            raise SetupError(f"result folder '{path}' has neither instructions.csv nor kernels.csv")
        rows = {}
        for f in files:
            rows.update(read_rows(f))
        return rows
    return read_rows(path)


# ---------------------------------------------------------------------------------------------
# Instructions executed (callgrind).

def need_tool(name, hint):
    path = shutil.which(name)
    if not path:
        raise SetupError(f"{name} not found: {hint}")
    return path


def callgrind_inclusive(command, env=None):
    """Runs command under callgrind; returns {demangled function: inclusive instructions}."""
    need_tool("valgrind", "apt-get install valgrind (tools/install-deps.sh does)")
    need_tool("callgrind_annotate", "it ships with valgrind")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "callgrind.out")
        run_env = dict(os.environ if env is None else env)
        # One OpenMP thread: with more, the count includes however long each thread spun in the
        # runtime's barriers, which depends on the machine's load.
        run_env["OMP_NUM_THREADS"] = "1"
        run_env["OMP_WAIT_POLICY"] = "passive"
        proc = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}"] + command,
                              cwd=tmp, env=run_env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if proc.returncode != 0:
            raise SetupError(f"'{' '.join(command)}' failed under callgrind (exit {proc.returncode}):\n"
                             + proc.stderr[-2000:])
        ann = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", out],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if ann.returncode != 0:
            raise SetupError("callgrind_annotate failed:\n" + ann.stderr[-2000:])
    costs = {}
    # Lines like: "123,456,789 (12.34%)  file.cpp:sph::Simulation::step() [/path/sphbench]"
    line_re = re.compile(r"^\s*([\d,]+)\s+(?:\([^)]*\)\s+)?(\S[^:]*):(.*?)(?:\s+\[[^\]]*\])?\s*$")
    for line in ann.stdout.splitlines():
        m = line_re.match(line)
        if m:
            name = m.group(3).strip()
            costs[name] = costs.get(name, 0) + int(m.group(1).replace(",", ""))
    return costs


def sum_matching(costs, patterns, subject, metric):
    regexes = [re.compile(p) for p in patterns]
    matched = {name: n for name, n in costs.items() if any(r.search(name) for r in regexes)}
    if not matched:
        raise SetupError(f"{subject}: no function matches {patterns} for {metric}; was the binary built with "
                         "symbols of its own functions, or were they renamed? (update HOST_METRICS in "
                         "tools/perf_check.py)")
    return sum(matched.values())


def measure_host(build):
    sphbench = os.path.join(build, "harness", "sphbench")
    if not os.access(sphbench, os.X_OK):
        raise SetupError(f"'{sphbench}' is missing: build first (make build)")
    rows = []
    for subject, args in HOST_SUBJECTS:
        with tempfile.TemporaryDirectory() as out:
            costs = callgrind_inclusive([os.path.abspath(sphbench)] + args + HOST_COMMON + ["--out", out])
        for metric, patterns in HOST_METRICS.items():
            rows.append((subject, metric, str(sum_matching(costs, patterns, subject, metric))))
    return rows


# ---------------------------------------------------------------------------------------------
# Kernel resources (cuobjdump).

def find_cuobjdump():
    """cuobjdump and nvdisasm (which --dump-sass needs): on PATH, beside nvcc, or from the
    nvidia-cuda-cuobjdump / nvidia-cuda-nvdisasm wheels (tools/install-deps.sh installs them
    where the toolkit lacks them)."""
    dirs = []
    nvcc = shutil.which("nvcc") or ("/usr/local/cuda/bin/nvcc" if os.path.exists("/usr/local/cuda/bin/nvcc") else None)
    if nvcc:
        dirs.append(os.path.dirname(os.path.realpath(nvcc)))
    try:
        import nvidia  # the wheels' namespace package
        for base in nvidia.__path__:
            dirs += sorted(glob.glob(os.path.join(base, "cu*", "bin")))
    except ImportError:
        pass
    path = os.pathsep.join(dirs + [os.environ.get("PATH", "")])
    cuobjdump = shutil.which("cuobjdump", path=path)
    nvdisasm = shutil.which("nvdisasm", path=path)
    if not cuobjdump or not nvdisasm:
        raise SetupError("cuobjdump and nvdisasm are needed to read the CUDA kernels: run tools/install-deps.sh "
                         "(pip install nvidia-cuda-cuobjdump nvidia-cuda-nvdisasm)")
    env = dict(os.environ)
    env["PATH"] = os.path.dirname(nvdisasm) + os.pathsep + env.get("PATH", "")
    return cuobjdump, env


def demangle(names):
    if not names:
        return {}
    cxxfilt = shutil.which("c++filt")
    if not cxxfilt:
        raise SetupError("c++filt not found (binutils)")
    out = subprocess.run([cxxfilt], input="\n".join(names) + "\n", stdout=subprocess.PIPE, text=True, check=True)
    return dict(zip(names, out.stdout.splitlines()))


def readable_kernel_name(demangled):
    """sph::gpu::(anonymous namespace)::forces_kernel<sph::WendlandC2, ...>(sph::ForceInputs, ...)
    -> forces_kernel<WendlandC2, CellSearch<2, false>, true>: the anonymous namespace's mangled
    name carries a hash of the build path, and the parameters are the same for every
    instantiation."""
    name = demangled.replace("(anonymous namespace)::", "")
    depth = 0
    for k, ch in enumerate(name):  # drop the parameter list: the first '(' outside <>
        if ch == "<":
            depth += 1
        elif ch == ">":
            depth -= 1
        elif ch == "(" and depth == 0:
            name = name[:k]
            break
    name = re.sub(r"\bsph::(gpu::|probe::)?", "", name)
    return name.strip()


def cuobjdump_text(cuobjdump, env, flag, files):
    text = []
    for f in files:  # cuobjdump reads one file a call
        proc = subprocess.run([cuobjdump, flag, f], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
        if proc.returncode != 0:
            raise SetupError(f"cuobjdump {flag} {f} failed:\n{proc.stderr[-2000:]}")
        text.append(proc.stdout)
    return "\n".join(text)


def parse_resource_usage(text):
    """{(arch, mangled): {registers, stack, local, shared}} from --dump-resource-usage."""
    out, arch = {}, "sm_?"
    for line in text.splitlines():
        m = re.search(r"arch = (sm_\d+\w*)", line) or re.search(r"code for (sm_\d+\w*)", line)
        if m:
            arch = m.group(1)
        m = re.match(r"\s*Function (\S+):\s*$", line)
        if m:
            current = (arch, m.group(1))
            continue
        m = re.match(r"\s*REG:(\d+) STACK:(\d+) SHARED:(\d+) LOCAL:(\d+)", line)
        if m:
            out[current] = {"registers": int(m.group(1)), "stack": int(m.group(2)), "shared": int(m.group(3)),
                            "local": int(m.group(4))}
    return out


def parse_sass(text):
    """{(arch, mangled): {sass_instructions, fchk, ...}} from --dump-sass. NOPs (the padding
    after the last instruction) are alignment, not code, and are not counted."""
    out, arch, current = {}, "sm_?", None
    classes = {k: re.compile(r"^(@!?U?P\w+\s+)?" + v) for k, v in SASS_CLASSES.items()}
    insn_re = re.compile(r"^\s*/\*[0-9a-f]{4,}\*/\s+(.*?)\s*;")
    for line in text.splitlines():
        m = re.search(r"code for (sm_\d+\w*)", line)
        if m:
            arch = m.group(1)
            continue
        m = re.match(r"\s*Function : (\S+)\s*$", line)
        if m:
            current = (arch, m.group(1))
            out[current] = {"sass_instructions": 0, **{k: 0 for k in SASS_CLASSES}}
            continue
        m = insn_re.match(line)
        if m and current:
            insn = m.group(1)
            if insn == "NOP":
                continue
            counts = out[current]
            counts["sass_instructions"] += 1
            for k, r in classes.items():
                if r.search(insn):
                    counts[k] += 1
    return out


def measure_kernels(files, name_filter=None):
    cuobjdump, env = find_cuobjdump()
    usage = parse_resource_usage(cuobjdump_text(cuobjdump, env, "--dump-resource-usage", files))
    sass = parse_sass(cuobjdump_text(cuobjdump, env, "--dump-sass", files))
    names = demangle(sorted({m for _, m in usage} | {m for _, m in sass}))
    rows, seen = [], {}
    for key in sorted(set(usage) | set(sass)):
        arch, mangled = key
        # Kernels return void; a template's demangled name spells its return type out.
        demangled = re.sub(r"^void ", "", names.get(mangled, mangled))
        if name_filter and not name_filter(demangled):
            continue
        subject = f"{arch} {readable_kernel_name(demangled)}"
        if subject in seen and seen[subject] != mangled:  # an overload: keep the parameters
            subject = f"{arch} {demangled}"
        seen[subject] = mangled
        metrics = {**usage.get(key, {}), **sass.get(key, {})}
        for metric in ["registers", "stack", "local", "shared", "sass_instructions"] + list(SASS_CLASSES):
            if metric in metrics:
                rows.append((subject, metric, str(metrics[metric])))
    if not rows:
        raise SetupError(f"no kernels found in {' '.join(files)}")
    return rows


def cuda_objects(build):
    """The solver's CUDA objects in a build (CMake names them *.cu.o); none in a host-only build.
    Only solver/: the tests' probe objects (tests/perf_check) hold injected costs."""
    return sorted(glob.glob(os.path.join(build, "solver", "**", "*.cu.o"), recursive=True))


def compiler_versions(build):
    """The compilers that made the build, from CMake's records: a reference made with another
    compiler differs for that reason alone."""
    rows = []
    for lang, var in (("CXX", "CMAKE_CXX_COMPILER_VERSION"), ("CUDA", "CMAKE_CUDA_COMPILER_VERSION")):
        for f in glob.glob(os.path.join(build, "CMakeFiles", "*", f"CMake{lang}Compiler.cmake")):
            m = re.search(rf'set\({var} "([^"]*)"\)', open(f).read())
            if m:
                rows.append(("compiler", lang, m.group(1)))
    return rows


def measure(build, out, parts):
    if not os.path.isfile(os.path.join(build, "CMakeCache.txt")):
        raise SetupError(f"'{build}' is not a configured build folder")
    versions = dict(((s, m), v) for s, m, v in compiler_versions(build))
    if "host" in parts:
        print(f"perf-check: counting instructions of {len(HOST_SUBJECTS)} host runs under callgrind ...", flush=True)
        rows = measure_host(build)
        cxx = versions.get(("compiler", "CXX"))
        write_rows(os.path.join(out, "instructions.csv"), ([("compiler", "CXX", cxx)] if cxx else []) + rows)
    if "kernels" in parts:
        objects = cuda_objects(build)
        if not objects:
            print(f"perf-check: {build} has no CUDA objects (built without nvcc): kernel resources not checked")
        else:
            # The solver's own kernels (sph::); CUB's and Thrust's change with the toolkit, not
            # with this project's code.
            rows = measure_kernels(objects, lambda d: d.startswith("sph::"))
            cuda = versions.get(("compiler", "CUDA"))
            write_rows(os.path.join(out, "kernels.csv"), ([("compiler", "CUDA", cuda)] if cuda else []) + rows)
            print(f"perf-check: read {len({r[0] for r in rows})} kernels from {len(objects)} CUDA objects")


# ---------------------------------------------------------------------------------------------
# Comparison, in the table format and with the verdict names of `sphbench compare`.

def tolerance_of(metric):
    if metric.startswith("instructions"):
        return INSTRUCTION_TOLERANCE
    if metric == "sass_instructions":
        return SASS_SIZE_TOLERANCE
    return None  # exact


def judge(metric, base_text, cand_text):
    """(change, verdict) of one metric."""
    try:
        b, c = float(base_text), float(cand_text)
    except ValueError:
        return (0.0 if base_text == cand_text else math.nan), ("SAME" if base_text == cand_text else "COUNTER CHANGED")
    change = (c - b) / b if b != 0 else (0.0 if c == 0 else math.copysign(math.inf, c))
    tol = tolerance_of(metric)
    if tol is None:
        return change, "SAME" if b == c else "COUNTER CHANGED"
    if abs(change) <= tol:
        return change, "SAME"
    return change, "SLOWER" if change > 0 else "FASTER"


def change_text(change):
    if math.isnan(change):
        return "-"
    if math.isinf(change):
        return "+inf" if change > 0 else "-inf"
    return f"{100 * change:+.1f}%" if abs(change) >= 0.001 or change == 0 else f"{100 * change:+.3f}%"


def print_table(rows):
    table = [["run", "metric", "baseline", "candidate", "change", "p", "verdict"]] + rows
    width = [max(len(r[i]) for r in table) for i in range(7)]
    for r in table:
        cells = []
        for i, cell in enumerate(r):
            pad = " " * (width[i] - len(cell))
            numeric = 2 <= i <= 5
            cells.append(pad + cell if numeric else (cell + pad if i + 1 < len(r) else cell))
        print("  ".join(cells))


def compare(baseline_path, candidate_path, show_all=False):
    base, cand = read_result(baseline_path), read_result(candidate_path)
    subjects = lambda rows: sorted({s for s, _ in rows})
    only_base = [s for s in subjects(base) if not any(k[0] == s for k in cand)]
    only_cand = [s for s in subjects(cand) if not any(k[0] == s for k in base)]
    table, tally, regressed = [], {}, False
    for key in sorted(set(base) & set(cand)):
        subject, metric = key
        change, verdict = judge(metric, base[key], cand[key])
        tally[verdict] = tally.get(verdict, 0) + 1
        regressed |= verdict in ("SLOWER", "COUNTER CHANGED")
        # Every instruction count is shown; of the many kernel metrics only what changed.
        if show_all or verdict != "SAME" or metric.startswith("instructions"):
            table.append([subject, metric, base[key], cand[key], change_text(change), "-", verdict])
    comparable = bool(tally)
    if comparable and table:
        print_table(table)
    for s in only_base:
        print(f"only in the baseline: {s}")
    for s in only_cand:
        print(f"only in the candidate: {s}")
    if not comparable:
        print(f"nothing comparable: no run and metric is present in both {baseline_path} and {candidate_path}")
        return EXIT_NOTHING_COMPARABLE
    counts = ", ".join(f"{tally[v]} {v}" for v in sorted(tally, key=VERDICT_ORDER.index))
    print(f"{'REGRESSION' if regressed else 'no regression'}: {counts} (instructions within "
          f"{100 * INSTRUCTION_TOLERANCE:g}%, SASS size within {100 * SASS_SIZE_TOLERANCE:g}%, registers, stack, "
          "local and shared memory and instruction classes exact)")
    return EXIT_REGRESSION if regressed else EXIT_OK


# ---------------------------------------------------------------------------------------------

ACCEPT_HINT = ("an intended change? `make perf-accept` rewrites the references under {ref}; commit them with the "
               "change, so that it shows in the diff")


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    for name in ("measure", "check", "accept"):
        p = sub.add_parser(name)
        p.add_argument("--build", required=True)
        p.add_argument("--parts", default="host,kernels", help="host, kernels or both (comma-separated)")
        if name != "measure":
            p.add_argument("--reference", required=True)
        if name != "accept":
            p.add_argument("--out", required=name == "measure", default="results/perf-check/host")
    p = sub.add_parser("compare")
    p.add_argument("baseline")
    p.add_argument("candidate")
    p.add_argument("--all", action="store_true", help="show unchanged kernel metrics too")
    p = sub.add_parser("instructions")
    p.add_argument("--subject", required=True)
    p.add_argument("--metric", default="instructions")
    p.add_argument("--function", required=True, help="regular expression on the demangled function names")
    p.add_argument("--out", required=True)
    p.add_argument("cmd", nargs=argparse.REMAINDER)
    p = sub.add_parser("kernels")
    p.add_argument("--out", required=True)
    p.add_argument("files", nargs="+")
    try:
        a = ap.parse_args(argv)
    except SystemExit as e:
        return EXIT_OK if e.code == 0 else EXIT_SETUP
    try:
        if a.command == "compare":
            return compare(a.baseline, a.candidate, a.all)
        if a.command == "instructions":
            cmd = a.cmd[1:] if a.cmd[:1] == ["--"] else a.cmd
            if not cmd:
                raise SetupError("no command to count")
            n = sum_matching(callgrind_inclusive(cmd), [a.function], a.subject, a.metric)
            write_rows(a.out, [(a.subject, a.metric, str(n))])
            return EXIT_OK
        if a.command == "kernels":
            write_rows(a.out, measure_kernels(a.files))
            return EXIT_OK
        parts = set(a.parts.split(","))
        if not parts <= {"host", "kernels"}:
            raise SetupError(f"--parts: unknown part in '{a.parts}'")
        if a.command == "measure":
            measure(a.build, a.out, parts)
            return EXIT_OK
        if a.command == "accept":
            measure(a.build, a.reference, parts)
            print(f"perf-accept: references rewritten under {a.reference}; `git diff {a.reference}` shows the change")
            return EXIT_OK
        # check
        shutil.rmtree(a.out, ignore_errors=True)
        measure(a.build, a.out, parts)
        codes = []
        for name in ("instructions.csv", "kernels.csv"):
            cand = os.path.join(a.out, name)
            if not os.path.exists(cand):
                continue
            ref = os.path.join(a.reference, name)
            if not os.path.exists(ref):
                raise SetupError(f"no reference {ref}: make one with `make perf-accept` and commit it")
            print(f"\nperf-check: {ref} against this build")
            codes.append(compare(ref, cand))
        if not codes:
            raise SetupError("nothing was measured")
        code = EXIT_REGRESSION if EXIT_REGRESSION in codes else max(codes)
        if code == EXIT_REGRESSION:
            print(ACCEPT_HINT.format(ref=a.reference))
        return code
    except SetupError as e:
        print(f"perf-check: setup error: {e}", file=sys.stderr)
        return EXIT_SETUP


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
