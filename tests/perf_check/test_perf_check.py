#!/usr/bin/env python3
"""ctest cases of tools/perf_check.py: test_perf_check.py CASE PERF_CHECK [FILES...].

Each case runs the tool's command line as `make perf-check` does and checks its exit code and
the verdict of the row the injection must move, so that a tool that flags everything (or
nothing) fails here. Exit 0: passed; 1: failed, with the reason."""
import os
import re
import subprocess
import sys
import tempfile

# The probe's force loop function, for callgrind (tests/perf_check/pair_loop_probe.cpp).
PROBE_FUNCTION = r"probe_force_loop\("


class Failed(Exception):
    pass


def run(tool, *args):
    proc = subprocess.run([sys.executable, tool, *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    print(f"$ perf_check.py {' '.join(args)}  -> exit {proc.returncode}\n{proc.stdout}")
    return proc.returncode, proc.stdout


def table_rows(output):
    """[(run, metric, baseline, candidate, change, p, verdict)] of the compare table."""
    rows = []
    for line in output.splitlines():
        cells = re.split(r"\s{2,}", line.strip())
        if len(cells) == 7 and cells[0] != "run":
            rows.append(cells)
    return rows


def expect(cond, why):
    if not cond:
        raise Failed(why)


def measure_instructions(tool, tmp, name, binary):
    out = os.path.join(tmp, f"{name}.csv")
    code, _ = run(tool, "instructions", "--subject", "probe lattice", "--metric", "instructions_forces",
                  "--function", PROBE_FUNCTION, "--out", out, "--", binary)
    expect(code == 0, f"counting instructions of {binary} failed (exit {code})")
    return out


def measure_kernels(tool, tmp, name, obj):
    out = os.path.join(tmp, f"{name}.csv")
    code, _ = run(tool, "kernels", "--out", out, obj)
    expect(code == 0, f"reading kernels of {obj} failed (exit {code})")
    return out


def case_host_clean(tool, tmp, baseline):
    a = measure_instructions(tool, tmp, "a", baseline)
    b = measure_instructions(tool, tmp, "b", baseline)
    code, out = run(tool, "compare", a, b)
    expect(code == 0, f"two runs of one build must compare clean, exit {code}")
    rows = table_rows(out)
    expect(rows and all(r[6] == "SAME" for r in rows), "every row must be SAME")


def case_host_extra_work(tool, tmp, baseline, extra):
    a = measure_instructions(tool, tmp, "baseline", baseline)
    b = measure_instructions(tool, tmp, "extra", extra)
    code, out = run(tool, "compare", a, b)
    expect(code == 1, f"10% more pair work must be a regression (exit 1), got exit {code}")
    rows = [r for r in table_rows(out) if r[1] == "instructions_forces"]
    expect(len(rows) == 1 and rows[0][6] == "SLOWER", "instructions_forces must be SLOWER")
    change = float(rows[0][4].rstrip("%"))
    # Every 10th pair twice is 10% more pair evaluations plus a counter: the count must say so.
    expect(8 <= change <= 20, f"10% more pair work measured as {change:+.1f}%, expected about +10%")


def case_kernels_clean(tool, tmp, baseline, again, *_):
    a = measure_kernels(tool, tmp, "a", baseline)
    b = measure_kernels(tool, tmp, "b", again)
    code, out = run(tool, "compare", a, b)
    expect(code == 0, f"two compilations of one source must compare clean, exit {code}")
    expect("only in" not in out, "both must hold the same kernels")


def case_kernels_division(tool, tmp, baseline, _again, division, _spill):
    a = measure_kernels(tool, tmp, "baseline", baseline)
    b = measure_kernels(tool, tmp, "division", division)
    code, out = run(tool, "compare", a, b)
    expect(code == 1, f"an extra division per pair must be a regression (exit 1), got exit {code}")
    for kernel in ("probe_forces_kernel", "probe_forces_listed_kernel"):
        rows = {r[1]: r for r in table_rows(out) if r[0].endswith(kernel)}
        # One more per inlined copy of the pair body (the cell search inlines it at each of its
        # visiting loops), each with its call to the division's slow path.
        for metric in ("fchk", "slow_path_calls"):
            expect(metric in rows and rows[metric][6] == "COUNTER CHANGED"
                   and int(rows[metric][3]) > int(rows[metric][2]), f"{kernel}: more {metric} must be flagged")


def case_kernels_spill(tool, tmp, baseline, _again, _division, spill):
    a = measure_kernels(tool, tmp, "baseline", baseline)
    b = measure_kernels(tool, tmp, "spill", spill)
    code, out = run(tool, "compare", a, b)
    expect(code == 1, f"a spill must be a regression (exit 1), got exit {code}")
    for kernel in ("probe_forces_kernel", "probe_forces_listed_kernel"):
        rows = {r[1]: r for r in table_rows(out) if r[0].endswith(kernel)}
        expect("stl" in rows and rows["stl"][6] == "COUNTER CHANGED" and int(rows["stl"][3]) > int(rows["stl"][2]),
               f"{kernel}: more local stores (spills) must be flagged")
        expect("stack" in rows and rows["stack"][6] == "COUNTER CHANGED", f"{kernel}: the stack frame must be flagged")


def case_compare_rules(tool, tmp):
    def csv(name, rows):
        path = os.path.join(tmp, name)
        with open(path, "w") as f:
            f.write("subject,metric,value\n" + "".join(f"{s},{m},{v}\n" for s, m, v in rows))
        return path

    base = csv("base.csv", [("scene", "instructions_forces", "1000000"), ("k", "registers", "40"),
                            ("k", "sass_instructions", "1000"), ("compiler", "CUDA", "13.0.88")])
    cases = [  # (candidate rows, expected exit, expected verdict of the row that moved)
        ([("scene", "instructions_forces", "1004000")], 0, "SAME"),           # +0.4%: within 0.5%
        ([("scene", "instructions_forces", "1006000")], 1, "SLOWER"),         # +0.6%
        ([("scene", "instructions_forces", "900000")], 0, "FASTER"),
        ([("k", "registers", "41")], 1, "COUNTER CHANGED"),                   # registers exact
        ([("k", "registers", "39")], 1, "COUNTER CHANGED"),
        ([("k", "sass_instructions", "1020")], 0, None),                      # +2%: within 3%
        ([("k", "sass_instructions", "1040")], 1, "SLOWER"),
        ([("compiler", "CUDA", "13.1.0")], 1, "COUNTER CHANGED"),             # another compiler
        ([("other", "registers", "40")], 3, None),                            # nothing comparable
    ]
    for k, (rows, want_code, want_verdict) in enumerate(cases):
        cand = csv(f"cand{k}.csv", rows)
        code, out = run(tool, "compare", base, cand)
        expect(code == want_code, f"{rows}: exit {code}, expected {want_code}")
        if want_verdict:
            got = table_rows(out)
            expect(len(got) == 1 and got[0][6] == want_verdict, f"{rows}: expected {want_verdict}")
    code, _ = run(tool, "compare", base, os.path.join(tmp, "missing.csv"))
    expect(code == 2, f"a missing result must be a setup error (exit 2), got {code}")


CASES = {"host-clean": case_host_clean, "host-extra-work": case_host_extra_work, "kernels-clean": case_kernels_clean,
         "kernels-division": case_kernels_division, "kernels-spill": case_kernels_spill,
         "compare-rules": case_compare_rules}

if __name__ == "__main__":
    if len(sys.argv) < 3 or sys.argv[1] not in CASES:
        print(__doc__)
        sys.exit(2)
    with tempfile.TemporaryDirectory() as tmp:
        try:
            CASES[sys.argv[1]](sys.argv[2], tmp, *sys.argv[3:])
        except Failed as e:
            print(f"FAILED: {e}")
            sys.exit(1)
    print("passed")
