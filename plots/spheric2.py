"""Issue 27: SPHERIC Test 2 (Kleefsman et al. 2005), our runs and DualSPHysics' against the MARIN
measurements: error against run time per run of both codes, with the Pareto front, and the
time histories of H2, H4 and P1.

Errors, the same for every code:
  water heights H1-H4: RMS of (simulated - measured) over 0 to 2 s (or the run's end if sooner)
      at the measurement times, relative to the column's 0.55 m; for a run of 6 s or more also
      over 0 to 6 s (the _6s columns). The measured file's H1 and H3 columns
      are swapped against SPHERIC's figure (validation/data/kleefsman2005_spheric2.md): its H1 is
      the probe at x = 1.488 and its H3 the one at x = 0.496, and they are read so. A water-level
      gauge with no fluid on its line (a dry probe) reads nan in our CSV and the floor in
      DualSPHysics': both count as 0 m.
  pressures (ours only: DualSPHysics' case has no pressure gauge): both series filtered by the
      same centred 5 ms mean, the integral of the linearly interpolated series over each window
      (SPH pressures are noisy at the time step; the measurement is sampled every ms), read on a
      1 ms grid; a sensor with no fluid over it reads 0.
      P1-P4: the first impact's peak (the largest value in 0.3-0.8 s) and its time against the
      measured one; and its impulse, the integral of the pressure over the 100 ms from its arrival
      (the first time in 0.3-0.8 s the series passes a fifth of its own first peak), against the
      measured one, with the arrival's time. Our impact rings for an acoustic period or two (the
      period follows the sound speed, the first swing does not: docs/results.md), and the peak
      holds that ringing; the impulse, the momentum the impact delivers, does not depend on it.
      P5-P8: the RMS of the difference over the run, in kPa.
The run time is seconds per simulated second over the whole run: ours s_per_sim_s (runs.csv),
DualSPHysics' "Runtime per physical second" (Run.out, in its summary.tsv).

Usage: python3 plots/spheric2.py [--results results/spheric2] [--dualsphysics DIR] [--measured FILE] [--out plots/out]
  --dualsphysics: a folder of DualSPHysics runs of the case (anchors/dualsphysics/run.sh's LOGDIR:
  summary.tsv and CASE.GaugesSWL_H1.csv ...; each CASE names its spacing, e.g. dp0.01);
  default spheric2-dualsphysics beside RESULTS when it exists (`make reference` writes it there).
Writes spheric2.png/.pdf and spheric2.csv (one row per run of either code) into --out.
"""
import re
from pathlib import Path

import numpy as np

import accuracy
import sphplot
from sphplot import pd, plt

NAME = "spheric2"
MEASURED = sphplot.REPO / "validation" / "data" / "kleefsman2005_spheric2.dat"
COLUMN_HEIGHT = 0.55  # m, the water column at rest: the scale of the water-height errors
PROBES = ["H1", "H2", "H3", "H4"]
SENSORS = [f"P{k}" for k in range(1, 9)]
IMPACT_SENSORS = SENSORS[:4]
TOP_SENSORS = SENSORS[4:]
IMPACT_WINDOW = (0.3, 0.8)  # s: the first impact on the box's face (measured P1 peak: 0.415 s)
IMPULSE_S = 0.1             # s: the first impact's impulse is integrated over this long from its arrival
ARRIVAL_FRACTION = 0.2      # the arrival: the series first passes this fraction of its first peak
RESAMPLE_DT = 0.001        # s
SMOOTH_S = 0.005           # s, the width of the centred mean applied to every pressure series
DSPH_COLOUR, OUR_COLOUR = "#d95f02", "#1f77b4"


def read_measured(path):
    """The measurements as a DataFrame: time, P1-P8 (Pa), H1-H4 (m), H1 and H3 as SPHERIC's figure places them."""
    path = Path(path)
    if not path.is_file():
        raise sphplot.ResultsError(f"{path}, the SPHERIC Test 2 measurements, does not exist.")
    data = np.loadtxt(path, skiprows=1)
    if data.ndim != 2 or data.shape[1] != 13:
        raise sphplot.ResultsError(f"{path} does not have 13 columns (time, P1-P8, H1-H4).")
    m = pd.DataFrame(data, columns=["time"] + SENSORS + ["H1", "H2", "H3", "H4"])
    m = m.rename(columns={"H1": "H3", "H3": "H1"})  # the file's swap, undone
    return m[["time"] + SENSORS + PROBES]


