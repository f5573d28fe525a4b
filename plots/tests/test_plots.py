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


# ---- Figures 3, 5-9 and the CLL/VL table, on synthetic folders with known times ----------
GPU_META = dict(META, backend="cuda", devices="NVIDIA H200; NVIDIA H200 | driver 13.0, runtime 13.0",
                cuda="NVIDIA H200; NVIDIA H200 | driver 13.0, runtime 13.0", scale="1", reduced_scale="no")
STEP_COLS = ("step,time,dt,fluid,boundary,out_of_domain,kinetic_energy,max_speed,min_density,max_density,"
             "neighbour_list_ms,forces_ms,integrate_ms,diagnostics_ms,exchange_ms,migrate_ms,balance_ms,"
             "update_ms,update_ideal_ms,step_ms,subdomains,slices_moved,particles_migrated,ghosts_sent,"
             "bytes_exchanged,subdomain_update_ms,subdomain_particles").split(",")
SIZES = {"armadillo": 1034000, "bunny": 3049000}


def write_runs(folder, meta, rows):
    """rows: dicts; the header is their union, in first-seen order (missing cells stay empty)."""
    folder.mkdir(parents=True, exist_ok=True)
    header = list(dict.fromkeys(k for r in rows for k in r))
    write_csv(folder / "runs.csv", meta, header, [[r.get(k, "") for k in header] for r in rows])


def run_row(run_id, scene, **kw):
    row = {"run_id": run_id, "scene": scene, "repetition": 0, "backend": "cuda", "device": "NVIDIA H200",
           "particles": SIZES[scene], "fluid": SIZES[scene] - 1000, "boundary": 1000, "dp": 0.01, "steps": 30,
           "warmup": 2, "cells_per_support": 1, "merge": "false", "devices": 1, "balancer": "none",
           "verlet": "false", "set.particles": SIZES[scene]}
    row.update(kw)
    return row


# fig3: update time per (n, merge); CLL is (1, false). Speedups are CLL / variant.
FIG3_T = {"armadillo": {(1, False): 10.0, (1, True): 8.0, (2, False): 20.0, (2, True): 5.0,
                        (3, False): 25.0, (3, True): 6.25, (4, False): 30.0, (4, True): 8.0},
          "bunny": {(1, False): 30.0, (1, True): 24.0, (2, False): 60.0, (2, True): 15.0}}
FIG3_EXPECT = {"armadillo": (1.25, 0.5, 2.0), "bunny": (1.25, 0.5, 2.0)}


def make_fig3(folder):
    rows = []
    for scene, times in FIG3_T.items():
        for (n, merge), t in times.items():
            cand = 10.0 * (2 + 1 / n) ** 3 * SIZES[scene]
            rows.append(run_row(f"{scene}_n{n}_m{merge}", scene, cells_per_support=n, merge=str(merge).lower(),
                                update_ms_median=t, step_ms_median=t + 1, candidates_per_step=cand,
                                neighbours_per_step=40.0 * SIZES[scene], steps_file=""))
    # A Verlet-list run must not count as CLL.
    rows.append(run_row("armadillo_vl", "armadillo", verlet="true", update_ms_median=1.0, steps_file=""))
    write_runs(folder, GPU_META, rows)


# cll-vs-vl: (CLL update, CLL step, CLL B/p, VL update, VL step, VL B/p) per scene
VL = {"armadillo": (10.0, 12.0, 100.0, 9.4, 11.5, 3000.0), "bunny": (20.0, 24.0, 120.0, 18.8, 23.0, 1200.0)}


def make_vl(folder):
    rows = []
    for scene, (cu, cs, cb, vu, vs, vb) in VL.items():
        rows.append(run_row(f"{scene}_cll", scene, update_ms_median=cu, step_ms_median=cs, bytes_per_particle=cb))
        rows.append(run_row(f"{scene}_vl", scene, verlet="true", skin=0.1, rebuild_every=10, update_ms_median=vu,
                            step_ms_median=vs, bytes_per_particle=vb))
    write_runs(folder, GPU_META, rows)


