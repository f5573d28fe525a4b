"""Figure 6 of the paper (section 5.2): speedup on several GPUs with the simple load balancer,
S_n = T_1 / T_n, where T is the mean real update time per step (the slowest device's forces +
integration) and T_1 comes from the scene's 1-device run. The paper finds the balancer's
effect improving as the particle count grows.

Usage: python3 plots/fig6.py [--results results/multi-gpu] [--out plots/out]
"""
import numpy as np

import multigpu
import sphplot
from sphplot import plt

NAME = "fig6"
BALANCER = "simple"


def describe(r):
    """One summary line for a run; a speedup only where the run is allowed one."""
    head = f"  {r.group}, {r.devices} devices: "
    if isinstance(r.note, str):
        return head + f"{r.note} (real {r.real_ms:.3f} ms per step)"
    if not np.isfinite(r.speedup):
        return head + f"no 1-device run of this scene, so no speedup (real {r.real_ms:.3f} ms per step)"
    return head + (f"S_{r.devices} = T_1/T_{r.devices} = {r.speedup:.3f} "
                   f"(T_1 {r.T1:.3f} ms, T_{r.devices} {r.real_ms:.3f} ms)")


def grouped_bars(ax, t, columns, colours):
    """Bars per (scene, device count) for each column; leaves out NaN and marks shared GPUs."""
    groups, counts = list(dict.fromkeys(t.group)), sorted(t.devices.unique())
    width = 0.8 / (len(counts) * len(columns))
    for i, n in enumerate(counts):
        for j, (col, lab) in enumerate(columns):
            rows = t[t.devices == n].set_index("group").reindex(groups)
            x = np.arange(len(groups)) - 0.4 + width * (i * len(columns) + j + 0.5)
            vals = rows[col].to_numpy(dtype=float)
            bars = ax.bar(x, np.nan_to_num(vals), width, color=colours[i % len(colours)],
                          alpha=(1.0, 0.55, 0.3)[j % 3], hatch=("", "//", "..")[j % 3],
                          label=f"{lab}, {n} devices" if np.isfinite(vals).any() else None)
            ax.bar_label(bars, labels=[f"{v:.2f}" if np.isfinite(v) else "" for v in vals], fontsize=7, padding=1)
            multigpu.mark_shared(ax, x, rows)
    ax.set_xticks(np.arange(len(groups)), groups)
    # The linear line only where some run has a speedup to hold against it.
    return [n for n in counts if np.isfinite(t[t.devices == n][columns[0][0]].to_numpy(dtype=float)).any()]


def linear_lines(ax, counts, colours, label):
    """A dashed line at each device count n: the linear speedup a run of n devices could reach."""
    for k, n in enumerate(counts):
        ax.axhline(n, ls="--", lw=0.9, color=colours[k % len(colours)], label=label.format(n=n))


def main(argv=None):
    args = sphplot.parse_args(NAME, __doc__.split("\n\n")[0], argv, experiment=multigpu.EXPERIMENT)
    table, _, meta, label, _ = multigpu.load(args.results)
    t = multigpu.pick_balancer(table, BALANCER)
    print(f"Figure 6 summary, speedup S_n = T_1/T_n of the mean real update time per step, {BALANCER} balancer")
    print(f"  from {args.results}: {label}")
    for r in t.itertuples():
        print(describe(r))
    sphplot.apply_style()
    fig, ax = plt.subplots(figsize=(8.0, 4.4))
    counts = grouped_bars(ax, t, [("speedup", "real speedup")], ["#1b9e77", "#d95f02", "#7570b3"])
    linear_lines(ax, counts, ["#1b9e77", "#d95f02", "#7570b3"], "linear: {n}")
    ax.set_ylim(0, 1.15 * max(counts + [2]))
    ax.set_ylabel("speedup T$_1$ / T$_n$ (update time)")
    if ax.get_legend_handles_labels()[0]:  # none when no run is allowed a speedup
        ax.legend(frameon=False, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    multigpu.finish(fig, NAME, f"Figure 6: speedup on several GPUs, {BALANCER} balancer", label, meta, args.out)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
