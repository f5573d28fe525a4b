"""Section 4.1 of the paper: the cell linked list (CLL: neighbours searched from the cells every
step) against Verlet lists (VL: each particle's neighbour list kept over several steps), in
time and memory, per scene and scale. Prints a Markdown table, saves it as table_vl.md and
draws table_vl.png/pdf.

Times are medians over steps. update_ms (forces + integration) leaves the list builds out,
since they are timed in neighbour_list_ms; step_ms holds every phase, builds included.

Usage: python3 plots/table_vl.py [--results results/cll-vs-vl] [--out plots/out]
"""
import numpy as np

import sphplot
from sphplot import pd, plt

NAME = "table_vl"
EXPERIMENT = "cll-vs-vl"
CLAIMS = ["Paper (section 4.1): VL about 6% faster, about 30x the memory (Dominguez et al.); "
          "about 1 KB per particle (Rustico et al.).",
          "Ratios are VL / CLL: a time ratio of 0.94 is VL 6% faster, a memory ratio of 30 is 30x the memory."]
NUM = ["update_ms_median", "step_ms_median", "bytes_per_particle", "neighbour_list_bytes_per_particle"]


def compare(runs):
    """One row per scene, size, search setting and VL setting (skin, rebuild_every), with ratios."""
    runs = runs.copy()
    runs["group"] = sphplot.scene_labels(runs)
    runs["size"] = pd.to_numeric(sphplot.column(runs, "set.particles", np.nan), errors="coerce").fillna(
        pd.to_numeric(sphplot.column(runs, "particles", 0), errors="coerce"))
    runs["vl"] = sphplot.as_bool(sphplot.column(runs, "verlet", "false"))
    for c in NUM:
        runs[c] = pd.to_numeric(sphplot.column(runs, c, np.nan), errors="coerce")
    for c in ("cells_per_support", "merge", "skin", "rebuild_every"):  # 10.0 (a column with gaps) -> "10"
        runs[c] = sphplot.column(runs, c, "").map(lambda v: "" if pd.isna(v) else f"{v:g}" if isinstance(v, float)
                                                  else str(v))
    search = ["scene", "size", "group", "cells_per_support", "merge"]
    # Repetitions pool into their median.
    cll = runs[~runs.vl].groupby(search, as_index=False)[NUM].median()
    vl = runs[runs.vl].groupby(search + ["skin", "rebuild_every"], as_index=False)[NUM].median()
    t = vl.merge(cll, on=search, suffixes=("_vl", "_cll"))
    if t.empty:
        raise sphplot.ResultsError(f"The {EXPERIMENT} results hold no scene with both a CLL and a Verlet-list run.")
    t["update_ratio"] = t.update_ms_median_vl / t.update_ms_median_cll
    t["step_ratio"] = t.step_ms_median_vl / t.step_ms_median_cll
    t["mem_ratio"] = t.bytes_per_particle_vl / t.bytes_per_particle_cll
    return t.sort_values(["scene", "size"]).reset_index(drop=True)


def fmt(v, spec):
    return format(v, spec) if pd.notna(v) and np.isfinite(v) else "n/a"


