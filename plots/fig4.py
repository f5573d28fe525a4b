"""Figure 4 of the paper (section 5.2): how much the time to update particles' physical
quantity (forces plus integration, `update_ms`) changes from one step to the next,
|t_k - t_{k-1}| / t_{k-1} in percent, for the armadillo and the bunny. The paper states
the change stays within 3% for the armadillo and within 1% for the bunny; that slow drift
is what justifies its simple threshold load balancer.

Usage: python3 plots/fig4.py [--results results/fig4] [--out plots/out]
"""
import numpy as np

import sphplot
from sphplot import plt

NAME = "fig4"
# The paper's claims (section 5.2) and the scales it measured them at.
PAPER_BOUND_PCT = {"armadillo": 3.0, "bunny": 1.0}
PAPER_PARTICLES = {"armadillo": "2980K", "bunny": "3049K"}


def relative_change(steps):
    """(step numbers k, percent change of update_ms against step k-1); k starts at the 2nd step."""
    s = steps.sort_values("step")
    t = s["update_ms"].to_numpy(dtype=float)
    if len(t) < 2:
        raise sphplot.ResultsError(f"{steps.attrs['path']} has fewer than two steps, so nothing changes.")
    prev = t[:-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        pct = np.abs(t[1:] - prev) / prev * 100.0
    # A zero or missing previous time has no relative change; drop it rather than plot inf.
    keep = np.isfinite(pct) & (prev > 0)
    return s["step"].to_numpy()[1:][keep], pct[keep], int((~keep).sum())


def summarise(scene, run_id, particles, k, pct, dropped):
    bound = PAPER_BOUND_PCT.get(scene)
    stats = {"largest": pct.max(), "at": int(k[pct.argmax()]), "p99": np.percentile(pct, 99),
             "median": np.median(pct), "n": len(pct), "bound": bound,
             "within": int((pct <= bound).sum()) if bound is not None else None}
    size = f"{particles:,} particles, " if particles is not None else ""
    line = (f"{scene} run {run_id} ({size}{stats['n']} changes): largest {stats['largest']:.3f}% "
            f"at step {stats['at']}, p99 {stats['p99']:.3f}%, median {stats['median']:.3f}%, ")
    if bound is None:
        line += "no paper bound for this scene"
    else:
        line += (f"within the paper's {bound:g}%: {stats['within']}/{stats['n']} "
                 f"({100.0 * stats['within'] / stats['n']:.1f}%)")
    if dropped:
        line += f"; {dropped} step(s) skipped (previous time zero or missing)"
    return stats, line


def draw(series, label, reduced):
    """series: {scene: [(legend, k, pct, stats)]} -> Figure with one panel per scene."""
    scenes = list(series)
    fig, axes = plt.subplots(len(scenes), 1, figsize=(8.0, 1.2 + 2.5 * len(scenes)), sharex=True, squeeze=False)
    for ax, scene in zip(axes[:, 0], scenes):
        bound = PAPER_BOUND_PCT.get(scene)
        many = len(series[scene]) > 1
        # Scale to the bulk of the data (and the bound), not to a single timing spike;
        # spikes above the top are marked on the edge and counted, never hidden.
        bulk = max(np.percentile(pct, 99.5) for _, _, pct, _ in series[scene])
        top = max(1.5 * (bound or 0), 1.15 * bulk) or 1.0
        for i, (legend, k, pct, st) in enumerate(series[scene]):
            colour = sphplot.SCENE_COLOURS.get(scene) if not many else None
            ax.plot(k, pct, lw=0.7, color=colour, alpha=0.9,
                    label=f"{legend}\nmax {st['largest']:.2f}%\np99 {st['p99']:.2f}%\nmedian {st['median']:.2f}%")
            off = pct > top
            if off.any():
                ax.plot(k[off], np.full(off.sum(), top), "^", ms=4, color=colour or f"C{i}", clip_on=False,
                        label=f"{off.sum()} step(s) off scale\n(above {top:.2g}%)")
        if bound is not None:
            ax.axhline(bound, ls="--", lw=1.0, color="black", label=f"paper: within {bound:g}%")
        ax.set_ylim(0, top)
        ax.set_ylabel(r"$|t_k - t_{k-1}|\,/\,t_{k-1}$ (%)")
        size, paper = series[scene][0][3]["size"], PAPER_PARTICLES.get(scene)
        ax.set_title(scene + (f": {size}" if size else "") + (f" (paper: {paper})" if paper else ""), loc="left")
        # Beside the axes, not on them: any spot inside can hide the very spike that matters.
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False, labelspacing=0.8)
    axes[-1, 0].set_xlabel("time step k")
    fig.suptitle("Figure 4: step-to-step change in the time to update particles' physical quantity\n"
                 "(forces + integration) against the previous step", fontsize=10)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    sphplot.add_footer(fig, label, alert=reduced)
    return fig


def main(argv=None):
    args = sphplot.parse_args(NAME, __doc__.split("\n\n")[0], argv)
    runs, meta, steps = sphplot.load_experiment(args.results, NAME)
    sphplot.require_columns(runs, ["scene"])
    label = sphplot.provenance_label(meta, runs)
    print("Figure 4 summary, change of update_ms (forces + integration) against the previous step")
    print(f"  from {args.results}: {label}")
    series = {}
    for _, run in runs.iterrows():
        df = steps[run["run_id"]]
        sphplot.require_columns(df, ["step", "update_ms"])
        k, pct, dropped = relative_change(df)
        if len(pct) == 0:
            raise sphplot.ResultsError(f"{df.attrs['path']} has no step with a usable update time.")
        particles = int(run["particles"]) if "particles" in run and sphplot.pd.notna(run["particles"]) else None
        stats, line = summarise(run["scene"], run["run_id"], particles, k, pct, dropped)
        stats["size"] = f"{particles:,} particles" if particles is not None else ""
        print("  " + line)
        rep = run.get("repetition")
        legend = f"rep {rep}" if sum(runs["scene"] == run["scene"]) > 1 and rep is not None else f"run {run['run_id']}"
        series.setdefault(run["scene"], []).append((legend, k, pct, stats))
    sphplot.apply_style()
    fig = draw(series, label, sphplot.is_reduced(meta))
    sphplot.save_figure(fig, NAME, args.out, description=label)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
