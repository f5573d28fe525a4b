"""docs/results.md's tables of measured figures (all but the claims table) are what
plots/results_tables.py makes of the committed results; a changed figure, a missing block or a
missing results folder is caught; the captions carry claims.py's STALE mark. Run by ctest
(`make test`, test results_tables)."""
import contextlib
import io
import re
import shutil
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import claims  # noqa: E402
import results_tables as rt  # noqa: E402

GENERATED, HIST = rt.blocks()


def page(blocks):
    return "intro\n" + "".join(f"{rt.begin(n)}\n{b}{rt.end(n)}\n\nprose\n" for n, b in blocks.items())


class ResultsPage(unittest.TestCase):
    def test_results_page_tables_are_the_generated_ones(self):
        ok, message = rt.check(rt.DOC.read_text(), GENERATED, HIST)
        self.assertTrue(ok, message)

    def test_every_declared_table_has_its_markers_in_the_page(self):
        have = rt.doc_blocks(rt.DOC.read_text())
        for t in rt.load_spec():
            self.assertIn(t["name"], have, t["name"])

    def test_the_claims_block_is_left_to_claims_py(self):
        text = rt.DOC.read_text()
        new = rt.write(text, GENERATED)
        self.assertEqual(claims.doc_block(text), claims.doc_block(new))


class Check(unittest.TestCase):
    def test_a_changed_figure_fails_the_check(self):
        doc = page(GENERATED)
        self.assertTrue(rt.check(doc, GENERATED, HIST)[0])
        # One digit of one figure in one table, e.g. '| 3.056 |' -> '| 4.056 |'.
        m = re.search(r"\| (\d)\.(\d+) \|", rt.doc_blocks(doc)["dualsphysics"])
        self.assertIsNotNone(m)
        wrong = m.group(0).replace(f"| {m.group(1)}.", f"| {(int(m.group(1)) + 1) % 10}.", 1)
        changed = doc.replace(m.group(0), wrong, 1)
        self.assertNotEqual(changed, doc)
        ok, message = rt.check(changed, GENERATED, HIST)
        self.assertFalse(ok)
        self.assertIn("dualsphysics", message)
        # Without git history only the 'current?' marks are spared, never the figures.
        self.assertFalse(rt.check(changed, GENERATED, (None, "shallow clone"))[0])

    def test_a_changed_figure_in_the_real_page_fails(self):
        text = rt.DOC.read_text()
        block = rt.doc_blocks(text)["accuracy-gpu"]
        m = re.search(r"\| 0\.(\d)(\d+) \(", block)
        self.assertIsNotNone(m)
        changed = text.replace(m.group(0), f"| 0.{(int(m.group(1)) + 1) % 10}{m.group(2)} (", 1)
        self.assertFalse(rt.check(changed, GENERATED, HIST)[0])

    def test_stale_marks_may_differ_only_without_history(self):
        doc = page(GENERATED)
        other = re.sub(r"(current\?: ).*$", r"\1yes (was marked otherwise)", doc, flags=re.M)
        self.assertNotEqual(other, doc)
        if HIST[0] is not None:
            self.assertFalse(rt.check(other, GENERATED, HIST)[0])
        self.assertTrue(rt.check(other, GENERATED, (None, "shallow clone"))[0])

    def test_a_missing_block_and_an_undeclared_one_fail(self):
        blocks = dict(GENERATED)
        blocks.pop("fig3")
        ok, message = rt.check(page(blocks), GENERATED, HIST)
        self.assertFalse(ok)
        self.assertIn("table:fig3:begin", message)
        blocks = dict(GENERATED, stray="a hand-typed table\n")
        self.assertFalse(rt.check(page(blocks), GENERATED, HIST)[0])

    def test_write_fills_the_markers_and_check_then_passes(self):
        with tempfile.TemporaryDirectory() as t:
            doc = Path(t) / "results.md"
            doc.write_text(page({n: "an old table | 1.0 |\n" for n in GENERATED}))
            with contextlib.redirect_stdout(io.StringIO()) as out:
                self.assertEqual(rt.main(["--check", "--doc", str(doc)]), 1)
                self.assertEqual(rt.main(["--write", "--doc", str(doc)]), 0)
            self.assertIn("differs", out.getvalue())
            text = doc.read_text()
            self.assertNotIn("an old table", text)
            self.assertTrue(text.startswith("intro\n") and text.count("prose\n") == len(GENERATED))
            self.assertEqual(rt.main(["--check", "--doc", str(doc)]), 0)

    def test_write_refuses_a_page_without_the_markers(self):
        with tempfile.TemporaryDirectory() as t:
            doc = Path(t) / "results.md"
            doc.write_text("no tables\n")
            with self.assertRaises(SystemExit):
                rt.main(["--write", "--doc", str(doc)])


