"""Tests for the plot scripts, without pytest: python3 plots/tests/test_plots.py
Writes a synthetic results folder laid out as `sphbench run` writes it, with update times
chosen so every number fig4.py prints is known in advance.
"""
import re
import subprocess
import sys
import tempfile
import traceback
from pathlib import Path

PLOTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(PLOTS))
import sphplot  # noqa: E402

STEPS = 50
META = {"git_commit": "0123456789abcdef0123456789abcdef01234567", "git_dirty": "dirty", "backend": "host",
        "devices": "host", "cuda": "none", "host": "ci", "date": "2025-01-01T00:00:00Z",
        "command_line": "sphbench run experiments/fig4.toml", "spec": "experiments/fig4.toml",
        "spec_hash": "abc123", "scale": "0.01", "reduced_scale": "yes"}


def update_times(base, bumps):
    """base everywhere, except {step: value}; steps are numbered 1..STEPS."""
    return [bumps.get(k, base) for k in range(1, STEPS + 1)]


# Armadillo: one 2.5% rise at step 20 and back (2.439%) at 21, inside the paper's 3%.
# Bunny: a 2% rise at step 40 and back at 41, both outside the paper's 1%.
RUNS = {"armadillo_r0": ("armadillo", update_times(10.0, {20: 10.25})),
        "bunny_r0": ("bunny", update_times(20.0, {40: 20.4}))}


def expected(times):
    pct = [abs(b - a) / a * 100 for a, b in zip(times, times[1:])]
    return max(pct), pct


def write_csv(path, meta, header, rows):
    with open(path, "w") as f:
        f.writelines(f"# {k}: {v}\n" for k, v in meta.items())
        f.write(",".join(header) + "\n")
        f.writelines(",".join(map(str, r)) + "\n" for r in rows)


def make_results(folder):
    folder.mkdir(parents=True)
    step_cols = ("step,time,dt,fluid,boundary,out_of_domain,kinetic_energy,max_speed,min_density,max_density,"
                 "neighbour_list_ms,forces_ms,integrate_ms,diagnostics_ms,exchange_ms,migrate_ms,balance_ms,"
                 "update_ms,step_ms").split(",")
    run_cols = ["run_id", "scene", "repetition", "backend", "device", "particles", "fluid", "boundary", "steps",
                "update_ms_median", "step_ms_median", "mparticle_steps_per_s", "steps_file", "set.particles"]
    rows = []
    for run_id, (scene, times) in RUNS.items():
        steps = [[k, k * 1e-4, 1e-4, 900, 100, 0, 1.0, 0.5, 990, 1010, 1, t * 0.8, t * 0.2, 0.1, 0, 0, 0, t, t + 1.1]
                 for k, t in enumerate(times, start=1)]
        write_csv(folder / f"{run_id}_steps.csv", META, step_cols, steps)
        t_med = sorted(times)[len(times) // 2]
        rows.append([run_id, scene, 0, "host", "host", 1000, 900, 100, STEPS, t_med, t_med + 1.1, 0.1,
                     f"{run_id}_steps.csv", 1000])
    write_csv(folder / "runs.csv", META, run_cols, rows)


def run_fig4(*args):
    return subprocess.run([sys.executable, str(PLOTS / "fig4.py"), *map(str, args)],
                          capture_output=True, text=True)


def test_figure_and_summary(tmp):
    results, out = tmp / "results" / "fig4", tmp / "out"
    make_results(results)
    p = run_fig4("--results", results, "--out", out)
    assert p.returncode == 0, f"fig4.py failed:\n{p.stderr}"
    for ext in ("png", "pdf"):
        f = out / f"fig4.{ext}"
        assert f.is_file() and f.stat().st_size > 0, f"{f} missing or empty"
    assert not list(out.glob(".*.tmp")), "a temporary file was left behind"
    for run_id, (scene, times) in RUNS.items():
        line = next((l for l in p.stdout.splitlines() if f"{scene} run {run_id} " in l), None)
        assert line, f"no summary line for {run_id} in:\n{p.stdout}"
        largest, pct = expected(times)
        got = float(re.search(r"largest ([0-9.]+)%", line).group(1))
        assert abs(got - largest) < 1e-3, f"{run_id}: printed largest {got}, expected {largest:.3f}"
        bound = {"armadillo": 3.0, "bunny": 1.0}[scene]
        within = sum(x <= bound for x in pct)
        assert f"within the paper's {bound:g}%: {within}/{len(pct)} " in line, line
    assert "REDUCED SCALE on the host backend" in p.stdout


def test_missing_folder_is_one_sentence(tmp):
    p = run_fig4("--results", tmp / "nowhere", "--out", tmp / "out2")
    assert p.returncode != 0, "a missing results folder must fail"
    err = p.stderr.strip()
    assert "Traceback" not in err and len(err.splitlines()) == 1, f"expected one line, got:\n{err}"
    assert err.endswith(".") and err.count(". ") == 0, f"expected one sentence: {err}"
    assert "make fig4" in err and "nowhere" in err, err
    assert not (tmp / "out2").exists(), "nothing should be written on failure"


def test_missing_step_file_names_it(tmp):
    results = tmp / "broken"
    make_results(results)
    (results / "bunny_r0_steps.csv").unlink()
    p = run_fig4("--results", results, "--out", tmp / "out3")
    assert p.returncode != 0 and "bunny_r0_steps.csv" in p.stderr and "Traceback" not in p.stderr, p.stderr


def test_metadata_reader_and_label(tmp):
    f = tmp / "m.csv"
    # The writer quotes a cell holding '#'; it must survive as data, not be cut as a comment.
    f.write_text('# git_commit: abcdef1234567\n# note: a: b\nrun_id,label\n1,"x # y"\n')
    df, meta = sphplot.read_csv_with_metadata(f)
    assert meta == {"git_commit": "abcdef1234567", "note": "a: b"}, meta
    assert df["label"].tolist() == ["x # y"], df
    runs = sphplot.pd.DataFrame({"device": ["NVIDIA H100 80GB HBM3"]})
    label = sphplot.provenance_label({"git_commit": "abcdef1234567", "git_dirty": "clean", "backend": "cuda",
                                      "scale": "full", "reduced_scale": "no"}, runs)
    assert label == "NVIDIA H100 80GB HBM3 | cuda backend | scale full | commit abcdef1", label
    label = sphplot.provenance_label({"cuda": "NVIDIA H200 | driver 13.0, runtime 13.0", "git_dirty": "dirty"})
    assert label.startswith("NVIDIA H200 |") and "(dirty)" in label, label


def main():
    tests = [v for k, v in globals().items() if k.startswith("test_")]
    failed = 0
    with tempfile.TemporaryDirectory() as d:
        for i, t in enumerate(tests):
            tmp = Path(d) / f"t{i}"
            tmp.mkdir()
            try:
                t(tmp)
                print(f"PASS {t.__name__}")
            except Exception:
                failed += 1
                print(f"FAIL {t.__name__}\n{traceback.format_exc()}")
    print(f"{len(tests) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
