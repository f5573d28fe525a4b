"""Figure 7 of the paper (section 5.2): speedup of the threshold load balancer (equations 3 to
6) over the simple one, T_simple / T_threshold per scene and device count, where T is the mean
real update time per step (forces + integration on the slowest device). The threshold exists
to stop slices going back and forth, which costs in the balancing and exchange phases rather
than in the update, so the ratio of whole step times (step_ms) is shown beside it, and a second
panel counts the cell slices each balancer moved per 100 steps.

Usage: python3 plots/fig7.py [--results results/multi-gpu] [--out plots/out]
"""
import numpy as np

import multigpu
import sphplot
from sphplot import plt

NAME = "fig7"


def pairs(table):
    """One row per (scene, device count) holding both balancers, with the two ratios."""
    t = table[table.devices > 1]
    cols = ["group", "size", "scene", "devices"]
    p = t[t.balancer == "simple"].merge(t[t.balancer == "threshold"], on=cols, suffixes=("_s", "_t"))
    p = p.sort_values(["scene", "size", "devices"]).reset_index(drop=True)
    if p.empty:
        raise sphplot.ResultsError(f"The {multigpu.EXPERIMENT} results hold no scene run with both the simple and "
                                   f"the threshold balancer on the same devices; run `make {multigpu.EXPERIMENT}`.")
    # Like any speedup, none where subdomains share GPUs (both runs have the same device count).
    p["note"] = p.note_s
    shared = p.note.map(lambda v: isinstance(v, str))
    p["update_ratio"] = np.where(shared, np.nan, p.real_ms_s / p.real_ms_t)
    p["step_ratio"] = np.where(shared, np.nan, p.step_ms_s / p.step_ms_t)
    return p


def main(argv=None):
    args = sphplot.parse_args(NAME, __doc__.split("\n\n")[0], argv, experiment=multigpu.EXPERIMENT)
    table, _, meta, label, _ = multigpu.load(args.results)
    p = pairs(table)
    print("Figure 7 summary, threshold balancer against simple: T_simple/T_threshold of the mean real update "
          "time per step (and of the whole step), slices moved per 100 steps")
    print(f"  from {args.results}: {label}")
    for r in p.itertuples():
        moved = f"slices moved per 100 steps: simple {r.per100_s:.1f}, threshold {r.per100_t:.1f}"
        if isinstance(r.note, str):
            print(f"  {r.group}, {r.devices} devices: {r.note}; {moved}")
        else:
            print(f"  {r.group}, {r.devices} devices: T_simple/T_threshold {r.update_ratio:.3f} (update), "
                  f"{r.step_ratio:.3f} (whole step); {moved}")
    sphplot.apply_style()
    fig, (a, b) = plt.subplots(1, 2, figsize=(12.0, 4.4))
    x = np.arange(len(p))
    names = [f"{g}\n{n} devices" for g, n in zip(p.group, p.devices)]
    for ax, cols in ((a, [("update_ratio", "update time (forces + integration)", "#1b9e77"),
                          ("step_ratio", "whole step (all phases)", "#a6dba0")]),
                     (b, [("per100_s", "simple", "#d95f02"), ("per100_t", "threshold", "#7570b3")])):
        for j, (col, lab, colour) in enumerate(cols):
            vals = p[col].to_numpy(dtype=float)
            bars = ax.bar(x + (j - 0.5) * 0.4, np.nan_to_num(vals), 0.4, color=colour, label=lab)
            ax.bar_label(bars, labels=[f"{v:.3g}" if np.isfinite(v) else "" for v in vals], fontsize=7, padding=1)
        ax.set_xticks(x, names)
        ax.legend(frameon=False, loc="upper left")
    multigpu.mark_shared(a, x, p)
    a.axhline(1.0, color="black", lw=0.8, ls="--")
    top = np.nanmax(p[["update_ratio", "step_ratio"]].to_numpy(dtype=float), initial=1.0)
    a.set(ylabel="T$_{simple}$ / T$_{threshold}$", ylim=(0, 1.3 * top))
    a.set_title("(a) speedup of the threshold balancer over the simple one", loc="left")
    b.set(ylabel="cell slices moved per 100 steps", ylim=(0, 1.2 * max(p.per100_s.max(), p.per100_t.max(), 1)))
    b.set_title("(b) load-balancing moves", loc="left")
    multigpu.finish(fig, NAME, "Figure 7: threshold load balancer against the simple one", label, meta, args.out)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
