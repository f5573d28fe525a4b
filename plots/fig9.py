"""Figure 9 of the paper (section 5.2): ideal and real speedup per scene. Real: S_n = T_1 / T_n
(mean real update time per step). Ideal: the paper's equation 7 as printed,
n * walltime_ideal_n / walltime_real_n, which reaches n when every device takes the same time
and ignores communication; also shown (markers) is T_1 / T_ideal_n, the speedup had every device
finished at the mean time. Drawn for the threshold balancer when the results have it, else the
simple one.

Usage: python3 plots/fig9.py [--results results/multi-gpu] [--out plots/out]
"""
import numpy as np

import fig6
import multigpu
import sphplot
from sphplot import plt

NAME = "fig9"
COLOURS = ["#1b9e77", "#d95f02", "#7570b3"]


def main(argv=None):
    args = sphplot.parse_args(NAME, __doc__.split("\n\n")[0], argv, experiment=multigpu.EXPERIMENT)
    table, _, meta, label, _ = multigpu.load(args.results)
    has = set(table[table.devices > 1].balancer)
    balancer = "threshold" if "threshold" in has else "simple"
    t = multigpu.pick_balancer(table, balancer)
    print(f"Figure 9 summary, real and ideal speedup, {balancer} balancer (real = T_1/T_n; "
          "ideal (eq. 7) = n * ideal/real; ideal vs T_1 = T_1/T_ideal)")
    print(f"  from {args.results}: {label}")
    for r in t.itertuples():
        head = f"  {r.group}, {r.devices} devices: "
        if np.isfinite(r.speedup):
            print(head + f"real {r.speedup:.3f}, ideal (eq. 7) {r.ideal_eq7:.3f}, ideal vs T_1 {r.ideal_t1:.3f}")
        else:
            print(fig6.describe(r))
    sphplot.apply_style()
    fig, ax = plt.subplots(figsize=(8.5, 4.4))
    counts = fig6.grouped_bars(ax, t, [("speedup", "real"), ("ideal_eq7", "ideal (eq. 7)"),
                                       ("ideal_t1", "T$_1$ / T$_{ideal}$")], COLOURS)
    fig6.linear_lines(ax, counts, COLOURS, "n = {n}")
    top = np.nanmax(t[["speedup", "ideal_eq7", "ideal_t1"]].to_numpy(dtype=float), initial=0)
    ax.set_ylim(0, 1.15 * max(counts + [2, float(top)]))
    ax.set_ylabel("speedup")
    if ax.get_legend_handles_labels()[0]:  # none when no run is allowed a speedup
        ax.legend(frameon=False, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    multigpu.finish(fig, NAME, f"Figure 9: real and ideal speedup, {balancer} balancer", label, meta, args.out)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
