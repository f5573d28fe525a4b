"""tools/reference.py (`make reference`) against fake GPU programs: the plan, the budget, the
state that lets a second call resume, the harness's freshness check reused, the archive for the
run tool, and the one-sentence refusal without a GPU. No GPU, no solver build needed."""
import json
import os
import subprocess
import sys
import tarfile
import tempfile
import unittest
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "tools" / "reference.py"

FAKE_SMI = """#!/bin/sh
case "$*" in
  *topo*) echo "GPU0 X";;
  *noheader*) i=0; while [ $i -lt ${FAKE_GPUS:-1} ]; do echo "NVIDIA H200, 580.159.04, 143771 MiB"; i=$((i+1)); done;;
  *) echo "name, driver_version, memory.total"; echo "NVIDIA H200, 580.159.04, 143771 MiB";;
esac
"""
# sphbench: `run SPEC --out D` writes D/<spec>/runs.csv unless it is there (then "up to date", as
# the harness says); `run --dry-run` lists run ids; `simulate SCENE --out D`; `stability SPEC --out D`.
FAKE_SPHBENCH = r"""#!/bin/bash
# version 1
cmd=$1; shift
out=""; spec=""; scene=""; dry=0
while [ $# -gt 0 ]; do
  case "$1" in --out) out=$2; shift;; --dry-run) dry=1;; *.toml) spec=$(basename "$1" .toml);; esac
  [ -z "$scene" ] && scene=$1
  shift
done
echo "$cmd $spec" >> "$FAKE_CALLS"
case $cmd in
run)
  if [ $dry = 1 ]; then for n in 1 2 4; do echo "armadillo-1034K_balancer-simple_devices-$n armadillo 1000 20"; done; exit 0; fi
  if [ -f "$out/$spec/runs.csv" ]; then echo "$spec: up to date (use --force to run again)"; exit 0; fi
  mkdir -p "$out/$spec"; printf '# git_commit: abc\nrun_id\nx\n' > "$out/$spec/runs.csv"; echo "$spec: 1 runs";;
simulate) mkdir -p "$out"; echo "step" > "$out/${scene}_steps.csv"; echo "time per step: median 1.0 ms";;
stability) mkdir -p "$out/$spec"; echo "run_id" > "$out/$spec/summary.csv";;
esac
"""
FAKE_TESTS = "#!/bin/sh\necho '[  PASSED  ] 4 tests.'\n"
FAKE_BENCH = """#!/bin/sh
for a in "$@"; do case $a in --benchmark_out=*) echo '{}' > "${a#--benchmark_out=}";; esac; done
"""