def markdown(t, label):
    several = t[["cells_per_support", "merge"]].drop_duplicates().shape[0] > 1
    head = ["scene", "VL skin / rebuild every", "CLL update ms", "VL update ms (no builds)", "CLL step ms",
            "VL step ms (with builds)", "update VL/CLL", "step VL/CLL", "CLL B/particle", "VL B/particle",
            "memory VL/CLL"]
    has_list = t.neighbour_list_bytes_per_particle_vl.notna().any()
    if has_list:
        head.append("VL list B/particle")
    lines = [f"_{c}_" for c in CLAIMS] + ["", f"Measured on: {label}", "",
                                          "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in t.itertuples():
        scene = r.group + (f" (n={r.cells_per_support}, merge {r.merge})" if several else "")
        cells = [scene, f"{r.skin} / {r.rebuild_every}", fmt(r.update_ms_median_cll, ".3f"),
                 fmt(r.update_ms_median_vl, ".3f"), fmt(r.step_ms_median_cll, ".3f"), fmt(r.step_ms_median_vl, ".3f"),
                 fmt(r.update_ratio, ".3f"), fmt(r.step_ratio, ".3f"), fmt(r.bytes_per_particle_cll, ".0f"),
                 fmt(r.bytes_per_particle_vl, ".0f"), fmt(r.mem_ratio, ".2f") + "x"]
        if has_list:
            cells.append(fmt(r.neighbour_list_bytes_per_particle_vl, ".0f"))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def draw(t, label, reduced):
    fig, (a, b) = plt.subplots(1, 2, figsize=(11.0, 4.2))
    names = [f"{g}\nskin {s} / every {k}" for g, s, k in zip(t.group, t.skin, t.rebuild_every)]
    x = np.arange(len(t))
    series = [(a, "update_ms_median_cll", "CLL update", "#1b9e77"), (a, "update_ms_median_vl", "VL update", "#d95f02"),
              (a, "step_ms_median_cll", "CLL step", "#a6dba0"), (a, "step_ms_median_vl", "VL step (builds)", "#fdb863"),
              (b, "bytes_per_particle_cll", "CLL", "#1b9e77"), (b, "bytes_per_particle_vl", "VL", "#d95f02")]
    for k, (ax, col, lab, colour) in enumerate(series):
        j, m = (k, 4) if ax is a else (k - 4, 2)
        vals = t[col].to_numpy(dtype=float)
        bars = ax.bar(x + (j - (m - 1) / 2) * 0.8 / m, np.nan_to_num(vals), 0.8 / m, color=colour, label=lab)
        texts = [fmt(v, ".3g" if ax is a else ".0f") for v in vals]
        if col == "bytes_per_particle_vl":  # the memory ratio on the VL bar
            texts = [f"{v} ({fmt(r, '.3g')}x CLL)" for v, r in zip(texts, t.mem_ratio)]
        ax.bar_label(bars, labels=texts, fontsize=6.5, padding=1)
    b.axhline(1024, ls="--", color="black", lw=0.8, label="1 KB (Rustico et al.)")
    for ax in (a, b):
        ax.set_xticks(x, names)
        ax.legend(frameon=False, fontsize=7, loc="upper left")
    a.set(ylabel="median time per step (ms)", ylim=(0, 1.25 * np.nanmax(t[[s[1] for s in series[:4]]].to_numpy())))
    a.set_title("(a) time: update (no list builds) and whole step", loc="left")
    top = np.nanmax(t[["bytes_per_particle_cll", "bytes_per_particle_vl"]].to_numpy(dtype=float), initial=1024)
    b.set(ylabel="bytes allocated per particle", ylim=(0, 1.2 * max(top, 1024)))
    b.set_title("(b) memory per particle", loc="left")
    fig.suptitle("CLL against Verlet lists (paper section 4.1). " + CLAIMS[0].split(": ", 1)[1], fontsize=9)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    sphplot.add_footer(fig, label, alert=reduced)
    return fig


def main(argv=None):
    args = sphplot.parse_args(NAME, __doc__.split("\n\n")[0], argv, experiment=EXPERIMENT)
    runs, meta = sphplot.load_runs(args.results, EXPERIMENT)
    sphplot.require_columns(runs, ["scene", "update_ms_median", "step_ms_median"])
    label = sphplot.provenance_label(meta, runs)
    t = compare(runs)
    text = markdown(t, label)
    print(f"CLL vs Verlet lists summary, from {args.results}\n")
    print(text)
    args.out.mkdir(parents=True, exist_ok=True)
    md = args.out / f"{NAME}.md"
    md.write_text(text, encoding="utf-8")
    print(f"wrote {sphplot._shown(md)}")
    sphplot.apply_style()
    sphplot.save_figure(draw(t, label, sphplot.is_reduced(meta)), NAME, args.out, description=label)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