def water_height_rms(t, h, measured, end):
    """RMS of h(t) - measured over [0, end], relative to the column's height (a fraction).
    measured: a DataFrame of time and the probe's heights."""
    m = measured[measured["time"] <= end + 1e-9].to_numpy(float)
    t = np.asarray(t, float)
    h = np.nan_to_num(np.asarray(h, float), nan=0.0)  # a dry probe is at the floor
    ok = np.isfinite(t)
    sim = np.interp(m[:, 0], t[ok], h[ok])
    return float(np.sqrt(np.mean((sim - m[:, 1]) ** 2)) / COLUMN_HEIGHT)


def window_means(t, p, centres, width):
    """The mean of the piecewise-linear series (t, p) over [c - width/2, c + width/2] for each c in
    centres: its integral over each window (exact for the linear pieces), divided by the width.
    Outside the series its end values hold. Unlike an average of point samples, this is the
    signal's mean whatever the sampling: a series sampled at every step and one sampled every ms
    of the same signal give the same means, up to what the coarser one missed between samples."""
    t = np.asarray(t, float)
    p = np.asarray(p, float)
    lo, hi = centres[0] - width, centres[-1] + width
    if t[0] > lo:
        t, p = np.concatenate([[lo], t]), np.concatenate([[p[0]], p])
    if t[-1] < hi:
        t, p = np.concatenate([t, [hi]]), np.concatenate([p, [p[-1]]])
    dt = np.diff(t)
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (p[1:] + p[:-1]) * dt)])

    def integral_to(x):
        k = np.clip(np.searchsorted(t, x, side="right") - 1, 0, len(t) - 2)
        u = x - t[k]
        slope = np.where(dt[k] > 0, (p[k + 1] - p[k]) / np.where(dt[k] > 0, dt[k], 1.0), 0.0)
        return cumulative[k] + p[k] * u + 0.5 * slope * u * u

    return (integral_to(centres + width / 2) - integral_to(centres - width / 2)) / width


def smoothed(t, p, end):
    """A pressure series on a 1 ms grid over [0, end], nan as 0: the centred 5 ms mean of the
    signal at each grid time (window_means: the integral over the window, not an average of
    point samples, so that a series sampled at every step is filtered as the same signal
    sampled every ms is)."""
    grid = np.arange(0.0, end + RESAMPLE_DT / 2, RESAMPLE_DT)
    t = np.asarray(t, float)
    p = np.nan_to_num(np.asarray(p, float), nan=0.0)
    ok = np.isfinite(t)
    t, p = t[ok], p[ok]
    order = np.argsort(t, kind="stable")
    return grid, window_means(t[order], p[order], grid, SMOOTH_S)


def point_sampled(t, p, every=RESAMPLE_DT):
    """The series as a gauge sampled every `every` seconds would have read it: the first sample at
    or after each multiple of `every` (the harness's rule), for comparing a run sampled at every
    step with its 1 ms readings."""
    t = np.asarray(t, float)
    p = np.asarray(p, float)
    ticks = np.arange(t[0], t[-1] + 1e-6 * every, every)
    k = np.unique(np.clip(np.searchsorted(t, ticks - 1e-6 * every, side="left"), 0, len(t) - 1))
    return t[k], p[k]


def first_peak(grid, p):
    """(peak, time of the peak) within the impact window."""
    inside = (grid >= IMPACT_WINDOW[0]) & (grid <= IMPACT_WINDOW[1])
    if not inside.any():
        return np.nan, np.nan
    k = np.argmax(np.where(inside, p, -np.inf))
    return float(p[k]), float(grid[k])


def first_impulse(grid, p):
    """(impulse in Pa s over IMPULSE_S from the arrival, time of the arrival) of the first impact."""
    peak, _ = first_peak(grid, p)
    inside = (grid >= IMPACT_WINDOW[0]) & (grid <= IMPACT_WINDOW[1]) & (p > ARRIVAL_FRACTION * peak)
    if not np.isfinite(peak) or peak <= 0 or not inside.any():
        return np.nan, np.nan
    arrival = float(grid[np.argmax(inside)])
    span = (grid >= arrival) & (grid <= arrival + IMPULSE_S)
    return float(np.trapezoid(p[span], grid[span])), arrival


