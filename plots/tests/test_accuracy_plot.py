"""Tests for plots/accuracy.py, without pytest: python3 plots/tests/test_accuracy_plot.py
Writes a synthetic results/accuracy folder whose Pareto front is known in advance.
"""
import subprocess
import sys
import tempfile
import traceback
from pathlib import Path

PLOTS = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(PLOTS))
import accuracy  # noqa: E402
import sphplot  # noqa: E402

META = {"git_commit": "0123456789abcdef0123456789abcdef01234567", "git_dirty": "clean", "backend": "host",
        "devices": "host", "cuda": "none", "date": "2025-01-01T00:00:00Z", "experiment": "accuracy",
        "command_line": "sphbench run experiments/accuracy.toml", "scale": "0.008", "reduced_scale": "yes"}

# (run_id, scene, wall_s, validation_s, error, secondary). Run time = wall_s - validation_s.
# Dam break: base (10 s, 0.10), fine (30 s, 0.05) and coarse (4 s, 0.30) are the front; cubic
# (12 s, 0.12) is beaten by base, cfl-0.1 (20 s, 0.10) ties base's error but is slower.
RUNS = [
    ("dambreak-base", "dambreak", 11.0, 1.0, 0.10, 0.08),
    ("dambreak-fine", "dambreak", 31.0, 1.0, 0.05, 0.06),
    ("dambreak-coarse", "dambreak", 4.5, 0.5, 0.30, 0.25),
    ("dambreak-cubic", "dambreak", 13.0, 1.0, 0.12, 0.11),
    ("dambreak-cfl-0.1", "dambreak", 21.0, 1.0, 0.10, 0.09),
    ("dambreak-no-diffusion", "dambreak", 2.0, 0.5, 0.01, 0.01),  # blew up: fast, 'accurate', no result
    ("tank-base", "tank", 5.0, 0.2, 0.02, None),
    ("tank-float64", "tank", 9.0, 0.2, 0.02, None),
]
FRONT = {"dambreak-base", "dambreak-fine", "dambreak-coarse", "tank-base"}


def make_results(folder):
    folder.mkdir(parents=True)
    cols = ["run_id", "config", "scene", "backend", "device", "wall_s", "validation_s", "front_rms_martin_moyce",
            "front_rms_koshizuka_oka", "hydro_rel_rms_final", "blow_up"]
    with open(folder / "runs.csv", "w") as f:
        f.writelines(f"# {k}: {v}\n" for k, v in META.items())
        f.write(",".join(cols) + "\n")
        for run_id, scene, wall, val, err, sec in RUNS:
            front = (err, "" if sec is None else sec, "") if scene == "dambreak" else ("", "", err)
            blew = "blew up at step 9" if run_id.endswith("no-diffusion") else ""
            f.write(",".join(map(str, [run_id, run_id, scene, "host", "host", wall, val, *front, blew])) + "\n")


def run(*args):
    return subprocess.run([sys.executable, str(PLOTS / "accuracy.py"), *map(str, args)], capture_output=True, text=True)


def test_pareto_mask():
    assert list(accuracy.pareto_mask([1, 2, 3], [3, 2, 1])) == [True, True, True]
    assert list(accuracy.pareto_mask([1, 2, 3], [1, 2, 3])) == [True, False, False]
    # A tie on error: the slower run is dominated; a NaN error is never on the front.
    assert list(accuracy.pareto_mask([1, 2, 3], [1, 1, float("nan")])) == [True, False, False]


def test_figure_table_and_summary(tmp):
    results, out = tmp / "results" / "accuracy", tmp / "out"
    make_results(results)
    p = run("--results", results, "--out", out)
    assert p.returncode == 0, f"accuracy.py failed:\n{p.stderr}"
    for ext in ("png", "pdf"):
        f = out / f"accuracy.{ext}"
        assert f.is_file() and f.stat().st_size > 0, f"{f} missing or empty"
    table, meta = sphplot.read_csv_with_metadata(out / "accuracy.csv")
    assert meta.get("git_commit", "").startswith("0123456"), "the table lost its provenance"
    got = set(table.loc[table["pareto"].astype(str) == "True", "run_id"])
    assert got == FRONT, f"Pareto front {got}, expected {FRONT}"
    base = table[table["run_id"] == "dambreak-base"].iloc[0]
    assert abs(base["run_time_s"] - 10.0) < 1e-9, "run time must exclude the metric's evaluation"
    nodiff = table[table["run_id"] == "dambreak-no-diffusion"].iloc[0]
    assert str(nodiff["blew_up"]) == "True" and "BLEW UP" in p.stdout, "a blown-up run must say so"
    assert "REDUCED SCALE" in p.stdout and "commit 0123456" in p.stdout, p.stdout
    line = next((l for l in p.stdout.splitlines() if "base" in l and "10.00 s" in l), None)
    assert line and "Pareto" in line, f"no summary line for dambreak-base in:\n{p.stdout}"


