"""Issue 6: validation error against run time. Each run of experiments/accuracy.toml varies
one factor (resolution, CFL, kernel, density diffusion, search strategy, precision) around a
baseline; the figure puts its error against its run time, one panel per validation case, and
marks the Pareto front: the runs that no other run beats on both time and error.

  dam break: RMS of the surge front Z = x/a (the mass-threshold front on the floor) against
             Martin and Moyce (1952, a = 2.25 in), filled markers (Koshizuka and Oka (1996), open
             markers, for comparison; the front uses the first)
  tank:      relative RMS of the pressure against rho0 g (H - z) at the end of the run

The gate's opening: the experiments' clock starts as the gate starts to open, the model's
column is released at once. A third panel draws the baseline dam break's front against all
three data sets (Martin and Moyce at a = 2.25 and 1.125 in, Koshizuka and Oka), as computed
and delayed by the offset dT fitted to Martin and Moyce's 2.25 in column, and a printed table
(also NAME_offsets.csv) gives per dam-break run and data set the RMS without an offset, the
fitted dT (positive: our front leads) with its RMS, the RMS with the published correction
dT = +0.175, and the slope b of the lead in T fitted as a + b T, with a judgement: a constant
shift when b changes the lead by less than one output interval (0.063 in T at every = 0.01 s)
over the data's T range, else our front pulls ahead (b > 0) or falls back (b < 0) as T grows.
An offset at the fit's search bound (|dT| = 1) is marked: the best shift lies beyond it.

Run time is the run's wall time less the time spent evaluating the metric (wall_s - validation_s).
A run that blew up (its `blow_up` cell says where) has no error: it is drawn as a cross on the
top edge at the time it ran, and is never on the front.
Also writes NAME.csv beside the figure: one row per run with its time, error and front membership.

Usage: python3 plots/accuracy.py [--results results/accuracy] [--out plots/out]
"""
import numpy as np
import pandas as pd

import sphplot
from sphplot import plt

NAME = "accuracy"
# Per scene: (error column, axis label, secondary column or None, its legend)
CASES = {
    "dambreak": ("front_rms_martin_moyce", "surge front RMS error in Z = x/a\n(against Martin and Moyce 1952)",
                 "front_rms_koshizuka_oka", "against Koshizuka and Oka 1996"),
    "tank": ("hydro_rel_rms_final", "pressure error, relative RMS\n(against rho0 g (H - z))", None, None),
}
TITLES = {"dambreak": "Dam break: surge front", "tank": "Hydrostatic tank: pressure"}
# The front's data sets: summary key suffix, legend, file in validation/data (sample column Z_<key>).
FRONT_DATA = [("martin_moyce", "Martin and Moyce 1952, a = 2.25 in", "martin_moyce_1952.csv"),
              ("martin_moyce_1125", "Martin and Moyce 1952, a = 1.125 in", "martin_moyce_1952_a1125.csv"),
              ("koshizuka_oka", "Koshizuka and Oka 1996", "koshizuka_oka_1996.csv")]
PUBLISHED_OFFSET_T = 0.175  # the published correction for the gate's opening
OFFSET_SEARCH_BOUND_T = 1.0  # the metric fits dT within [-1, 1] (solver/validation/time_offset_fit.hpp)
# Below this change of the lead over the data's T range the lead is a constant shift: one output
# interval in T (0.01 s x sqrt(2 g / a) at a = 0.5 m).
CONSTANT_LEAD_T = 0.063


def pareto_mask(time, error):
    """True for runs that no other run matches or beats on both time and error (strictly on one)."""
    t, e = np.asarray(time, float), np.asarray(error, float)
    keep = np.isfinite(t) & np.isfinite(e)
    mask = np.zeros(len(t), bool)
    for i in np.flatnonzero(keep):
        dominated = keep & (t <= t[i]) & (e <= e[i]) & ((t < t[i]) | (e < e[i]))
        mask[i] = not dominated.any()
    return mask


def variant_of(run_id, scene):
    prefix = f"{scene}-"
    return run_id[len(prefix):] if run_id.startswith(prefix) else run_id


def table(runs):
    """One row per run with a usable error: scene, run_id, variant, time_s, error, secondary, pareto."""
    rows = []
    for scene, (err_col, _, sec_col, _) in CASES.items():
        sub = runs[runs["scene"] == scene]
        if sub.empty:
            continue
        sphplot.require_columns(sub, ["wall_s", err_col])
        time = sub["wall_s"].astype(float) - sphplot.column(sub, "validation_s", 0.0).astype(float)
        blew = sphplot.column(sub, "blow_up", "").astype(object).fillna("").astype(str).str.strip() != ""
        err = sub[err_col].astype(float).where(~blew)  # what it measured before blowing up is no result
        front = pareto_mask(time, err)
        sec = sub[sec_col].astype(float) if sec_col and sec_col in sub.columns else [np.nan] * len(sub)
        for run_id, t, e, s, p, b in zip(sub["run_id"], time, err, sec, front, blew):
            rows.append({"scene": scene, "run_id": run_id, "variant": variant_of(run_id, scene), "run_time_s": t,
                         "error_name": err_col, "error": e, "secondary": np.nan if b else s, "pareto": bool(p),
                         "blew_up": bool(b)})
    if not rows:
        raise sphplot.ResultsError(f"{runs.attrs.get('path', 'runs.csv')} has no dambreak or tank run with "
                                   "validation columns; run experiments/accuracy.toml.")
    return sphplot.pd.DataFrame(rows)