# multi-gpu: (scene, devices, balancer) -> (real ms per step alternating +-d, ideal ms, slice moves every k steps,
# balance ms per step). Means: real and ideal exactly as given.
MG = {("armadillo", 1, "simple"): (10.0, 10.0, 0, 0.0),
      ("armadillo", 2, "simple"): (6.0, 5.5, 1, 2.0), ("armadillo", 2, "threshold"): (5.5, 5.2, 10, 0.5),
      ("bunny", 1, "simple"): (32.0, 32.0, 0, 0.0),
      ("bunny", 2, "simple"): (16.0, 15.0, 1, 2.0), ("bunny", 2, "threshold"): (15.0, 14.5, 10, 0.5),
      ("bunny", 4, "simple"): (9.0, 8.0, 1, 2.0)}
MG_STEPS = 30


def make_multi(folder, meta=GPU_META):
    rows = []
    folder.mkdir(parents=True, exist_ok=True)
    for (scene, n, bal), (real, ideal, every, bal_ms) in MG.items():
        run_id = f"{scene}_d{n}_{bal}"
        steps = []
        for k in range(1, MG_STEPS + 1):
            r = real + (0.5 if k % 2 else -0.5) * (n > 1)
            per = ";".join([f"{r}"] + [f"{(ideal * n - r) / (n - 1)}"] * (n - 1)) if n > 1 else f"{r}"
            moved = int(every > 0 and k % every == 0)
            steps.append([k, k * 1e-4, 1e-4, 900, 100, 0, 1, 1, 990, 1010, 1, r * 0.8, r * 0.2, 0.1, 0.2, 0.1,
                          bal_ms, r, ideal + (r - real) / n, r + 1.4 + bal_ms, n, moved, 5, 50, 5000, per,
                          ";".join(["500"] * n)])
        write_csv(folder / f"{run_id}_steps.csv", meta, STEP_COLS, steps)
        rows.append(run_row(run_id, scene, devices=n, balancer=bal, update_ms_median=real,
                            device="NVIDIA H200" if n == 1 else f"{n} subdomains on NVIDIA H200",
                            steps_file=f"{run_id}_steps.csv"))
    write_runs(folder, meta, rows)


def run_script(name, *args):
    return subprocess.run([sys.executable, str(PLOTS / f"{name}.py"), *map(str, args)], capture_output=True, text=True)


def check_outputs(p, out, name):
    assert p.returncode == 0, f"{name}.py failed:\n{p.stdout}\n{p.stderr}"
    for ext in ("png", "pdf"):
        f = out / f"{name}.{ext}"
        assert f.is_file() and f.stat().st_size > 0, f"{f} missing or empty"


def line_of(stdout, *words):
    line = next((l for l in stdout.splitlines() if all(w in l for w in words)), None)
    assert line, f"no line with {words} in:\n{stdout}"
    return line


def close(got, want, what, tol=1e-3):
    assert abs(float(got) - want) < tol, f"{what}: printed {got}, expected {want:.3f}"


def test_fig3(tmp):
    make_fig3(tmp / "fig3")
    p = run_script("fig3", "--results", tmp / "fig3", "--out", tmp / "out")
    check_outputs(p, tmp / "out", "fig3")
    for scene, want in FIG3_EXPECT.items():
        line = line_of(p.stdout, f"  {scene} {SIZES[scene] // 1000}K ")
        got = re.findall(r"([0-9.]+)x", line)
        assert len(got) == 3, line
        for g, w, what in zip(got, want, ("merging", "n=2", "both")):
            close(g, w, f"{scene} {what}")
    line = line_of(p.stdout, "armadillo 1034K n=3:")
    close(re.search(r"merging ([0-9.]+)", line.split("no merging")[1]).group(1), 0.625, "n=3 merging")
    close(re.search(r"candidates ([0-9.]+)", line).group(1), 10 * (2 + 1 / 3) ** 3, "candidates n=3", 0.05)


