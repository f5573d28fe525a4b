"""Stability studies (`make stability`): the largest stable CFL number per scene, the drift of
energy and free surface in still water, high-speed impacts and the armadillo collapse, from
the tables `sphbench stability` writes under results/stability-*/.

Energy drifts are in percent of the "energy scale" (summary.csv's energy_scale): the initial
kinetic energy plus the potential energy above the lowest fluid particle's floor.

Usage: python3 plots/stability.py [--results results] [--out plots/out]
"""
import argparse
from pathlib import Path

import sphplot
from sphplot import plt

NAME = "stability"
STUDIES = ["stability-cfl", "stability-still-water", "stability-impact", "stability-armadillo"]
DEFAULT_CFL = 0.2  # the scenes' default (set_common_physics)


def load(results, study, required):
    path = Path(results) / study / "summary.csv"
    if not path.is_file():
        if required:
            raise sphplot.ResultsError(f"{path} does not exist; run `make stability` first.")
        return None, None
    return sphplot.read_csv_with_metadata(path)


def series(results, study, summary):
    out = {}
    for _, run in summary.iterrows():
        df, _ = sphplot.read_csv_with_metadata(Path(results) / study / run["series"])
        out[run["run_id"]] = df
    return out


def draw_cfl(ax, cfl):
    labels = list(cfl["run_id"])
    x = range(len(labels))
    stable, unstable = cfl["cfl_stable"].astype(float), cfl["cfl_unstable"].astype(float)
    ax.bar(x, stable, color="#1f77b4", label="largest stable")
    top = unstable.where(unstable > 0, stable)
    ax.bar(x, top - stable, bottom=stable, color="#d95f02", alpha=0.5, label="limit lies here")
    for i, (s, u, q) in enumerate(zip(stable, unstable, cfl["unstable_quantity"].fillna(""))):
        text = f"{s:.2f}" + (f"\n{q}" if q else "\n(none up to cfl_high)")
        ax.text(i, max(s, u), text, ha="center", va="bottom", fontsize=7)
    ax.axhline(DEFAULT_CFL, color="k", lw=0.8, ls="--", label=f"default cfl {DEFAULT_CFL}")
    ax.set_xticks(list(x), labels, rotation=15, fontsize=8)
    ax.set_ylabel("CFL number")
    ax.set_ylim(0, 1.3 * max(float(top.max()), DEFAULT_CFL))
    ax.set_title(f"largest stable CFL (reach {cfl['target_time'].iloc[0]:g} s without a blow-up)", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")


def draw_still(ax, run, df):
    dp = float(run["dp"])
    ax.plot(df["time"], 100 * df["total_drift"], color="#1f77b4", label="total energy")
    ax.set_xlabel("simulated time (s)")
    ax.set_ylabel("energy drift (% of energy scale)", color="#1f77b4")
    twin = ax.twinx()
    twin.plot(df["time"], df["free_surface_drift"] / dp, color="#d95f02", label="free surface")
    twin.set_ylabel("free-surface drift (spacings)", color="#d95f02")
    ax.set_title(f"still water: {run['run_id']}, {int(run['steps']):,} steps, {int(run['particles']):,} particles",
                 fontsize=9)


def draw_energy_runs(ax, summary, data, title):
    for _, run in summary.iterrows():
        df = data[run["run_id"]]
        blew = not sphplot.as_bool(sphplot.pd.Series([run["stable"]])).iloc[0]
        line, = ax.plot(df["time"], 100 * df["total_drift"], label=run["run_id"] + (" (blew up)" if blew else ""))
        if blew:
            ax.plot(df["time"].iloc[-1], 100 * df["total_drift"].iloc[-1], "x", color=line.get_color(), ms=8)
    ax.set_xlabel("simulated time (s)")
    ax.set_ylabel("total energy drift (% of energy scale)")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)


def main(argv=None):
    p = argparse.ArgumentParser(prog=f"{NAME}.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--results", type=Path, default=sphplot.REPO / "results",
                   help="folder holding results/stability-*/ (default: results)")
    p.add_argument("--out", type=Path, default=sphplot.REPO / "plots" / "out")
    args = p.parse_args(argv)
    cfl, meta = load(args.results, STUDIES[0], True)
    still, _ = load(args.results, STUDIES[1], True)
    impact, _ = load(args.results, STUDIES[2], True)
    armadillo, _ = load(args.results, STUDIES[3], False)
    label = sphplot.provenance_label(meta, cfl)
    print("Stability summary")
    print(f"  from {args.results}: {label}")
    for _, r in cfl.iterrows():
        print(f"  {r['run_id']}: largest stable cfl {r['cfl_stable']:.3g}, smallest unstable {r['cfl_unstable']:.3g}"
              f" ({r['unstable_quantity'] if isinstance(r['unstable_quantity'], str) else 'none'})")
    for study, table in (("still water", still), ("impact", impact), ("armadillo", armadillo)):
        if table is None:
            continue
        for _, r in table.iterrows():
            state = "stable" if sphplot.as_bool(sphplot.pd.Series([r["stable"]])).iloc[0] else \
                f"BLEW UP at step {r['failed_step']} ({r['quantity']})"
            print(f"  {study} {r['run_id']}: {state}, {int(r['steps'])} steps to t = {r['time']:.3g} s, energy drift "
                  f"{100 * r['total_drift']:+.2f}% (largest {100 * r['largest_total_drift']:+.2f}%), free surface "
                  f"{r['free_surface_drift'] / r['dp']:+.3f} dp")
    sphplot.apply_style()
    panels = 4 if armadillo is not None else 3
    fig, axes = plt.subplots(panels, 1, figsize=(8.0, 1.0 + 3.0 * panels))
    draw_cfl(axes[0], cfl)
    draw_still(axes[1], still.iloc[0], series(args.results, STUDIES[1], still)[still["run_id"].iloc[0]])
    draw_energy_runs(axes[2], impact, series(args.results, STUDIES[2], impact),
                     "dam break launched at the far wall (initial_speed)")
    if armadillo is not None:
        draw_energy_runs(axes[3], armadillo, series(args.results, STUDIES[3], armadillo), "armadillo collapse")
    fig.suptitle("Stability: CFL limits, still water, impacts", fontsize=10)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    sphplot.add_footer(fig, label, alert=sphplot.is_reduced(meta))
    sphplot.save_figure(fig, NAME, args.out, description=label)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
