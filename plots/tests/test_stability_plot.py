"""Tests for plots/stability.py on synthetic tables laid out as `sphbench stability` writes
them, without pytest: python3 plots/tests/test_stability_plot.py
"""
import subprocess
import sys
import tempfile
from pathlib import Path

PLOTS = Path(__file__).resolve().parents[1]
META = {"git_commit": "0123456789abcdef", "git_dirty": "clean", "backend": "host", "devices": "host",
        "date": "2025-01-01T00:00:00Z", "scale": "0.015625", "reduced_scale": "yes"}
RUN = "run_id,scene,backend,particles,fluid,boundary,dp,target_time,max_steps"


def write(path, header, rows):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as f:
        f.writelines(f"# {k}: {v}\n" for k, v in META.items())
        f.write(header + "\n")
        f.writelines(r + "\n" for r in rows)


def energy_study(folder, runs):
    cols = (RUN + ",cfl,stable,steps,time,failed_step,particle,quantity,energy_scale,total_drift,mechanical_drift,"
            "largest_total_drift,free_surface_0,free_surface_drift,largest_free_surface_drift,wall_s,series,last_good")
    rows = []
    for run_id, stable, drift in runs:
        write(folder / f"{run_id}_energy.csv", "step,time,total_drift,free_surface_drift",
              [f"{k * 100},{k * 0.1},{drift * k / 4},{0.001 * k}" for k in range(5)])
        rows.append(f"{run_id},tank,host,100,50,50,0.05,0,400,0.2,{'true' if stable else 'false'},400,0.4,"
                    f"{0 if stable else 401},{'' if stable else 7},{'' if stable else 'density'},10,{drift},{drift},"
                    f"{drift},0.4,0.004,0.004,1.0,{run_id}_energy.csv,")
    write(folder / "summary.csv", cols, rows)


def run(*args):
    return subprocess.run([sys.executable, str(PLOTS / "stability.py"), *map(str, args)], capture_output=True, text=True)


def main():
    with tempfile.TemporaryDirectory() as d:
        res = Path(d) / "results"
        cols = RUN + ",cfl_stable,cfl_unstable,trials,unstable_failed_step,unstable_quantity"
        write(res / "stability-cfl" / "summary.csv", cols,
              ["dambreak,dambreak,host,5618,600,5018,0.05,0.1,1000,0.615,0.675,7,116,density",
               "tank,tank,host,1671,168,1503,0.05,0.1,1000,4,0,1,,"])
        energy_study(res / "stability-still-water", [("tank", True, -0.02)])
        energy_study(res / "stability-impact", [("slow", True, -0.1), ("fast", False, -0.4)])
        p = run("--results", res, "--out", Path(d) / "out")
        assert p.returncode == 0, p.stdout + p.stderr
        for ext in ("png", "pdf"):
            assert (Path(d) / "out" / f"stability.{ext}").stat().st_size > 0
        assert "dambreak: largest stable cfl 0.615, smallest unstable 0.675 (density)" in p.stdout, p.stdout
        assert "impact fast: BLEW UP at step 401 (density)" in p.stdout, p.stdout
        assert "still water tank: stable, 400 steps" in p.stdout and "energy drift -2.00%" in p.stdout, p.stdout
        missing = run("--results", Path(d) / "nowhere", "--out", Path(d) / "o")
        err = missing.stderr.strip()
        assert missing.returncode != 0 and "Traceback" not in err and "make stability" in err, err
    print("PASS stability plot")
    return 0


if __name__ == "__main__":
    sys.exit(main())
