"""Figure 10 of the paper (section 6): the final speedup on 1 to 4 GPUs with the communication
optimisation of section 5.3 (boundary slices updated first and sent whole under the inner
update, the repartition decided under the forces) and without it, threshold balancer, the
paper's scenes. The whole step: S_n = W_1 / W_n, W the mean host wall time of a step (wall_ms:
everything a step does, overlapped where it overlaps) and W_1 from the scene's 1-device runs
(pooled over the switch, which one device never uses). Panel (b): what the optimisation gained
at each GPU count, S_n(on) / S_n(off) - 1 (the paper reports about 10%). A run with more
subdomains than the machine has GPUs shares GPUs: its times are printed, never a speedup.

Usage: python3 plots/fig10.py [--results results/fig10] [--out plots/out]
"""
import numpy as np

import multigpu
import sphplot
from sphplot import pd, plt

NAME = "fig10"
EXPERIMENT = "fig10"
STYLE = {True: ("-", "o", "with the optimisation"), False: ("--", "s", "without")}


def as_bool(value):
    return str(value).strip().lower() in ("true", "1", "yes", "on")


def per_run(runs, steps, gpus):
    rows = []
    labels = sphplot.scene_labels(runs)
    for i, run in runs.iterrows():
        s = steps[run["run_id"]]
        sphplot.require_columns(s, ["wall_ms", "update_ms"])
        n = int(run.get("devices", 1))
        rows.append({"group": labels[i], "devices": n, "overlap": as_bool(run["overlap"]),
                     "wall_ms": s["wall_ms"].mean(), "update_ms": s["update_ms"].mean(),
                     "exchange_ms": sphplot.column(s, "exchange_ms", np.nan).mean(),
                     "transfer_ms": pd.to_numeric(sphplot.column(s, "transfer_ms", np.nan), errors="coerce").mean(),
                     "integrate_ms": pd.to_numeric(sphplot.column(s, "integrate_ms", np.nan), errors="coerce").mean(),
                     "note": multigpu.shared_note(n, gpus)})
    return pd.DataFrame(rows)


def with_speedups(t):
    """Repetitions pooled; W1 per scene from its 1-device runs (either switch); S and the gain."""
    w1 = t[t.devices == 1].groupby("group")["wall_ms"].mean()
    t = t.assign(overlap=t.overlap | (t.devices == 1))  # one subdomain never overlaps: one reference row
    many = t.groupby(["group", "devices", "overlap"], as_index=False, sort=False).agg(
        wall_ms=("wall_ms", "mean"), update_ms=("update_ms", "mean"), exchange_ms=("exchange_ms", "mean"),
        transfer_ms=("transfer_ms", "mean"), integrate_ms=("integrate_ms", "mean"), note=("note", "first"))
    many["W1"] = many.group.map(w1)
    ok = many.note.isna() & many.W1.notna() & (many.wall_ms > 0)
    many["speedup"] = np.where(ok, many.W1 / many.wall_ms, np.nan)
    on = many[many.overlap].set_index(["group", "devices"]).speedup
    off = many[~many.overlap].set_index(["group", "devices"]).speedup
    gain = (on / off - 1.0) * 100.0
    many["gain_pct"] = [gain.get((g, n), np.nan) if o and n > 1 else np.nan
                        for g, n, o in zip(many.group, many.devices, many.overlap)]
    return many


def describe(r, unit="GPU"):
    """unit: what a device is ("GPU"; "subdomain" on the host)."""
    if r.devices == 1:
        return f"  {r.group}, 1 {unit}: W_1 {r.wall_ms:.3f} ms per step (the reference; one subdomain exchanges nothing)"
    head = f"  {r.group}, {r.devices} {unit}s, {'with' if r.overlap else 'without'}: "
    if isinstance(r.note, str):
        return head + f"{r.note} (wall {r.wall_ms:.3f} ms per step)"
    if not np.isfinite(r.speedup):
        return head + f"no 1-device run, so no speedup (wall {r.wall_ms:.3f} ms per step)"
    text = head + f"speedup {r.speedup:.3f} (W_1 {r.W1:.3f} ms, W_{r.devices} {r.wall_ms:.3f} ms)"
    if r.overlap and np.isfinite(r.gain_pct):
        text += f", gain over without {r.gain_pct:+.1f}%"
    if r.overlap and np.isfinite(r.transfer_ms):  # the exchange's copies, run under the inner update
        text += f"; transfers {r.transfer_ms:.3f} ms per step under integrate {r.integrate_ms:.3f} ms"
    return text