RINGING_S = 0.04  # s after the unfiltered first peak in which its ringing's period is read


def first_ringing(t, p):
    """(the unfiltered first peak in Pa, the period in s of the ringing after it: the strongest
    frequency of the RINGING_S that follow) of one sensor's raw series."""
    t = np.asarray(t, float)
    raw = np.nan_to_num(np.asarray(p, float))
    inside = (t >= IMPACT_WINDOW[0]) & (t <= IMPACT_WINDOW[1])
    if not inside.any():
        return np.nan, np.nan
    k = int(np.argmax(np.where(inside, raw, -np.inf)))
    after = raw[(t >= t[k]) & (t < t[k] + RINGING_S)]
    if len(after) < 4:
        return float(raw[k]), np.nan
    spectrum = np.abs(np.fft.rfft(after - after.mean()))
    freq = np.fft.rfftfreq(len(after), d=float(np.median(np.diff(t))))
    return float(raw[k]), float(1.0 / freq[1 + int(np.argmax(spectrum[1:]))])


LONG_END = 6.0  # s: a run this long also has its water heights' errors over 0 to 6 s
# A gauge's last sample may fall short of the run's end by up to its interval (DualSPHysics' last,
# every 5 ms, is at 5.995 s of a run to 6 s); such a run still counts as one to LONG_END.
LONG_END_SLACK_S = 0.01


def run_errors(series, measured, end, sim_time=None):
    """Errors of one run: series maps H1-H4 (and, for ours, P1-P8) to (times, values); end is 2 s
    (or less for a shorter run); a run of at least LONG_END (sim_time) also gets <probe>_rms_6s
    and H_rms_mean_6s, nan otherwise."""
    row = {}
    long_run = sim_time is not None and sim_time >= LONG_END - LONG_END_SLACK_S
    for probe in PROBES:
        t, h = series[probe]
        row[f"{probe}_rms"] = water_height_rms(t, h, measured[["time", probe]], end)
        row[f"{probe}_rms_6s"] = (water_height_rms(t, h, measured[["time", probe]], LONG_END) if long_run else np.nan)
    row["H_rms_mean"] = float(np.mean([row[f"{p}_rms"] for p in PROBES]))
    row["H_rms_mean_6s"] = float(np.mean([row[f"{p}_rms_6s"] for p in PROBES]))
    for sensor in SENSORS:
        if sensor not in series:
            continue
        grid, ours = smoothed(*series[sensor], end)
        _, meas = smoothed(measured["time"], measured[sensor], end)
        if sensor in IMPACT_SENSORS:
            peak, when = first_peak(grid, ours)
            mpeak, mwhen = first_peak(grid, meas)
            row[f"{sensor}_peak_kpa"] = peak / 1e3
            row[f"{sensor}_peak_err"] = (peak - mpeak) / mpeak
            row[f"{sensor}_peak_dt_ms"] = (when - mwhen) * 1e3
            impulse, arrival = first_impulse(grid, ours)
            mimpulse, marrival = first_impulse(grid, meas)
            row[f"{sensor}_impulse"] = impulse
            row[f"{sensor}_impulse_err"] = (impulse - mimpulse) / mimpulse
            row[f"{sensor}_arrival_dt_ms"] = (arrival - marrival) * 1e3
            raw_peak, period = first_ringing(*series[sensor])
            row[f"{sensor}_raw_peak_kpa"] = raw_peak / 1e3
            row[f"{sensor}_ringing_ms"] = period * 1e3
        else:
            row[f"{sensor}_rms_kpa"] = float(np.sqrt(np.mean((ours - meas) ** 2))) / 1e3
    return row


def dp_of(value):
    """A spacing: a number, or the one a name carries (DualSPHysics' case folders: dp0.01)."""
    try:
        return float(value)
    except (TypeError, ValueError):
        match = re.search(r"dp([0-9]*\.[0-9]+)", str(value))
        return float(match.group(1)) if match else np.nan


