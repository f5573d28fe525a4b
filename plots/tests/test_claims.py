"""docs/results.md's claims table is what plots/claims.py makes of the committed results; a result is
marked STALE once solver/ changes after its commit; a shallow clone cannot tell, and says so
without failing. Run by ctest (`make test`)."""
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import claims  # noqa: E402

REPO = claims.REPO


def git(repo, *args):
    return subprocess.run(["git", "-C", str(repo), *args], check=True, capture_output=True, text=True).stdout.strip()


class ResultsPageTable(unittest.TestCase):
    def test_results_page_table_is_the_generated_one(self):
        generated, hist = claims.table()
        ok, message = claims.check(claims.DOC.read_text(), generated, hist)
        self.assertTrue(ok, message)

    def test_write_puts_the_table_between_the_markers_and_check_then_passes(self):
        with tempfile.TemporaryDirectory() as t:
            page = Path(t) / "results.md"
            page.write_text(f"before\n{claims.BEGIN}\nan old table\n{claims.END}\nafter\n")
            self.assertEqual(claims.main(["--check", "--doc", str(page)]), 1)
            self.assertEqual(claims.main(["--write", "--doc", str(page)]), 0)
            text = page.read_text()
            self.assertTrue(text.startswith("before\n") and text.endswith("after\n"), text[:200])
            self.assertNotIn("an old table", text)
            self.assertEqual(claims.main(["--check", "--doc", str(page)]), 0)

    def test_a_page_without_markers_is_refused_by_name(self):
        with tempfile.TemporaryDirectory() as t:
            page = Path(t) / "results.md"
            page.write_text("no table here\n")
            with self.assertRaises(SystemExit) as e:
                claims.main(["--write", "--doc", str(page)])
            self.assertIn("results.md lacks the markers", str(e.exception.code))

    def test_every_claim_has_a_row_and_a_verdict(self):
        generated, _ = claims.table()
        rows = [ln for ln in generated.splitlines() if ln.startswith("| ") and not ln.startswith(("| where", "| ---"))]
        self.assertGreaterEqual(len(rows), len(claims.load_spec()))
        for row in rows:
            self.assertTrue(any(f"**{v}**" in row for v in claims.VERDICTS), row)

    def test_a_changed_figure_fails_the_check(self):
        generated, hist = claims.table()
        readme = f"intro\n{claims.BEGIN}\n{generated}{claims.END}\n"
        self.assertTrue(claims.check(readme, generated, hist)[0])
        changed = readme.replace("| 1.", "| 9.", 1) if "| 1." in readme else readme.replace("x ", "y ", 1)
        self.assertNotEqual(changed, readme)
        self.assertFalse(claims.check(changed, generated, hist)[0])
        # Without history only the 'current?' column is spared, never the figures.
        no_history = (None, "shallow clone")
        self.assertFalse(claims.check(changed, generated, no_history)[0])
        other_marks = readme.replace("**STALE**", "yes (was stale)").replace("| yes |", "| unknown (shallow clone) |")
        self.assertTrue(claims.check(other_marks, generated, no_history)[0])

    def test_verdicts_are_declared_ones(self):
        for c in claims.load_spec():
            for r in c["rule"]:
                self.assertIn(r["verdict"], claims.VERDICTS, c["id"])


class OneRowPerClaim(unittest.TestCase):
    def test_a_current_result_is_shown_before_a_stale_one_listed_first(self):
        stale = ["Figure 4", "claim", "1.34%", "NVIDIA H200", "92b8249", claims.STALE, "**holds**", "why"]
        current = ["Figure 4", "claim", "0.70%", "NVIDIA H100", "f5f90d3", "yes", "**holds**", "why"]
        self.assertIs(claims.current_first([stale, current]), current)
        self.assertIs(claims.current_first([current, stale]), current)
        other_stale = stale[:2] + ["2.0%"] + stale[3:]
        self.assertIs(claims.current_first([stale, other_stale]), stale)