def main(argv=None):
    args = sphplot.parse_args(NAME, __doc__.split("\n\n")[0], argv, experiment=EXPERIMENT)
    runs, meta, steps = sphplot.load_experiment(args.results, EXPERIMENT)
    sphplot.require_columns(runs, ["scene", "devices", "overlap"])
    names = multigpu.gpu_names(meta, runs)
    t = with_speedups(per_run(runs, steps, len(names)))
    if t[t.devices > 1].empty:
        raise sphplot.ResultsError(f"{args.results} holds no run on more than one device.")
    shown = pd.DataFrame({"device": ["; ".join(names) or "host"]})
    label = sphplot.provenance_label(meta, shown) + f" | {len(names)} physical GPU(s)"
    print("Figure 10 summary, whole-step speedup S_n = W_1/W_n (mean wall time per step), with and without the "
          "communication optimisation (paper 5.3)")
    print(f"  from {args.results}: {label}")
    if not names:
        print("  no GPU: the subdomains share the host's cores, so no speedup is shown; the times per step are")
    for r in t.sort_values(["group", "devices", "overlap"], ascending=[True, True, False]).itertuples():
        print(describe(r, "GPU" if names else "subdomain"))
    sphplot.apply_style()
    fig, (a, b) = plt.subplots(1, 2, figsize=(12.0, 4.4), gridspec_kw={"width_ratios": [1.3, 1]})
    groups = list(dict.fromkeys(t.group))
    counts = sorted(t.devices.unique())
    for k, g in enumerate(groups):
        colour = f"C{k}"
        for overlap, (ls, marker, what) in STYLE.items():
            rows = t[(t.group == g) & (t.overlap == overlap) & (t.devices > 1)].sort_values("devices")
            x = [1] + list(rows.devices)
            y = [1.0] + list(rows.speedup)
            a.plot(x, y, ls=ls, marker=marker, color=colour, ms=4, label=f"{g}, {what}")
    a.plot(counts, counts, ":", color="#444444", lw=0.9, label="linear")
    a.set_xticks(counts)
    a.set_xlabel("GPUs")
    a.set_ylabel("speedup W$_1$ / W$_n$ (wall time per step)")
    a.set_ylim(0, 1.15 * max(counts + [float(np.nanmax(t.speedup.to_numpy(dtype=float), initial=0))]))
    a.set_title("(a) final speedup", loc="left")
    a.legend(frameon=False, fontsize=6.5, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    many = [n for n in counts if n > 1]
    width = 0.8 / max(len(groups), 1)
    for k, g in enumerate(groups):
        rows = t[(t.group == g) & t.overlap].set_index("devices").reindex(many)
        x = np.arange(len(many)) - 0.4 + width * (k + 0.5)
        vals = rows.gain_pct.to_numpy(dtype=float)
        bars = b.bar(x, np.nan_to_num(vals), width, color=f"C{k}", label=g)
        b.bar_label(bars, labels=[f"{v:+.1f}" if np.isfinite(v) else "" for v in vals], fontsize=7, padding=1)
        multigpu.mark_shared(b, x, rows.reset_index())
    b.axhline(0, color="#444444", lw=0.8)
    b.set_xticks(np.arange(len(many)), [f"{n} GPUs" for n in many])
    b.set_ylabel("speedup gained by the optimisation (%)")
    b.set_title("(b) with against without", loc="left")
    b.legend(frameon=False, fontsize=7)
    multigpu.finish(fig, NAME, "Figure 10: final speedup with and without the communication optimisation",
                    label, meta, args.out)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
