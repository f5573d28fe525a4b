"""Figure 3 of the paper (section 4.4): speedup on one GPU of the time to update particles'
physical quantity (forces plus integration, `update_ms`) over the traditional cell linked list
(CLL: cell size = support radius h, 27 cells searched one by one), for Cell Merging (the cells
of a Z column read as one range), Smaller Cell n=2 (cell size h/2) and both together. The paper
finds Smaller Cell alone about 80% slower and the two together the fastest.

A second panel sweeps n = 1..4 with and without merging; a third shows the candidates each
particle tests against the search volume (2 + 1/n)^3 h^3 (27, 15.6, 12.7, 11.4 h^3).

Usage: python3 plots/fig3.py [--results results/fig3] [--out plots/out]
"""
import numpy as np

import sphplot
from sphplot import pd, plt

NAME = "fig3"
# (cells_per_support, merge) -> name, as in the paper's Figure 3
VARIANTS = {(1, True): "Cell Merging", (2, False): "Smaller Cell n=2", (2, True): "both (n=2 + merging)"}
VARIANT_COLOURS = ["#1b9e77", "#d95f02", "#7570b3"]


def geometric(n):
    """Side (2 + 1/n) h, so the searched volume is (2 + 1/n)^3 h^3: 27 for n=1, 15.625 for n=2."""
    return (2.0 + 1.0 / n) ** 3


def single_gpu_cll(runs):
    """Runs of the cell-list search on one device, with (group, size, n, merge, T, cand) columns."""
    runs = runs.copy()
    keep = ~sphplot.as_bool(sphplot.column(runs, "verlet", "false"))
    keep &= pd.to_numeric(sphplot.column(runs, "devices", 1), errors="coerce").fillna(1) == 1
    runs = runs[keep]
    runs["group"] = sphplot.scene_labels(runs)
    runs["size"] = pd.to_numeric(sphplot.column(runs, "set.particles", np.nan), errors="coerce").fillna(
        pd.to_numeric(sphplot.column(runs, "particles", 0), errors="coerce"))
    runs["n"] = pd.to_numeric(sphplot.column(runs, "cells_per_support", 1), errors="coerce").fillna(1).astype(int)
    runs["merging"] = sphplot.as_bool(sphplot.column(runs, "merge", "false"))
    runs["T"] = pd.to_numeric(runs["update_ms_median"], errors="coerce")
    cand = pd.to_numeric(sphplot.column(runs, "candidates_per_step", np.nan), errors="coerce")
    neigh = pd.to_numeric(sphplot.column(runs, "neighbours_per_step", np.nan), errors="coerce")
    particles = pd.to_numeric(sphplot.column(runs, "particles", np.nan), errors="coerce")
    runs["cand"], runs["neigh"] = cand / particles, neigh / particles
    # Repetitions of one configuration pool into their median.
    table = runs.groupby(["scene", "size", "group", "n", "merging"], as_index=False)[["T", "cand", "neigh"]].median()
    return table.sort_values(["scene", "size", "n", "merging"])


def speedups(table):
    """{group: (T_CLL, {variant name: speedup})}; a group without its CLL run is left out."""
    out = {}
    for group, g in table.groupby("group", sort=False):
        t = {(int(r.n), bool(r.merging)): r.T for r in g.itertuples()}
        base = t.get((1, False))
        if base is None or not base > 0:
            print(f"  {group}: no CLL run (n=1, no merging), so no speedup")
            continue
        out[group] = (base, {name: base / t[k] if t.get(k, 0) > 0 else np.nan for k, name in VARIANTS.items()})
    return out