class Blocks(unittest.TestCase):
    def test_each_table_names_folder_gpu_commit_and_freshness(self):
        for name, text in GENERATED.items():
            self.assertTrue(text.startswith(rt.GENERATED.format(name=name)), name)
            if "**No committed result**" in text or "**No result**" in text:
                continue
            lines = [ln for ln in text.splitlines() if ln.startswith("- `results/reference/")]
            self.assertTrue(lines, name)
            for ln in lines:
                self.assertRegex(ln, r": .+, commit (\w{7}|not recorded)( \(dirty\))?; current\?: ", name)
            self.assertIn("| --- |", text, name)

    def test_results_of_a_stale_commit_are_marked(self):
        if HIST[0] is None:
            self.skipTest(f"no history ({HIST[1]})")
        for name in ("whole-run", "fig3", "multi-gpu"):
            src = [ln for ln in GENERATED[name].splitlines() if "current?:" in ln]
            for ln in src:
                commit = re.search(r"commit (\w{7})", ln).group(1)
                self.assertIn(claims.freshness(commit, HIST), ln)

    def test_a_missing_folder_is_said_instead_of_a_table(self):
        with tempfile.TemporaryDirectory() as t:
            ref = Path(t) / "reference"
            shutil.copytree(rt.REFERENCE / "h200" / "fig3", ref / "h200" / "fig3")
            blocks, _ = rt.blocks(ref)
            self.assertIn("| --- |", blocks["fig3"])
            self.assertIn("**No result**", blocks["fig4"])
            self.assertIn("results/reference/h200/fig4", blocks["fig4"])
            self.assertNotIn("| --- |", blocks["fig4"])

    def test_absent_results_say_so(self):
        absent = [t for t in rt.load_spec() if "absent" in t]
        self.assertTrue(absent)
        for t in absent:
            self.assertIn("**No committed result**", GENERATED[t["name"]])
            self.assertNotIn("| --- |", GENERATED[t["name"]])