def reference_data(key_file):
    """(T, Z) of one validation data set, read from validation/data."""
    df, _ = sphplot.read_csv_with_metadata(sphplot.REPO / "validation" / "data" / key_file)
    return df["T"].to_numpy(float), df["Z"].to_numpy(float)


def lead_judgement(slope, data_first_T, T_end):
    """Whether a lead whose slope in T is `slope` is a constant shift over the data's T range."""
    if not np.isfinite(slope):
        return "undefined"
    change = slope * (T_end - data_first_T) if np.isfinite(T_end) else np.nan
    if not np.isfinite(change) or abs(change) < CONSTANT_LEAD_T:
        return "constant shift"
    return "ours pulls ahead" if change > 0 else "ours falls back"


def offset_table(runs):
    """One row per dam-break run and data set: RMS without and with offsets, the fitted offset, the trend."""
    sub = runs[runs["scene"] == "dambreak"]
    rows = []
    for key, legend, file in FRONT_DATA:
        if f"front_offset_{key}" not in sub.columns:
            continue  # results from before the offsets were measured
        first_T = reference_data(file)[0][0]
        for _, r in sub.iterrows():
            T_end = float(r.get("front_T_end", np.nan))
            slope = float(r[f"front_lead_slope_{key}"])
            rows.append({"run_id": r["run_id"], "variant": variant_of(r["run_id"], "dambreak"), "data": key,
                         "rms": float(r[f"front_rms_{key}"]), "offset_T": float(r[f"front_offset_{key}"]),
                         "rms_offset": float(r[f"front_rms_offset_{key}"]),
                         "rms_published_offset": float(r[f"front_rms_published_offset_{key}"]),
                         "lead_slope": slope, "lead_change_T": slope * (T_end - first_T),
                         "trend": lead_judgement(slope, first_T, T_end),
                         "rms_particle_front": float(r.get(f"front_particle_rms_{key}", np.nan))})
    return pd.DataFrame(rows)


def baseline_front(folder, offsets):
    """(validation samples, fitted offset against Martin and Moyce 2.25 in) of the baseline dam break, or None."""
    path = folder / "dambreak-base_validation.csv"
    if not path.is_file():
        return None
    samples, _ = sphplot.read_csv_with_metadata(path)
    if "Z" not in samples.columns or "T" not in samples.columns:
        return None
    row = offsets[(offsets["run_id"] == "dambreak-base") & (offsets["data"] == "martin_moyce")] \
        if not offsets.empty else offsets
    return samples, float(row["offset_T"].iloc[0]) if len(row) else np.nan


def draw_front(ax, samples, offset):
    """The baseline's front against the three data sets, as computed and delayed by the fitted offset."""
    T, Z = samples["T"].to_numpy(float), samples["Z"].to_numpy(float)
    ax.plot(T, Z, color="#1f77b4", lw=1.5, label="computed (mass threshold)")
    if "Z_particle" in samples.columns:
        ax.plot(T, samples["Z_particle"].to_numpy(float), color="#1f77b4", lw=0.8, ls=":",
                label="computed (furthest particle)")
    if np.isfinite(offset):
        ax.plot(T + offset, Z, color="#d62728", lw=1.2, ls="--", label=f"computed, delayed by dT = {offset:+.3f}")
    for (key, legend, file), marker in zip(FRONT_DATA, ("o", "s", "^")):
        dT, dZ = reference_data(file)
        keep = dT <= T.max() + 0.3
        ax.scatter(dT[keep], dZ[keep], marker=marker, s=24, facecolors="none", edgecolors="k", zorder=4, label=legend)
    ax.set_xlabel("T = t sqrt(2g/a)")
    ax.set_ylabel("Z = x/a")
    ax.set_title("Dam break: baseline front and the data", loc="left")
    ax.legend(loc="upper left", frameon=False, fontsize=7)