def test_lead_judgement():
    # Martin and Moyce's 2.25 in data start at T = 0.832; a run to T = 2.5 spans 1.668 in T.
    assert accuracy.lead_judgement(0.0, 0.832, 2.5) == "constant shift"
    assert accuracy.lead_judgement(0.03, 0.832, 2.5) == "constant shift"  # 0.05 in T: under one output interval
    assert accuracy.lead_judgement(0.1, 0.832, 2.5) == "ours pulls ahead"
    assert accuracy.lead_judgement(-0.1, 0.832, 2.5) == "ours falls back"
    assert accuracy.lead_judgement(float("nan"), 0.832, 2.5) == "undefined"


def test_time_offsets_table_and_front_panel(tmp):
    """Runs with the front's offset columns: the printed table, NAME_offsets.csv and the baseline's panel."""
    folder, out = tmp / "results" / "accuracy", tmp / "out"
    folder.mkdir(parents=True)
    keys = [k for k, _, _ in accuracy.FRONT_DATA]
    cols = ["run_id", "scene", "wall_s", "validation_s", "front_T_end"]
    for what in ("front_rms_", "front_offset_", "front_rms_offset_", "front_rms_published_offset_",
                 "front_lead_slope_", "front_particle_rms_"):
        cols += [what + k for k in keys]
    # base: a constant lead of +0.15 against every data set; fine: a lead growing at 0.2 per unit T.
    values = {"dambreak-base": [0.2, 0.25, 0.18, 0.15, 0.16, 0.14, 0.03, 0.04, 0.02, 0.1, 0.12, 0.09, 0.0, 0.01, -0.01,
                                0.21, 0.26, 0.19],
              "dambreak-fine": [0.3, 0.35, 0.28, 0.2, 0.2, 0.2, 0.05, 0.06, 0.04, 0.15, 0.16, 0.14, 0.2, 0.2, 0.2,
                                0.31, 0.36, 0.29]}
    with open(folder / "runs.csv", "w") as f:
        f.writelines(f"# {k}: {v}\n" for k, v in META.items())
        f.write(",".join(cols) + "\n")
        for run_id, v in values.items():
            f.write(",".join(map(str, [run_id, "dambreak", 10.0, 1.0, 2.5, *v])) + "\n")
    with open(folder / "dambreak-base_validation.csv", "w") as f:
        f.write("step,time,T,Z,Z_particle,Z_martin_moyce,Z_martin_moyce_1125,Z_koshizuka_oka\n")
        for i in range(11):
            T = 0.25 * i
            f.write(f"{i},{T / 6.26},{T},{1 + 0.3 * T * T},{1.02 + 0.3 * T * T},nan,nan,nan\n")
    p = run("--results", folder, "--out", out)
    assert p.returncode == 0, f"accuracy.py failed:\n{p.stderr}"
    base = next((l for l in p.stdout.splitlines() if l.split()[:2] == ["base", "martin_moyce"]), None)
    assert base and "+0.1500" in base and "0.0300" in base and "0.1000" in base and "constant shift" in base, p.stdout
    fine = next((l for l in p.stdout.splitlines() if l.split()[:2] == ["fine", "koshizuka_oka"]), None)
    assert fine and "ours pulls ahead" in fine, p.stdout
    table, _ = sphplot.read_csv_with_metadata(out / "accuracy_offsets.csv")
    assert len(table) == 6 and set(table["data"]) == set(keys), table
    row = table[(table["run_id"] == "dambreak-base") & (table["data"] == "koshizuka_oka")].iloc[0]
    assert abs(row["rms_published_offset"] - 0.09) < 1e-12 and abs(row["rms_particle_front"] - 0.19) < 1e-12, row
    assert (out / "accuracy.png").is_file()


def test_missing_results_is_one_sentence(tmp):
    p = run("--results", tmp / "nothing", "--out", tmp / "out")
    assert p.returncode == 2 and "Traceback" not in p.stderr, p.stderr
    assert "no results folder" in p.stderr, p.stderr


def test_results_without_validation_columns(tmp):
    folder = tmp / "results" / "accuracy"
    folder.mkdir(parents=True)
    (folder / "runs.csv").write_text("# backend: host\nrun_id,scene,wall_s\nfig4-1,armadillo,3.0\n")
    p = run("--results", folder, "--out", tmp / "out")
    assert p.returncode == 2 and "Traceback" not in p.stderr, p.stderr


def main():
    failed = 0
    for name, fn in list(globals().items()):
        if not name.startswith("test_"):
            continue
        with tempfile.TemporaryDirectory() as d:
            try:
                fn(Path(d)) if fn.__code__.co_argcount else fn()
                print(f"ok   {name}")
            except Exception:  # noqa: BLE001  (report every failure, then exit non-zero)
                failed += 1
                print(f"FAIL {name}\n{traceback.format_exc()}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