def read_our_gauges(path):
    """{gauge column: (times, values)} of a <run>_gauges.csv. Each gauge has its own interval:
    a row holds an empty cell for a gauge not sampled then (dropped here), and nan for one sampled
    with no fluid where it looks (kept: a dry probe or sensor). The file is read once, as text, so
    that the two stay apart."""
    if not Path(path).is_file():
        raise sphplot.ResultsError(f"{path} does not exist.")
    raw = pd.read_csv(path, skiprows=sphplot.read_comment_block(path)[1], dtype=str, keep_default_na=False)
    sphplot.require_columns(raw, ["time"] + PROBES, path)
    times = pd.to_numeric(raw["time"], errors="coerce").to_numpy(float)
    series = {}
    for c in PROBES + SENSORS:
        if c not in raw.columns:
            continue
        cells = raw[c].str.strip()
        sampled = (cells != "").to_numpy()
        values = pd.to_numeric(cells[sampled], errors="coerce").to_numpy(float)
        series[c] = (times[sampled], values)
    return series


def our_runs(folder, measured):
    runs, meta = sphplot.load_runs(folder, NAME)
    sphplot.require_columns(runs, ["run_id", "s_per_sim_s", "sim_time", "particles"])
    rows, histories = [], {}
    for _, run in runs.iterrows():
        folder_of_runs = Path(runs.attrs["path"]).parent
        path = folder_of_runs / f"{run['run_id']}_gauges.csv"
        if not path.is_file():  # a float64 run's files stay in the float64 build's own folder
            path = next(folder_of_runs.rglob(f"{run['run_id']}_gauges.csv"), path)
        series = read_our_gauges(path)
        blew = str(run.get("blow_up", "")).strip() not in ("", "nan")
        sim_time = float(run["sim_time"])
        end = min(sim_time, 2.0)
        row = {"code": "ours", "run": run["run_id"], "dp": dp_of(run.get("set.dp", run["run_id"])),
               "particles": int(run["particles"]), "s_per_sim_s": float(run["s_per_sim_s"]), "sim_time": end,
               "precision": run.get("precision", ""), "blew_up": blew}
        row.update(run_errors(series, measured, end, sim_time))
        rows.append(row)
        histories[("ours", run["run_id"])] = series
    return rows, histories, runs, meta


def read_dsph_gauge(path):
    g = pd.read_csv(path, sep=";")
    time = [c for c in g.columns if c.startswith("time")]
    level = [c for c in g.columns if c.startswith("swlz")]
    if not time or not level:
        raise sphplot.ResultsError(f"{path} is not a DualSPHysics water-level gauge (no time or swlz column).")
    return g[time[0]].to_numpy(float), g[level[0]].to_numpy(float)


def dsph_runs(folder, measured):
    folder = Path(folder)
    summary = folder / "summary.tsv"
    if not summary.is_file():
        raise sphplot.ResultsError(f"{summary} is missing: run anchors/dualsphysics/run.sh into {folder} first.")
    table = pd.read_csv(summary, sep="\t")
    rows, histories = [], {}
    for _, case in table.iterrows():
        name = str(case["case"])
        if str(case.get("rc", 0)) not in ("0", "0.0"):
            continue
        series = {}
        for probe in PROBES:
            series[probe] = read_dsph_gauge(folder / f"{name}.GaugesSWL_{probe}.csv")
        sim_time = float(series["H1"][0][-1])
        end = min(sim_time, 2.0)
        row = {"code": "DualSPHysics", "run": name, "dp": dp_of(name), "particles": int(case["np"]),
               "s_per_sim_s": float(case["runtime_per_phys_s"]), "sim_time": end, "precision": "float32",
               "blew_up": False}
        row.update(run_errors(series, measured, end, sim_time))
        rows.append(row)
        histories[("DualSPHysics", name)] = series
    return rows, histories


GAP_WINDOWS = ((0.0, 1.0), (1.0, 2.0))