class Parsers(unittest.TestCase):
    def test_sphbench_summaries(self):
        text = ("== sphbench simulate dsph-dambreak --verlet --cells-per-support 2 --skin 0.05 --steps 300 --warmup 20\n"
                "scene dsph-dambreak on NVIDIA H200 (GPU 0) (cuda): 1037440 particles (882524 fluid, 154916 boundary)\n"
                "300 steps recorded after 20 warm-up, simulated time 0.01446 s\n"
                "time per step: median 1.137 ms (quartiles 1.133 to 1.140), mean 1.182 ms; update (forces + "
                "integration) 1.095 ms\n"
                "Verlet lists: rebuilt in 6 of the 300 recorded steps\n"
                "memory: 1182 bytes per particle (1169.4 MiB allocated)\n"
                "== sphbench simulate armadillo --set particles=2980000 --steps 300\n"
                "time per step: median 10.140 ms (quartiles 10.122 to 10.158); update (forces + integration) 9.182 ms\n")
        a, b = rt.sphbench_summaries(text)
        self.assertEqual((a["median"], a["mean"], a["rebuilds"], a["recorded"], a["bytes"], a["particles"]),
                         (1.137, 1.182, 6, 300, 1182, 1037440))
        self.assertEqual(rt.case_of(a["case"]), "dsph-dambreak --verlet --cells-per-support 2 --skin 0.05")
        self.assertEqual(b["median"], 10.140)
        self.assertEqual(rt.case_of(b["case"]), "armadillo --set particles=2980000")

    def test_whole_run_line(self):
        r = rt.whole_run_line(
            "[1/1] dambreak-4.04M-wendland-lists: 4040034 particles on NVIDIA H200 (GPU 0), 11303 steps to t = 0.3 s "
            "(stopped by end_time), 79.2 s, 264.1 s per simulated second; window of 11303 steps: update 5.004 ms\n"
            "    Verlet lists: 1287 rebuilds in 11303 steps; rebuild step 21.887 ms, listed step 5.095 ms (means)\n")
        self.assertEqual((r["steps"], r["s_per_sim_s"], r["list_rebuilds"], r["listed_step_ms"]),
                         (11303, 264.1, 1287, 5.095))

    def test_dualsphysics_whole_events_beside_ours_give_the_ratio_per_case(self):
        """With whole-run-dualsphysics/ beside whole-run/, each of our dam-break rows gets
        DualSPHysics' time for its case and the ratio; the claim's metric takes its fastest case."""
        with tempfile.TemporaryDirectory() as tmp:
            machine = Path(tmp) / "reference" / "h100"
            shutil.copytree(rt.REFERENCE / "h100" / "whole-run", machine / "whole-run")
            (machine / "whole-run-dualsphysics").mkdir()
            cols = "case np kernel cellmode steps runtime_per_phys_s gpu_mem_mib rc".split()
            rows = [["dp0045_cubic", "1048576", "CubicSpline", "Full", "24000", "117.0", "160", "0"],
                    ["dp0045_wendland_half", "1048576", "Wendland", "Half", "24491", "78.0", "180", "0"],
                    ["dp0028_cubic", "4037948", "CubicSpline", "Full", "1", "1.0", "600", "1"]]  # failed: ignored
            (machine / "whole-run-dualsphysics" / "summary-tmax-1.0.tsv").write_text(
                "\n".join("\t".join(r) for r in [cols, *rows]) + "\n")
            table = rt.whole_run(machine / "whole-run")
            ratio = table.header.index("DualSPHysics over ours")
            by_run = {r[0]: r for r in table.rows}
            ours = float(by_run["dambreak-1.04M-wendland-lists"][table.header.index("s per simulated second")].strip("*"))
            self.assertEqual(by_run["dambreak-1.04M-wendland-lists"][ratio], f"{78.0 / ours:.2f}x")
            self.assertEqual(by_run["armadillo-2980K-lists"][ratio], "-")
            self.assertIn("180 bytes a particle", table.notes[0])
            v = claims.whole_run_vs_dualsphysics(machine)
            self.assertAlmostEqual(v["fastest"], 78.0)
            cubic = float(by_run["dambreak-1.04M-cubic-lists"][table.header.index("s per simulated second")].strip("*"))
            self.assertAlmostEqual(v["vs_fastest"], 78.0 / max(ours, cubic), places=2)
            with self.assertRaises(claims.Missing):
                claims.whole_run_vs_dualsphysics(machine, size="4.04M", tmax="0.3")
            # With the 4.04M event there too, each size is judged by its own DualSPHysics cases only.
            shutil.copy(machine / "whole-run" / "dambreak-1.04M-wendland-lists.runs.csv",
                        machine / "whole-run" / "dambreak-4.04M-wendland-lists.runs.csv")
            (machine / "whole-run-dualsphysics" / "summary-tmax-0.3.tsv").write_text(
                "\t".join(cols) + "\n" + "\t".join(["dp0028_wendland_half", "4037948", "Wendland", "Half", "9000",
                                                      "390.0", "700", "0"]) + "\n")
            self.assertAlmostEqual(claims.whole_run_vs_dualsphysics(machine, size="4.04M", tmax="0.3")["fastest"], 390.0)
            self.assertAlmostEqual(claims.whole_run_vs_dualsphysics(machine)["fastest"], 78.0)

    def test_a_folder_of_several_builds_names_the_build_of_each_row(self):
        """A results folder that `make reference` refilled in part (some runs rerun, some not) names
        each row's build in its "from" cell; a folder of one build does not."""
        def stamp(path, digit):
            path.write_text(re.sub(r"(# git_commit: )[0-9a-f]+", r"\g<1>" + digit * 40, path.read_text()))

        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp) / "reference" / "h100" / "whole-run"
            shutil.copytree(rt.REFERENCE / "h100" / "whole-run", folder)
            csvs = sorted(folder.glob("*.runs.csv"))
            for p in csvs:  # one build everywhere first
                stamp(p, "1")
            table = rt.whole_run(folder)
            src = table.header.index("from")
            self.assertTrue(all(" at " not in r[src] for r in table.rows))
            stamp(csvs[0], "2")
            table = rt.whole_run(folder)
            commits = {r[src].split("`")[1]: r[src].rsplit(" at ", 1)[-1] for r in table.rows}
            self.assertEqual(commits[csvs[0].name], "2222222")
            self.assertEqual({c for n, c in commits.items() if n != csvs[0].name}, {"1111111"})


if __name__ == "__main__":
    unittest.main(verbosity=1)
