"""Shared loading for Figures 5 to 9 of the paper (section 5.2), all drawn from ONE experiment,
`multi-gpu`, whose runs vary the number of subdomains (`devices`: 1, 2, maybe 4) and the load
balancer (`simple`, `threshold`) per scene (scene + set.particles).

Per run, from its step file: the real wall time of a step, `update_ms` (the slowest device's
forces + integration, the paper's "walltime") and the ideal one, `update_ideal_ms` (the mean
over devices), each averaged over the recorded steps. From those:
  real speedup        S_n = T_1 / T_n, T = mean real update time per step, T_1 from the scene's
                      1-device run;
  ideal speedup (7)   n * walltime_ideal_n / walltime_real_n, the paper's equation 7 as printed:
                      it measures balance only (n when every device takes the same time), it
                      never looks at T_1;
  ideal vs T_1        T_1 / T_ideal_n: the speedup had every device finished at the mean time.
A run with more subdomains than the machine has GPUs shares GPUs between subdomains: its
per-device times are reported, but never a speedup.
"""
import numpy as np

import sphplot
from sphplot import pd, plt

EXPERIMENT = "multi-gpu"


def gpu_names(meta, runs):
    """Names of the machine's physical GPUs: `devices` (else `cuda`) metadata, 'A; B | driver ...'."""
    text = meta.get("devices") or meta.get("cuda") or ""
    names = [n.strip() for n in text.split(" | ")[0].split(";")]
    names = [n for n in names if n and n.lower() not in ("host", "none") and not n.startswith("driver ")]
    if names or text.strip():  # "host" or "none" says: no GPU
        return names
    best = []  # fallback: a device cell 'A; B' names distinct GPUs; 'N subdomains on A' only one
    for d in sphplot.column(runs, "device", "").dropna().astype(str):
        found = [x.strip() for x in d.split(" subdomains on ")[-1].split(";") if x.strip()]
        found = [x for x in found if x.lower() not in ("host", "none")]
        best = found if len(found) > len(best) else best
    return best


def shared_note(n, gpus):
    """None when each of the n subdomains can have its own GPU; else the warning to show."""
    if n <= 1 or n <= gpus:
        return None
    return f"{n} subdomains on {gpus} GPU{'' if gpus == 1 else 's'}: per-device times only, no speedup"


def per_run(runs, steps, gpus):
    """One row per run: group, devices, balancer, mean real/ideal/step ms, slices moved."""
    rows = []
    labels = sphplot.scene_labels(runs)
    size = pd.to_numeric(sphplot.column(runs, "set.particles", np.nan), errors="coerce").fillna(
        pd.to_numeric(sphplot.column(runs, "particles", 0), errors="coerce"))
    for i, run in runs.iterrows():
        s = steps[run["run_id"]]
        sphplot.require_columns(s, ["update_ms", "update_ideal_ms"])
        n = run.get("devices")
        n = int(n) if pd.notna(n) else int(sphplot.column(s, "subdomains", 1).max())
        moved = pd.to_numeric(sphplot.column(s, "slices_moved", 0), errors="coerce").fillna(0)
        rows.append({"run_id": run["run_id"], "scene": run["scene"], "size": size[i], "group": labels[i],
                     "devices": n, "balancer": str(run.get("balancer", "none")), "steps": len(s),
                     "real_ms": s["update_ms"].mean(), "ideal_ms": s["update_ideal_ms"].mean(),
                     "step_ms": sphplot.column(s, "step_ms", np.nan).mean(),
                     "slices": moved.sum(), "per100": 100.0 * moved.sum() / max(len(s), 1),
                     "note": shared_note(n, gpus)})
    return pd.DataFrame(rows)


def with_speedups(table):
    """Repetitions pooled (mean); adds T1, real speedup, eq. 7 and T1/ideal; NaN where not allowed."""
    keys = ["scene", "size", "group", "devices", "balancer"]
    t = table.groupby(keys, as_index=False, sort=False).agg(
        run_id=("run_id", "first"), steps=("steps", "sum"), real_ms=("real_ms", "mean"),
        ideal_ms=("ideal_ms", "mean"), step_ms=("step_ms", "mean"), slices=("slices", "sum"),
        per100=("per100", "mean"), note=("note", "first"))
    t1 = t[t.devices == 1].groupby("group")["real_ms"].mean()
    t["T1"] = t.group.map(t1)
    ok = t.note.isna() & t.T1.notna() & (t.real_ms > 0)
    t["speedup"] = np.where(ok, t.T1 / t.real_ms, np.nan)                      # S_n = T_1 / T_n
    t["ideal_eq7"] = np.where(ok, t.devices * t.ideal_ms / t.real_ms, np.nan)  # eq. 7 as printed
    t["ideal_t1"] = np.where(ok, t.T1 / t.ideal_ms, np.nan)                    # T_1 / T_ideal_n
    return t.sort_values(["scene", "size", "devices", "balancer"]).reset_index(drop=True)