def series_gaps(histories, windows=GAP_WINDOWS):
    """How far our water heights are from DualSPHysics' at the same spacing: per run of ours that
    has a DualSPHysics run at its spacing, per probe and window, the RMS of ours less theirs (m),
    read at their gauge's times, a dry probe at the floor as in water_height_rms. The codes share
    the case and, since DensityDT 2, the physics: where they part tells where the flows differ,
    apart from how either is measured."""
    theirs = {dp_of(run): series for (code, run), series in histories.items() if code == "DualSPHysics"}
    rows = []
    for (code, run), ours in histories.items():
        other = theirs.get(dp_of(run)) if code == "ours" else None
        if other is None:
            continue
        row = {"run": run, "dp": dp_of(run)}
        for probe in PROBES:
            t_o, h_o = (np.asarray(a, float) for a in ours[probe])
            t_d, h_d = (np.asarray(a, float) for a in other[probe])
            ok = np.isfinite(t_o)
            for a, b in windows:
                m = (t_d >= a - 1e-9) & (t_d <= b + 1e-9) & (t_d <= t_o[ok][-1] + 1e-9)
                diff = np.interp(t_d[m], t_o[ok], np.nan_to_num(h_o[ok])) - np.nan_to_num(h_d[m])
                row[f"{probe}_{a:g}-{b:g}"] = float(np.sqrt(np.mean(diff ** 2))) if m.any() else np.nan
        rows.append(row)
    return rows


def targets(data):
    """The issue's targets, one line each: per spacing both codes ran, per probe, ours at least as
    close and faster; P1's first peak within 20% and 20 ms at our finest spacing."""
    lines = []
    for c in comparisons(data):
        best, d = c["ours"], c["dsph"]
        probes = ", ".join(f"{p} {100 * best[f'{p}_rms']:.1f}% vs {100 * d[f'{p}_rms']:.1f}%" for p in PROBES)
        lines.append(f"dp {c['dp']:g}: {best['run']} {best['s_per_sim_s']:.1f} s/sim-s vs DualSPHysics "
                     f"{d['s_per_sim_s']:.1f}; {probes}: {'MET' if c['closer'] and c['faster'] else 'NOT MET'}"
                     f" ({'closer' if c['closer'] else 'not closer on every probe'}, "
                     f"{'faster' if c['faster'] else 'slower'})")
    finest = finest_p1(data)
    if finest is not None:
        ok = abs(finest["P1_peak_err"]) <= 0.2 and abs(finest["P1_peak_dt_ms"]) <= 20
        lines.append(f"P1 first peak at dp {finest['dp']:g} ({finest['run']}): {finest['P1_peak_kpa']:.2f} kPa, "
                     f"{100 * finest['P1_peak_err']:+.0f}% and {finest['P1_peak_dt_ms']:+.0f} ms against the "
                     f"measurement: {'MET' if ok else 'NOT MET'} (within 20% and 20 ms)")
    return lines


def impulses(data):
    """What the first impact on P1 delivers, per run of ours with a P1 series, one line each (not
    a target of the issue: its figure beside the peak's)."""
    lines = []
    ours = data[(data["code"] == "ours") & ~data["blew_up"]]
    if "P1_impulse" not in ours.columns:
        return lines
    for _, r in ours.sort_values(["dp", "s_per_sim_s"], ascending=[False, True]).iterrows():
        if np.isfinite(r["P1_impulse"]):
            lines.append(f"P1 impulse over {IMPULSE_S * 1e3:g} ms from the arrival, {r['run']}: {r['P1_impulse']:.0f} "
                         f"Pa s ({100 * r['P1_impulse_err']:+.1f}% against the measurement), arrival "
                         f"{r['P1_arrival_dt_ms']:+.0f} ms")
    return lines


def table(results, dualsphysics, measured):
    """(one row per run of either code with its errors and Pareto membership, {(code, run): gauge
    series}, our runs.csv, its metadata). dualsphysics: a folder, or None for the one beside results
    where it exists."""
    rows, histories, runs, meta = our_runs(results, measured)
    dsph_folder = dualsphysics or (Path(results).parent / "spheric2-dualsphysics")
    if dualsphysics is not None or dsph_folder.is_dir():
        more, more_hist = dsph_runs(dsph_folder, measured)
        rows += more
        histories.update(more_hist)
    data = pd.DataFrame(rows)
    data["pareto"] = accuracy.pareto_mask(data["s_per_sim_s"], data["H_rms_mean"].where(~data["blew_up"]))
    return data, histories, runs, meta