def test_table_vl(tmp):
    make_vl(tmp / "cll-vs-vl")
    p = run_script("table_vl", "--results", tmp / "cll-vs-vl", "--out", tmp / "out")
    check_outputs(p, tmp / "out", "table_vl")
    md = (tmp / "out" / "table_vl.md").read_text()
    assert "about 30x the memory" in md and "about 1 KB per particle" in md, md
    for scene, (cu, cs, cb, vu, vs, vb) in VL.items():
        cells = [c.strip() for c in line_of(md, f"| {scene} ").split("|")[1:-1]]
        close(cells[6], vu / cu, f"{scene} update ratio")
        close(cells[7], vs / cs, f"{scene} step ratio")
        close(cells[10].rstrip("x"), vb / cb, f"{scene} memory ratio")
        assert line_of(p.stdout, f"| {scene} ") == line_of(md, f"| {scene} ")


def test_multigpu_speedups(tmp):
    make_multi(tmp / "mg")
    out = tmp / "out"
    t1 = {"armadillo": 10.0, "bunny": 32.0}
    for name in ("fig5", "fig6", "fig7", "fig8", "fig9"):
        p = run_script(name, "--results", tmp / "mg", "--out", out)
        check_outputs(p, out, name)
        text = p.stdout
        if name == "fig5":
            line = line_of(text, "armadillo 1034K, 2 devices")
            close(re.search(r"real ([0-9.]+) ms", line).group(1), 6.0, "fig5 real")
            close(re.search(r"ideal ([0-9.]+) ms", line).group(1), 5.5, "fig5 ideal")
            assert "4 subdomains on 2 GPUs" in line_of(text, "bunny 3049K, 4 devices")
        if name == "fig6":
            for scene in t1:
                real = MG[(scene, 2, "simple")][0]
                close(re.search(r"= ([0-9.]+) \(", line_of(text, f"{scene} ", "2 devices")).group(1),
                      t1[scene] / real, f"fig6 {scene}")
        if name == "fig7":
            for scene in t1:
                line = line_of(text, f"{scene} ", "2 devices")
                close(re.search(r"threshold ([0-9.]+) \(update", line).group(1),
                      MG[(scene, 2, "simple")][0] / MG[(scene, 2, "threshold")][0], f"fig7 {scene}")
                close(re.search(r"simple ([0-9.]+),", line).group(1), 100.0, "slices simple")
                close(re.search(r"threshold ([0-9.]+)$", line).group(1), 10.0, "slices threshold")
        if name == "fig9":
            for scene in t1:
                real, ideal = MG[(scene, 2, "threshold")][:2]
                line = line_of(text, f"{scene} ", "2 devices")
                close(re.search(r"real ([0-9.]+)", line).group(1), t1[scene] / real, "fig9 real")
                close(re.search(r"\(eq. 7\) ([0-9.]+)", line).group(1), 2 * ideal / real, "fig9 eq. 7")
                close(re.search(r"vs T_1 ([0-9.]+)", line).group(1), t1[scene] / ideal, "fig9 T1/ideal")
        for line in text.splitlines():  # never a speedup for 4 subdomains on 2 GPUs
            if "4 devices" in line:
                assert "no speedup" in line and "S_4" not in line and not re.search(r"= [0-9]", line), line


def test_shared_gpus_get_no_speedup(tmp):
    import multigpu
    make_multi(tmp / "mg")
    table, _, _, label, gpus = multigpu.load(tmp / "mg")
    assert gpus == 2 and "2 x NVIDIA H200" in label, (gpus, label)
    four = table[table.devices == 4].iloc[0]
    assert four.note == "4 subdomains on 2 GPUs: per-device times only, no speedup", four.note
    assert all(sphplot.pd.isna(four[c]) for c in ("speedup", "ideal_eq7", "ideal_t1")), four
    two = table[(table.devices == 2) & (table.scene == "bunny") & (table.balancer == "simple")].iloc[0]
    assert abs(two.speedup - 2.0) < 1e-9 and abs(two.ideal_eq7 - 1.875) < 1e-9, two
    # One GPU in the label: now the 2-device runs get no speedup either.
    one = dict(GPU_META, devices="NVIDIA H200 | driver 13.0, runtime 13.0", cuda="NVIDIA H200")
    make_multi(tmp / "mg1", one)
    p = run_script("fig6", "--results", tmp / "mg1", "--out", tmp / "out")
    assert p.returncode == 0, p.stderr
    assert "2 subdomains on 1 GPU: per-device times only, no speedup" in p.stdout, p.stdout
    assert "S_2" not in p.stdout and "S_4" not in p.stdout, p.stdout