def draw(table, sp, label, reduced):
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(13.0, 4.2), gridspec_kw={"width_ratios": [1.4, 1, 1]})
    groups = list(sp)
    x, w = np.arange(len(groups)), 0.8 / len(VARIANTS)
    for i, (name, colour) in enumerate(zip(VARIANTS.values(), VARIANT_COLOURS)):
        vals = [sp[g][1][name] for g in groups]
        bars = a.bar(x + (i - 1) * w, vals, w, color=colour, label=name)
        a.bar_label(bars, labels=[f"{v:.2f}" if np.isfinite(v) else "n/a" for v in vals], fontsize=7, padding=1)
    a.axhline(1.0, color="black", lw=0.8, ls="--", label="CLL (= 1)")
    a.set_xticks(x, groups)
    a.set_ylabel("speedup of update time over CLL")
    a.set_title("(a) speedup on one device, per scene", loc="left")
    a.legend(loc="upper center", frameon=False, ncol=2)
    a.set_ylim(0, 1.45 * max([v for g in groups for v in sp[g][1].values() if np.isfinite(v)] + [1.0]))
    for k, (group, g) in enumerate(table.groupby("group", sort=False)):
        base = g[(g.n == 1) & ~g.merging]["T"]
        colour = f"C{k}"
        for merge, ls, mk in ((False, "-", "o"), (True, "--", "s")):
            s = g[g.merging == merge]
            if len(base) and len(s):
                b.plot(s.n, s["T"] / base.iloc[0], ls=ls, marker=mk, color=colour,
                       label=f"{group}, {'merging' if merge else 'no merging'}")
        s = g[~g.merging] if (~g.merging).any() else g[g.merging]
        if s["cand"].notna().any():
            first_group = not c.lines  # the line styles are explained once; colours match panel (b)
            c.plot(s.n, s["cand"], "o-", color=colour, label="candidates tested" if first_group else None)
            first = s[s.n == s.n.min()].iloc[0]
            ns = np.arange(1, 5)
            c.plot(ns, first["cand"] * geometric(ns) / geometric(first.n), ":", color=colour, lw=2,
                   label="(2+1/n)$^3$, scaled to n=1" if first_group else None)
            if s["neigh"].notna().any():
                c.plot(s.n, s["neigh"], "^--", color=colour, alpha=0.6, ms=4,
                       label="neighbours (within h)" if first_group else None)
    b.axhline(1.0, color="black", lw=0.8)
    b.set(xlabel="n (cell size = h / n)", ylabel="update time / CLL (n=1, no merging)", xticks=range(1, 5))
    b.set_title("(b) sweep over n, with and without merging", loc="left")
    b.legend(frameon=False, fontsize=6.5)
    c.set(xlabel="n (cell size = h / n)", ylabel="per particle per step", xticks=range(1, 5), ylim=(0, None))
    c.set_title("(c) candidates tested vs search volume", loc="left")
    volumes = ("search volume (2+1/n)$^3$h$^3$: " + ", ".join(f"{geometric(n):.3g}" for n in range(1, 5))
               + "\nfor n = 1..4; sphere of radius h: 4.19 h$^3$")
    if c.lines:
        c.legend(frameon=False, fontsize=7, loc="upper right", title=volumes, title_fontsize=7)
    else:
        c.text(0.5, 0.5, "no candidates_per_step in runs.csv", transform=c.transAxes, ha="center")
    fig.suptitle("Figure 3: speedup of the update time (forces + integration) on one device over traditional CLL",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    sphplot.add_footer(fig, label, alert=reduced)
    return fig


def main(argv=None):
    args = sphplot.parse_args(NAME, __doc__.split("\n\n")[0], argv)
    runs, meta = sphplot.load_runs(args.results, NAME)
    sphplot.require_columns(runs, ["scene", "update_ms_median"])
    label = sphplot.provenance_label(meta, runs)
    print("Figure 3 summary, speedup of update_ms (forces + integration, median per run) over CLL "
          "(n=1, no merging)")
    print(f"  from {args.results}: {label}")
    table = single_gpu_cll(runs)
    sp = speedups(table)
    if not sp:
        raise sphplot.ResultsError(f"{args.results} holds no CLL run (cells_per_support 1, merge false) "
                                   "to compare with.")
    width = max(len(g) for g in sp) + 2
    print("  " + "scene".ljust(width) + "CLL ms".rjust(10) + "".join(f"{v:>22}" for v in VARIANTS.values()))
    for group, (base, s) in sp.items():
        cells = "".join(f"{s[v]:>21.3f}x" if np.isfinite(s[v]) else f"{'n/a':>22}" for v in VARIANTS.values())
        print("  " + group.ljust(width) + f"{base:>10.3f}" + cells)
    print("  sweep: update time / CLL, candidates per particle per step (geometric: (2+1/n)^3 scaled to n=1)")
    for group, g in table.groupby("group", sort=False):
        if group not in sp:
            continue
        first = g[g.n == g.n.min()]["cand"].iloc[0]
        for n, s in g.groupby("n"):
            rel = ", ".join(f"{'merging' if m else 'no merging'} {t / sp[group][0]:.3f}"
                            for m, t in zip(s.merging, s["T"]))
            cand = s["cand"].iloc[0]
            extra = (f"; candidates {cand:.1f} (geometric {first * geometric(n) / geometric(g.n.min()):.1f})"
                     if np.isfinite(cand) else "")
            print(f"  {group} n={n}: {rel}{extra}")
    sphplot.apply_style()
    fig = draw(table[table.group.isin(list(sp))], sp, label, sphplot.is_reduced(meta))
    sphplot.save_figure(fig, NAME, args.out, description=label)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