def comparisons(data):
    """Per spacing both codes ran: our fastest float32 run there against DualSPHysics' run, as
    {dp, ours, dsph (the two rows), closer (on every probe), faster}."""
    ours = data[(data["code"] == "ours") & ~data["blew_up"] & (data["precision"].astype(str) != "float64")]
    out = []
    for _, d in data[data["code"] == "DualSPHysics"].sort_values("dp", ascending=False).iterrows():
        same = ours[np.isclose(ours["dp"], d["dp"])]
        if same.empty:
            continue
        best = same.sort_values("s_per_sim_s").iloc[0]
        out.append({"dp": d["dp"], "ours": best, "dsph": d,
                    "closer": all(best[f"{p}_rms"] <= d[f"{p}_rms"] for p in PROBES),
                    "faster": best["s_per_sim_s"] < d["s_per_sim_s"]})
    return out


BOX_FACE_AREA = 0.403 * 0.161   # m^2, the box's face toward the reservoir (x = 0.8245)
LOAD_WINDOWS = ((0.3, 0.8), (0.8, 2.0))  # s: the first impact and its run-up; the flow after


def box_load_row(code, run, dp, t, fx, net=True):
    """The water's load on the box along -x (N): in the first window its largest sample, its
    arrival (the first time it passes a fifth of that sample) and its impulse (N s) over IMPULSE_S
    from the arrival, before the water wraps round to the box's back face; and, for a net force
    (net), its mean over the second window, when water presses on the faces both ways."""
    t = np.asarray(t, float)
    load = -np.nan_to_num(np.asarray(fx, float))
    first = (t >= LOAD_WINDOWS[0][0]) & (t <= LOAD_WINDOWS[0][1])
    after = (t >= LOAD_WINDOWS[1][0]) & (t <= LOAD_WINDOWS[1][1])
    row = {"code": code, "run": run, "dp": dp, "peak_n": np.nan, "arrival_s": np.nan,
           "impulse_ns": np.nan, "mean_after_n": np.nan}
    if first.sum() >= 2:
        peak = float(load[first].max())
        arrival = float(t[first][np.argmax(load[first] > ARRIVAL_FRACTION * peak)])
        span = (t >= arrival) & (t <= arrival + IMPULSE_S)
        row.update(peak_n=peak, arrival_s=arrival, impulse_ns=float(np.trapezoid(load[span], t[span])))
    if net and after.sum() >= 2 and t[after][-1] >= LOAD_WINDOWS[1][1] - 0.01:
        row["mean_after_n"] = float(np.trapezoid(load[after], t[after]) / (t[after][-1] - t[after][0]))
    return row


def box_loads(results, dualsphysics, measured):
    """One row per run with a force on the box (ours: the gauge box_x of <run>_gauges.csv;
    DualSPHysics: forcex of CASE.GaugesForce_Box.csv), and one for the measurement: the mean of
    P1-P4 (the face's centre line, centred 5 ms means) times the face's area, an estimate that
    takes the centre line's pressure for the whole width."""
    rows = []
    runs, _ = sphplot.load_runs(results, NAME)
    folder_of_runs = Path(runs.attrs["path"]).parent
    for _, run in runs.iterrows():
        path = folder_of_runs / f"{run['run_id']}_gauges.csv"
        if not path.is_file():
            path = next(folder_of_runs.rglob(f"{run['run_id']}_gauges.csv"), path)
        raw = pd.read_csv(path, skiprows=sphplot.read_comment_block(path)[1], dtype=str, keep_default_na=False)
        if "box_x" not in raw.columns:
            continue
        cells = raw["box_x"].str.strip()
        sampled = (cells != "").to_numpy()
        t = pd.to_numeric(raw["time"][sampled], errors="coerce").to_numpy(float)
        fx = pd.to_numeric(cells[sampled], errors="coerce").to_numpy(float)
        rows.append(box_load_row("ours", run["run_id"], dp_of(run.get("set.dp", run["run_id"])), t, fx))
    dsph_folder = Path(dualsphysics) if dualsphysics is not None else Path(results).parent / "spheric2-dualsphysics"
    if (dsph_folder / "summary.tsv").is_file():
        for name in pd.read_csv(dsph_folder / "summary.tsv", sep="\t")["case"].astype(str):
            path = dsph_folder / f"{name}.GaugesForce_Box.csv"
            if not path.is_file():
                continue
            g = pd.read_csv(path, sep=";")
            fx = [c for c in g.columns if c.startswith("forcex")]
            if not fx:
                raise sphplot.ResultsError(f"{path} is not a DualSPHysics force gauge (no forcex column).")
            rows.append(box_load_row("DualSPHysics", name, dp_of(name), g[g.columns[0]], g[fx[0]]))
    end = float(measured["time"].iloc[-1])
    grid, face = None, 0.0
    for sensor in IMPACT_SENSORS:
        grid, p = smoothed(measured["time"], measured[sensor], min(end, LOAD_WINDOWS[1][1]))
        face = face + p / len(IMPACT_SENSORS)
    rows.append(box_load_row("measured (estimate)", "mean of P1-P4 x face area", np.nan, grid, -face * BOX_FACE_AREA,
                             net=False))
    return pd.DataFrame(rows)