def draw(data, label, reduced, front=None):
    scenes = [s for s in CASES if (data["scene"] == s).any()]
    panels = len(scenes) + (front is not None)
    fig, axes = plt.subplots(1, panels, figsize=(5.2 * panels, 4.4), squeeze=False)
    if front is not None:
        draw_front(axes[0][-1], *front)
    for ax, scene in zip(axes[0], scenes):
        d = data[data["scene"] == scene].sort_values("run_time_s")
        _, ylabel, _, sec_legend = CASES[scene]
        ok = np.isfinite(d["error"])
        ax.scatter(d["run_time_s"][ok], d["error"][ok], s=28, color="#1f77b4", zorder=3, label="run")
        if sec_legend and np.isfinite(d["secondary"]).any():
            ax.scatter(d["run_time_s"], d["secondary"], s=22, facecolors="none", edgecolors="#7f7f7f", zorder=2,
                       label=sec_legend)
        front = d[d["pareto"]].sort_values("run_time_s")
        # The front as a staircase: the best error reachable within each run time.
        ax.step(front["run_time_s"], front["error"], where="post", color="#d62728", lw=1.2, zorder=4)
        ax.scatter(front["run_time_s"], front["error"], s=80, facecolors="none", edgecolors="#d62728", lw=1.5,
                   zorder=5, label="Pareto front")
        for _, r in d[ok].iterrows():
            ax.annotate(r["variant"], (r["run_time_s"], r["error"]), textcoords="offset points", xytext=(4, 3),
                        fontsize=7)
        failed = d[d["blew_up"]]
        if not failed.empty:
            top = 1.1 * d["error"].max() if ok.any() else 1.0
            ax.scatter(failed["run_time_s"], [top] * len(failed), marker="x", s=40, color="#d62728", zorder=5,
                       label="blew up (no error)", clip_on=False)
            for _, r in failed.iterrows():
                ax.annotate(r["variant"], (r["run_time_s"], top), textcoords="offset points", xytext=(4, -9),
                            fontsize=7, color="#d62728")
        ax.set_xscale("log")
        finite = d["error"][ok & (d["error"] > 0)]
        if len(finite) and finite.max() > 30 * finite.min():  # a diverged run beside 2% errors
            ax.set_yscale("log")
        ax.set_xlabel("run time (s): wall time less metric evaluation")
        ax.set_ylabel(ylabel)
        ax.set_title(TITLES[scene], loc="left")
        ax.legend(loc="best", frameon=False)
    fig.suptitle("Accuracy against run time, one factor varied per run (resolution, CFL, kernel, "
                 "diffusion, search, precision)", fontsize=10)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    sphplot.add_footer(fig, label, alert=reduced)
    return fig


def main(argv=None):
    args = sphplot.parse_args(NAME, __doc__.split("\n\n")[0], argv)
    runs, meta = sphplot.load_runs(args.results, NAME)
    sphplot.require_columns(runs, ["scene", "wall_s"])
    label = sphplot.provenance_label(meta, runs)
    data = table(runs)
    print("Accuracy against run time (error; run time = wall_s - validation_s)")
    print(f"  from {args.results}: {label}")
    for scene, d in data.groupby("scene", sort=False):
        print(f"  {scene} ({d['error_name'].iloc[0]}):")
        for _, r in d.sort_values("run_time_s").iterrows():
            mark = "  Pareto" if r["pareto"] else "  BLEW UP" if r["blew_up"] else ""
            sec = f" (secondary {r['secondary']:.4g})" if np.isfinite(r["secondary"]) else ""
            print(f"    {r['variant']:<16} {r['run_time_s']:9.2f} s  error {r['error']:.4g}{sec}{mark}")
    offsets = offset_table(runs)
    if not offsets.empty:
        print("  dambreak front against each data set, with and without a time offset dT in T "
              f"(dT > 0: our front leads; published dT = {PUBLISHED_OFFSET_T:+.3f}):")
        print(f"    {'variant':<16} {'data':<18} {'RMS':>7} {'dT fit':>8} {'RMS(fit)':>9} "
              f"{f'RMS({PUBLISHED_OFFSET_T:+.3f})':>12} "
              f"{'slope b':>8}  trend")
        for _, r in offsets.iterrows():
            print(f"    {r['variant']:<16} {r['data']:<18} {r['rms']:7.4f} {r['offset_T']:+8.4f} {r['rms_offset']:9.4f} "
                  f"{r['rms_published_offset']:12.4f} {r['lead_slope']:+8.4f}  {r['trend']}"
                  f"{'  (dT at the search bound)' if abs(r['offset_T']) >= OFFSET_SEARCH_BOUND_T - 1e-6 else ''}")
    args.out.mkdir(parents=True, exist_ok=True)
    csv = args.out / f"{NAME}.csv"
    with open(csv, "w", encoding="utf-8") as f:
        f.writelines(f"# {k}: {v}\n" for k, v in meta.items())
        data.to_csv(f, index=False)
    print(f"wrote {sphplot._shown(csv)}")
    if not offsets.empty:
        offsets_csv = args.out / f"{NAME}_offsets.csv"
        with open(offsets_csv, "w", encoding="utf-8") as f:
            f.writelines(f"# {k}: {v}\n" for k, v in meta.items())
            offsets.to_csv(f, index=False)
        print(f"wrote {sphplot._shown(offsets_csv)}")
    sphplot.apply_style()
    fig = draw(data, label, sphplot.is_reduced(meta), baseline_front(args.results, offsets))
    sphplot.save_figure(fig, NAME, args.out, description=label)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