# fig10: (scene, devices, overlap) -> mean wall ms per step; 2 GPUs in GPU_META, so 4 devices share.
F10 = {("armadillo", 1, True): 12.0, ("armadillo", 1, False): 12.0, ("armadillo", 2, True): 6.5,
       ("armadillo", 2, False): 7.5, ("armadillo", 4, True): 4.0, ("armadillo", 4, False): 4.5,
       ("bunny", 1, True): 30.0, ("bunny", 1, False): 34.0, ("bunny", 2, True): 16.0, ("bunny", 2, False): 16.0}


def make_fig10(folder):
    rows = []
    folder.mkdir(parents=True, exist_ok=True)
    cols = STEP_COLS + ["wall_ms"]
    for (scene, n, overlap), wall in F10.items():
        run_id = f"{scene}_d{n}_{'on' if overlap else 'off'}"
        steps = [[k, k * 1e-4, 1e-4, 900, 100, 0, 1, 1, 990, 1010, 1, 4, 1, 0.1, 0.2, 0.1, 0, 5, 5, 6, n, 0, 5, 50,
                  5000, ";".join(["5"] * n), ";".join(["500"] * n), wall + (0.5 if k % 2 else -0.5)]
                 for k in range(1, MG_STEPS + 1)]
        write_csv(folder / f"{run_id}_steps.csv", GPU_META, cols, steps)
        rows.append(run_row(run_id, scene, devices=n, balancer="threshold", overlap=str(overlap).lower(),
                            steps_file=f"{run_id}_steps.csv"))
    write_runs(folder, GPU_META, rows)


def test_fig10_with_and_without_the_optimisation(tmp):
    make_fig10(tmp / "fig10")
    p = run_script("fig10", "--results", tmp / "fig10", "--out", tmp / "out")
    check_outputs(p, tmp / "out", "fig10")
    on = line_of(p.stdout, "armadillo 1034K, 2 GPUs, with:")
    close(re.search(r"speedup ([0-9.]+)", on).group(1), 12.0 / 6.5, "armadillo S_2 with")
    close(re.search(r"gain over without ([-+0-9.]+)%", on).group(1), (7.5 / 6.5 - 1) * 100, "gain", 0.06)
    off = line_of(p.stdout, "armadillo 1034K, 2 GPUs, without:")
    close(re.search(r"speedup ([0-9.]+)", off).group(1), 12.0 / 7.5, "armadillo S_2 without")
    # W_1 pools both one-device runs.
    bunny = line_of(p.stdout, "bunny 3049K, 2 GPUs, with:")
    close(re.search(r"speedup ([0-9.]+)", bunny).group(1), 32.0 / 16.0, "bunny S_2")
    assert "+0.0%" in bunny, bunny
    shared = line_of(p.stdout, "armadillo 1034K, 4 GPUs, with:")
    assert "4 subdomains on 2 GPUs" in shared and not re.search(r"speedup [0-9]", shared), shared


def test_new_scripts_fail_in_one_sentence(tmp):
    for name, target in (("fig3", "fig3"), ("table_vl", "cll-vs-vl"), ("fig6", "multi-gpu"), ("fig8", "multi-gpu"),
                         ("fig10", "fig10"), ("transports", "transports")):
        p = run_script(name, "--results", tmp / "nowhere", "--out", tmp / "o")
        err = p.stderr.strip()
        assert p.returncode != 0 and "Traceback" not in err and len(err.splitlines()) == 1, err
        assert f"make {target}" in err, err
    assert not (tmp / "o").exists()


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