class ReferenceRuns(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        t = Path(self.tmp.name)
        self.bin, self.root, self.out = t / "bin", t / "reference", t / "out"
        self.bin.mkdir()
        for name, text in {"nvidia-smi": FAKE_SMI, "sphbench": FAKE_SPHBENCH, "sphbench-f64": FAKE_SPHBENCH,
                           "sph_tests": FAKE_TESTS, "sph_bench": FAKE_BENCH, "sph_skip_bench": FAKE_BENCH}.items():
            (self.bin / name).write_text(text)
            (self.bin / name).chmod(0o755)
        self.calls = t / "calls.txt"
        self.env = {k: v for k, v in os.environ.items() if not k.startswith(("REFERENCE_", "PLAN", "DSPH", "OUT"))}
        self.env.update(PATH=f"{self.bin}:/usr/bin:/bin", FAKE_CALLS=str(self.calls), OUT=str(self.out),
                        SPH_GIT_COMMIT="0123456789abcdef", SPH_GIT_DIRTY="clean")

    def tearDown(self):
        self.tmp.cleanup()

    def reference(self, *args, **env):
        e = dict(self.env, **env)
        p = subprocess.run([sys.executable, str(SCRIPT), "--root", str(self.root), "--skip", "figures", "figures-multi",
                            *args], env=e, capture_output=True, text=True, cwd=REPO)
        return p.returncode, p.stdout, p.stderr

    def state(self, machine="h200"):
        return json.loads((self.root / machine / "reference-state.json").read_text())["items"]

    def test_without_a_gpu_it_says_so_and_fails(self):
        (self.bin / "nvidia-smi").unlink()
        rc, out, err = self.reference()
        self.assertNotEqual(rc, 0)
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertIn("no GPU here", err)
        self.assertFalse(self.root.exists())
        rc, out, _ = self.reference("--dry-run")  # the plan still prints
        self.assertEqual(rc, 0)
        self.assertIn("assumed: no GPU here", out)
        self.assertIn("estimate:", out)

    def test_budget_then_resume_then_nothing_left(self):
        rc, out, err = self.reference(REFERENCE_BUDGET_S="100")
        self.assertEqual(rc, 0, out + err)
        self.assertIn("estimate:", out.splitlines()[0 if "estimate" in out.splitlines()[0] else -1] + out)
        self.assertIn("left for the next call", out)
        first = self.state()
        self.assertIn("fig4", first)           # 50 s: fits
        self.assertNotIn("fig3", first)        # 200 s: over the budget
        self.assertNotIn("multi-gpu", first)   # one GPU: not planned
        self.assertTrue((self.root / "h200" / "fig4" / "runs.csv").is_file())
        self.assertTrue((self.root / "h200" / "reference-runs.md").is_file())
        with tarfile.open(self.out / "reference.tar.gz") as tar:  # what the run tool brings back
            self.assertIn("h200/fig4/runs.csv", tar.getnames())

        rc, out, err = self.reference()
        self.assertEqual(rc, 0, out + err)
        self.assertRegex(out, r"fig4 +up to date")
        self.assertIn("fig3", self.state())
        self.assertEqual(self.state()["fig4"]["date"], first["fig4"]["date"])  # not run again
        with tarfile.open(self.out / "reference.tar.gz") as tar:  # this call's files only
            names = tar.getnames()
        self.assertIn("h200/fig3/runs.csv", names)
        self.assertIn("h200/reference-state.json", names)
        self.assertNotIn("h200/fig4/runs.csv", names)

        self.calls.unlink()
        rc, out, err = self.reference()
        self.assertEqual(rc, 0, out + err)
        self.assertIn("nothing left to run", out)
        self.assertFalse(self.calls.exists(), "a call with everything up to date ran a program")

    def test_whole_runs_come_one_run_at_a_time(self):
        rc, out, err = self.reference(REFERENCE_ONLY="whole-run-4.04M whole-run-4.04M-cells")
        self.assertEqual(rc, 0, out + err)
        folder = self.root / "h200" / "whole-run"
        ids = ["dambreak-4.04M-wendland-lists", "dambreak-4.04M-wendland-cells", "dambreak-4.04M-cubic-lists",
               "dambreak-4.04M-cubic-cells"]
        for rid in ids:
            self.assertTrue((folder / f"{rid}.runs.csv").is_file(), rid)
            self.assertIn(f"--only {rid}", (folder / f"{rid}.txt").read_text())
        self.assertEqual(self.calls.read_text().count("run whole-run"), len(ids))
        self.assertIn("whole-run-4.04M", self.state())
        self.assertNotIn("whole-run-1.04M", self.state())

    def test_a_runs_windows_replace_its_old_rows(self):
        sys.path.insert(0, str(SCRIPT.parent))
        import reference
        t = Path(self.tmp.name)
        steps = t / "steps.csv"
        # 100 steps of 0.01 s, a rebuild every 4th: 1 s simulated.
        steps.write_text("time,neighbour_list_ms,wall_ms,forces_ms\n" + "".join(
            f"{0.01 * (k + 1):.2f},{2.0 if k % 4 == 0 else 0.0},{3.0 if k % 4 == 0 else 1.0},0.5\n" for k in range(100)))
        windows = t / "windows.csv"
        windows.write_text("run,window_s\nother,0-1.0\nrun-a,0-1.0\n")
        reference.merge_windows(windows, "run-a", steps)
        reference.merge_windows(windows, "run-a", steps)
        lines = windows.read_text().splitlines()
        self.assertTrue(lines[0].startswith("run,window_s,steps,rebuilds"))
        self.assertIn("other,0-1.0", lines)
        whole = [ln for ln in lines if ln.startswith("run-a,0-1,")]
        self.assertEqual(len(whole), 1, lines)  # replaced, not added to
        self.assertTrue(whole[0].startswith("run-a,0-1,100,25,"), whole)  # the whole run, its step at t = 1.00 too
        self.assertTrue(any(ln.startswith("run-a,0.6-1,41,") for ln in lines), lines)  # the last window to the end

    def test_a_run_to_0_3_s_has_no_window_past_its_end(self):
        sys.path.insert(0, str(SCRIPT.parent))
        import reference
        t = Path(self.tmp.name)
        steps = t / "steps.csv"
        # 30 steps of 0.01 s, the last one just past the end time 0.3 s (as a run stops).
        steps.write_text("time,neighbour_list_ms,wall_ms,forces_ms\n" + "".join(
            f"{0.01 * (k + 1) + (1e-5 if k == 29 else 0):.5f},{2.0 if k % 4 == 0 else 0.0},1.0,0.5\n" for k in range(30)))
        windows = t / "windows.csv"
        reference.merge_windows(windows, "run-b", steps)
        rows = [ln.split(",")[:3] for ln in windows.read_text().splitlines()[1:]]
        self.assertEqual([r[1] for r in rows], ["0-0.05", "0.05-0.3", "0-0.3"], rows)
        self.assertEqual([r[2] for r in rows], ["4", "26", "30"], rows)

    def test_an_archive_over_the_limit_comes_back_in_parts(self):
        sys.path.insert(0, str(SCRIPT.parent))
        import reference
        d = Path(self.tmp.name) / "h200"
        (d / "whole-run").mkdir(parents=True)
        data = os.urandom(300_000)  # incompressible: the archive is about this large
        (d / "whole-run" / "a_steps.csv").write_bytes(data)
        target = self.out / "reference.tar.gz"
        limit = reference.ARCHIVE_PART_BYTES
        try:
            reference.ARCHIVE_PART_BYTES = 100_000
            reference.archive([d], target)
        finally:
            reference.ARCHIVE_PART_BYTES = limit
        parts = sorted(self.out.glob("reference.tar.gz.part*"))
        self.assertGreaterEqual(len(parts), 3)
        self.assertFalse(target.exists())
        joined = Path(self.tmp.name) / "joined.tar.gz"
        joined.write_bytes(b"".join(p.read_bytes() for p in parts))
        with tarfile.open(joined) as tar:
            self.assertEqual(tar.extractfile("h200/whole-run/a_steps.csv").read(), data)

    def test_a_new_binary_is_handed_to_the_harness_check(self):
        self.assertEqual(self.reference("--only", "fig4")[0], 0)
        fake = self.bin / "sphbench"
        fake.write_text(fake.read_text().replace("# version 1", "# version 2"))
        rc, out, err = self.reference("--only", "fig4")
        self.assertEqual(rc, 0, out + err)
        self.assertRegex(out, r"fig4 +\d+ s +to run")      # the stamp changed
        self.assertIn("up to date (use --force", out)      # and sphbench's own check decided
        self.assertEqual(self.state()["fig4"]["result"], "up to date (sphbench)")

    def test_several_gpus_add_the_multi_gpu_folder(self):
        rc, out, err = self.reference("--only", "multi-gpu", "fig10", FAKE_GPUS="2")
        self.assertEqual(rc, 0, out + err)
        self.assertTrue((self.root / "h200-x2" / "multi-gpu" / "runs.csv").is_file())
        self.assertIn("--only", " ".join(self.state("h200-x2")["multi-gpu"]["commands"]))  # no 4-device runs
        self.assertIn("devices-2", " ".join(self.state("h200-x2")["multi-gpu"]["commands"]))
        self.assertNotIn("devices-4", " ".join(self.state("h200-x2")["multi-gpu"]["commands"]))

    def test_dualsphysics_travels_recompressed_and_runs_from_there(self):
        import gzip
        src = Path(self.tmp.name) / "anchor"
        (src / "cases" / "dp0045_cubic").mkdir(parents=True)
        (src / "run.sh").write_text('#!/bin/bash\nH=$(dirname "$0"); mkdir -p "$1"\n'
                                    '[ -x "$H/DualSPHysics5.4_linux64" ] || exit 3\n'
                                    'cmp -s "$H/cases/dp0045_cubic/CaseDambreak.bi4" <(echo particles) || exit 4\n'
                                    'echo "case ms_per_step rc" > "$1/summary.txt"; echo "dp0045_cubic 3.9 0" >> "$1/summary.txt"\n')
        (src / "DualSPHysics5.4_linux64.gz").write_bytes(gzip.compress(b"#!/bin/sh\n"))
        (src / "cases" / "dp0045_cubic" / "CaseDambreak.bi4.gz").write_bytes(gzip.compress(b"particles\n"))
        dest = Path(self.tmp.name) / "dsph"
        p = subprocess.run([sys.executable, str(SCRIPT), "--pack-dsph", str(src), str(dest)], capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertEqual(sorted(f.name for f in dest.rglob("*.gz")), [])
        self.assertTrue((dest / "DualSPHysics5.4_linux64.xz").is_file())
        rc, out, err = self.reference("--only", "dualsphysics", DSPH=str(dest))
        self.assertEqual(rc, 0, out + err)
        self.assertIn("dp0045_cubic 3.9", (self.root / "h200" / "dualsphysics" / "summary.txt").read_text())

    def test_gpu_names(self):
        sys.path.insert(0, str(SCRIPT.parent))
        import reference
        self.assertEqual(reference.gpu_short_name("NVIDIA H200"), "h200")
        self.assertEqual(reference.gpu_short_name("NVIDIA H100 80GB HBM3"), "h100")
        self.assertEqual(reference.gpu_short_name("NVIDIA A100-SXM4-80GB"), "a100")
        self.assertEqual(reference.gpu_short_name("Tesla V100-PCIE-16GB"), "v100")


if __name__ == "__main__":
    unittest.main(verbosity=1)