def finest_p1(data):
    """Our run with a P1 series at the finest spacing (the fastest of them), or None."""
    ours = data[(data["code"] == "ours") & ~data["blew_up"]]
    if "P1_peak_err" not in ours.columns:
        return None
    ours = ours[np.isfinite(ours["P1_peak_err"].astype(float))]
    return None if ours.empty else ours.sort_values(["dp", "s_per_sim_s"]).iloc[0]


def draw(data, histories, measured, label, reduced):
    fig, axes = plt.subplots(2, 2, figsize=(10.5, 7.6))
    ax = axes[0, 0]
    for code, colour, marker in (("ours", OUR_COLOUR, "o"), ("DualSPHysics", DSPH_COLOUR, "s")):
        d = data[(data["code"] == code) & np.isfinite(data["H_rms_mean"])]
        ax.scatter(d["s_per_sim_s"], 100 * d["H_rms_mean"], color=colour, marker=marker, s=30, zorder=3, label=code)
        for _, r in d.iterrows():
            ax.annotate(r["run"], (r["s_per_sim_s"], 100 * r["H_rms_mean"]), textcoords="offset points",
                        xytext=(4, 3), fontsize=6)
    front = data[data["pareto"]].sort_values("s_per_sim_s")
    ax.step(front["s_per_sim_s"], 100 * front["H_rms_mean"], where="post", color="#d62728", lw=1.2, zorder=4)
    ax.scatter(front["s_per_sim_s"], 100 * front["H_rms_mean"], s=80, facecolors="none", edgecolors="#d62728",
               lw=1.5, zorder=5, label="Pareto front")
    ax.set_xscale("log")
    ax.set_xlabel("run time: seconds per simulated second")
    ax.set_ylabel("water height error, RMS over H1-H4 (% of 0.55 m)")
    ax.set_title("Error against run time (0-2 s)", loc="left")
    ax.legend(frameon=False)
    shown = [k for k in histories if k[0] == "DualSPHysics"] + [
        ("ours", r) for r in data[(data["code"] == "ours") & data["run"].str.contains("wendland-lists")
                                 & ~data["run"].str.contains("float64")]["run"]]
    for ax, probe in ((axes[0, 1], "H2"), (axes[1, 0], "H4")):
        ax.plot(measured["time"], measured[probe], color="black", lw=1.0, label="measured (MARIN)")
        for key in shown:
            t, h = histories[key][probe]
            colour = OUR_COLOUR if key[0] == "ours" else DSPH_COLOUR
            alpha = 0.45 + 0.55 * (1 - _rank(data, key))
            ax.plot(t, np.nan_to_num(np.asarray(h, float)), color=colour, lw=0.9, alpha=alpha,
                    ls="-" if key[0] == "ours" else "--", label=f"{key[0]} {key[1]}")
        ax.set_xlim(0, 2)
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"water height at {probe} (m)")
        ax.set_title(f"{probe} (x = {'0.992' if probe == 'H2' else '2.638'} m)", loc="left")
    axes[1, 0].legend(frameon=False, fontsize=6)
    ax = axes[1, 1]
    grid, meas = smoothed(measured["time"], measured["P1"], 2.0)
    ax.plot(grid, meas / 1e3, color="black", lw=1.0, label="measured, 5 ms average")
    for key in shown:
        if key[0] != "ours" or "P1" not in histories[key]:
            continue
        g, p = smoothed(*histories[key]["P1"], 2.0)
        ax.plot(g, p / 1e3, color=OUR_COLOUR, lw=0.9, alpha=0.45 + 0.55 * (1 - _rank(data, key)),
                label=f"ours {key[1]}, 5 ms average")
    ax.set_xlim(0, 2)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("pressure at P1 (kPa)")
    ax.set_title("P1, box face, z = 0.021 m", loc="left")
    ax.legend(frameon=False, fontsize=6)
    fig.suptitle("SPHERIC Test 2 (Kleefsman et al. 2005): ours and DualSPHysics against the measurements",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    sphplot.add_footer(fig, label, alert=reduced)
    return fig


def _rank(data, key):
    """0 for a code's finest spacing, towards 1 for its coarsest: finer runs are drawn darker."""
    d = data[data["code"] == key[0]]["dp"]
    dp = data[(data["code"] == key[0]) & (data["run"] == key[1])]["dp"]
    if d.empty or dp.empty or d.max() == d.min():
        return 0.0
    return float((dp.iloc[0] - d.min()) / (d.max() - d.min()))


def main(argv=None):
    import argparse
    p = argparse.ArgumentParser(prog="spheric2.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--results", type=Path, default=sphplot.REPO / "results" / NAME,
                   help="results folder of experiments/spheric2.toml (default: results/spheric2)")
    p.add_argument("--dualsphysics", type=Path, default=None,
                   help="DualSPHysics runs of the case (default: spheric2-dualsphysics beside RESULTS when it exists)")
    p.add_argument("--measured", type=Path, default=MEASURED, help="the MARIN measurements")
    p.add_argument("--out", type=Path, default=sphplot.REPO / "plots" / "out", help="where the figure goes")
    args = p.parse_args(argv)
    measured = read_measured(args.measured)
    data, histories, runs, meta = table(args.results, args.dualsphysics, measured)
    label = sphplot.provenance_label(meta, runs)
    print("SPHERIC Test 2: water-height RMS over 0-2 s (% of 0.55 m), P1 first peak, run time")
    print(f"  from {args.results}: {label}")
    for _, r in data.sort_values(["code", "dp", "s_per_sim_s"]).iterrows():
        probes = " ".join(f"{p} {100 * r[f'{p}_rms']:5.1f}" for p in PROBES)
        p1 = (f"  P1 {r['P1_peak_kpa']:5.2f} kPa ({100 * r['P1_peak_err']:+.0f}%, {r['P1_peak_dt_ms']:+.0f} ms)"
              if np.isfinite(r.get("P1_peak_kpa", np.nan)) else "")
        mark = "  Pareto" if r["pareto"] else "  BLEW UP" if r["blew_up"] else ""
        print(f"  {r['code']:<12} {r['run']:<30} {r['particles']:>9,} {r['s_per_sim_s']:8.2f} s/sim-s  "
              f"{probes}{p1}{mark}")
    for line in targets(data):
        print("  target: " + line)
    for line in impulses(data):
        print("  " + line)
    gaps = series_gaps(histories)
    if gaps:
        print("  apart from DualSPHysics at the same spacing (RMS of our water height less theirs, mm):")
        for g in gaps:
            print(f"    {g['run']:<30} " + "  ".join(
                f"{p} {a:g}-{b:g} s {1e3 * g[f'{p}_{a:g}-{b:g}']:5.1f}" for p in PROBES for a, b in GAP_WINDOWS))
    args.out.mkdir(parents=True, exist_ok=True)
    csv = args.out / f"{NAME}.csv"
    with open(csv, "w", encoding="utf-8") as f:
        f.writelines(f"# {k}: {v}\n" for k, v in meta.items())
        f.write(f"# filter: pressures as their centred {SMOOTH_S * 1e3:g} ms means (the integral over each window) "
                f"read every {RESAMPLE_DT * 1e3:g} ms, every code and the measurement alike\n")
        data.to_csv(f, index=False)
    print(f"wrote {sphplot._shown(csv)}")
    sphplot.apply_style()
    fig = draw(data, histories, measured, label, sphplot.is_reduced(meta))
    sphplot.save_figure(fig, NAME, args.out, description=label)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