def load(results):
    """(table with speedups, steps, meta, provenance label, number of physical GPUs)."""
    runs, meta, steps = sphplot.load_experiment(results, EXPERIMENT)
    sphplot.require_columns(runs, ["scene"])
    names = gpu_names(meta, runs)
    table = with_speedups(per_run(runs, steps, len(names)))
    shown = pd.DataFrame({"device": ["; ".join(names) or "host"]})
    if "backend" in runs.columns:
        shown["backend"] = ", ".join(map(str, runs["backend"].dropna().unique()))
    label = sphplot.provenance_label(meta, shown) + f" | {len(names)} physical GPU(s)"
    return table, steps, meta, label, len(names)


def pick_balancer(table, wanted):
    """Rows of one balancer on more than one device; a ResultsError when there are none."""
    t = table[(table.balancer == wanted) & (table.devices > 1)]
    if t.empty:
        raise sphplot.ResultsError(f"The {EXPERIMENT} results hold no run of the {wanted} balancer on more "
                                   f"than one device; run `make {EXPERIMENT}` with balancer = \"{wanted}\".")
    return t


def category_labels(t):
    return [f"{g}\n{n} devices" for g, n in zip(t.group, t.devices)]


def mark_shared(ax, x, t, y=0.02):
    """Writes the shared-GPU warning where a run's speedup is left out."""
    for xi, note in zip(x, t.note):
        if isinstance(note, str):
            ax.text(xi, y, note.replace(": ", ":\n"), rotation=90, ha="center", va="bottom", fontsize=6,
                    color="#b00000", transform=ax.get_xaxis_transform(),
                    bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.85, "pad": 1})


def finish(fig, name, title, label, meta, out):
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    sphplot.add_footer(fig, label, alert=sphplot.is_reduced(meta))
    sphplot.save_figure(fig, name, out, description=label)


def real_vs_ideal(name, balancer, figure, argv=None):
    """Figures 5 and 8: mean real and ideal update time per scene, and the per-step series of
    the largest scene, for one balancer."""
    args = sphplot.parse_args(name, f"Figure {figure}: real vs ideal wall time, {balancer} balancer", argv,
                              experiment=EXPERIMENT)
    table, steps, meta, label, gpus = load(args.results)
    t = pick_balancer(table, balancer)
    print(f"Figure {figure} summary, real (slowest device) vs ideal (mean over devices) update time per step, "
          f"{balancer} balancer")
    print(f"  from {args.results}: {label}")
    for r in t.itertuples():
        line = (f"  {r.group}, {r.devices} devices: real {r.real_ms:.3f} ms, ideal {r.ideal_ms:.3f} ms per step, "
                f"real/ideal {r.real_ms / r.ideal_ms:.3f} ({r.steps} steps)")
        print(line + (f"; {r.note}" if isinstance(r.note, str) else ""))
    sphplot.apply_style()
    fig, (a, b) = plt.subplots(1, 2, figsize=(12.0, 4.4), gridspec_kw={"width_ratios": [1.2, 1]})
    x = np.arange(len(t))
    for off, col, colour, lab in ((-0.2, "real_ms", "#d95f02", "real (slowest device)"),
                                  (0.2, "ideal_ms", "#7570b3", "ideal (mean over devices)")):
        bars = a.bar(x + off, t[col], 0.4, color=colour, label=lab,
                     hatch=["//" if isinstance(nt, str) else "" for nt in t.note])
        a.bar_label(bars, fmt="%.3g", fontsize=7, padding=1)
    a.set_xticks(x, category_labels(t))
    a.set_ylabel("update time per step, mean over steps (ms)")
    shared = t.note.map(lambda v: isinstance(v, str)).any()
    a.set_title("(a) per scene and device count" + (" (hatched: GPUs shared)" if shared else ""), loc="left")
    a.legend(frameon=False, loc="upper left")
    a.set_ylim(0, 1.2 * t.real_ms.max())
    big, top = t[t["size"] == t["size"].max()], 0.0
    for k, r in enumerate(big.itertuples()):
        s = steps[r.run_id].sort_values("step")
        top = max(top, s.update_ms.max())
        mark = " (GPUs shared)" if isinstance(r.note, str) else ""
        b.plot(s.step, s.update_ms, lw=0.8, color=f"C{k}", label=f"real, {r.devices} devices{mark}")
        b.plot(s.step, s.update_ideal_ms, lw=0.8, ls="--", color=f"C{k}", label=f"ideal, {r.devices} devices")
    b.set(xlabel="time step", ylabel="update time (ms)", ylim=(0, 1.15 * top))
    b.set_title(f"(b) per step: {big.group.iloc[0]}", loc="left")
    b.legend(frameon=False, fontsize=7)
    finish(fig, name, f"Figure {figure}: real wall time (slowest device's forces + integration) vs ideal "
           f"(mean over devices), {balancer} balancer", label, meta, args.out)
    return 0
