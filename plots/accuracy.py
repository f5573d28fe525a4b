"""Issue 6: validation error against run time. Each run of experiments/accuracy.toml varies
one factor (resolution, CFL, kernel, density diffusion, search strategy, precision) around a
baseline; the figure puts its error against its run time, one panel per validation case, and
marks the Pareto front: the runs that no other run beats on both time and error.

  dam break: RMS of the surge front Z = x/a against Martin and Moyce (1952), filled markers
             (Koshizuka and Oka (1996), open markers, for comparison; the front uses the first)
  tank:      relative RMS of the pressure against rho0 g (H - z) at the end of the run

Run time is the run's wall time less the time spent evaluating the metric (wall_s - validation_s).
A run that blew up (its `blow_up` cell says where) has no error: it is drawn as a cross on the
top edge at the time it ran, and is never on the front.
Also writes NAME.csv beside the figure: one row per run with its time, error and front membership.

Usage: python3 plots/accuracy.py [--results results/accuracy] [--out plots/out]
"""
import numpy as np

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


def draw(data, label, reduced):
    scenes = [s for s in CASES if (data["scene"] == s).any()]
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.2 * len(scenes), 4.4), squeeze=False)
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
    args.out.mkdir(parents=True, exist_ok=True)
    csv = args.out / f"{NAME}.csv"
    with open(csv, "w", encoding="utf-8") as f:
        f.writelines(f"# {k}: {v}\n" for k, v in meta.items())
        data.to_csv(f, index=False)
    print(f"wrote {sphplot._shown(csv)}")
    sphplot.apply_style()
    fig = draw(data, label, sphplot.is_reduced(meta))
    sphplot.save_figure(fig, NAME, args.out, description=label)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