class BenchmarkLogs(unittest.TestCase):
    def test_both_layouts_of_benchmarks_txt(self):
        old = ("== sphbench-base simulate dsph-dambreak (repetition 1)\ntime per step: median 4.355 ms (quartiles)\n"
               "== sphbench simulate dsph-dambreak (repetition 1)\ntime per step: median 3.536 ms (quartiles)\n")
        new = ("== sphbench simulate dsph-dambreak --set dp=0.0028 --steps 300 --warmup 20 --backend cuda --quiet --out x\n"
               "scene dsph-dambreak\ntime per step: median 13.488 ms (quartiles 1 to 2)\n")
        self.assertEqual(claims.ours_per_step(old), {"dsph-dambreak": 3.536})
        self.assertEqual(claims.ours_per_step(new), {"dsph-dambreak --set dp=0.0028": 13.488})
        # Since the summary leads with the whole run, the window's line says so (issue 25).
        windowed = ("== sphbench simulate dsph-dambreak --steps 300 --warmup 20 --backend cuda --quiet --out x\n"
                    "whole run: 0.500 s wall, 62.1 s per simulated second\n"
                    "time per step in the window: median 1.135 ms (quartiles 1 to 2)\n")
        self.assertEqual(claims.ours_per_step(windowed), {"dsph-dambreak": 1.135})

    def test_a_folder_of_make_reference_names_its_commit(self):
        with tempfile.TemporaryDirectory() as t:
            folder = Path(t)
            (folder / "reference-state.json").write_text(
                '{"items": {"benchmarks": {"commit": "0123456789", "dirty": "clean"}}}')
            self.assertEqual(claims.recorded(folder, "benchmarks")["git_commit"], "0123456789")
            self.assertIsNone(claims.recorded(folder, "fig3"))


class Staleness(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.repo = Path(self.tmp.name) / "repo"
        self.repo.mkdir()
        git(self.repo, "init", "-q")
        git(self.repo, "config", "user.email", "t@example.org")
        git(self.repo, "config", "user.name", "t")

    def tearDown(self):
        self.tmp.cleanup()

    def commit(self, path, text):
        f = self.repo / path
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text(text)
        git(self.repo, "add", "-A")
        git(self.repo, "commit", "-qm", path)
        return git(self.repo, "rev-parse", "HEAD")

    def test_stale_once_the_solver_changes_after_the_result(self):
        self.commit("solver/a.cpp", "1")
        measured = self.commit("README.md", "results")  # the build the results came from
        hist = claims.history(self.repo)
        self.assertEqual(claims.freshness(measured, hist, self.repo), "yes")
        self.assertEqual(claims.freshness(measured[:7], hist, self.repo), "yes")
        self.commit("plots/x.py", "a plot change is no solver change")
        self.assertEqual(claims.freshness(measured, claims.history(self.repo), self.repo), "yes")
        (self.repo / "solver" / "a.cpp").write_text("2")  # being changed: stale already, as it will be once committed
        self.assertEqual(claims.freshness(measured, claims.history(self.repo), self.repo), claims.STALE)
        self.commit("solver/a.cpp", "2")
        mark = claims.freshness(measured, claims.history(self.repo), self.repo)
        self.assertIn("**STALE**", mark)
        self.assertEqual(mark, claims.STALE)
        self.assertIn("not in history", claims.freshness("0123456", claims.history(self.repo), self.repo))

    def test_a_shallow_clone_cannot_tell_and_says_so(self):
        self.commit("solver/a.cpp", "1")
        measured = self.commit("README.md", "results")
        self.commit("solver/a.cpp", "2")
        clone = Path(self.tmp.name) / "shallow"
        subprocess.run(["git", "clone", "-q", "--depth", "1", f"file://{self.repo}", str(clone)], check=True)
        hist = claims.history(clone)
        self.assertIsNone(hist[0])
        self.assertIn("unknown (shallow clone)", claims.freshness(measured, hist, clone))
        self.assertIn("unknown", claims.freshness(measured, claims.history(Path(self.tmp.name)), Path(self.tmp.name)))


if __name__ == "__main__":
    unittest.main(verbosity=1)
