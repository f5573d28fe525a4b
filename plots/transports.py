"""The transports compared (experiments/transports.toml, not a paper figure; Figure 10 is
fig10.py): the whole-step speedup per transport. Unlike Figures 5 to 9 (the update only),
this is the whole step: S = W_1 / W_n,
W the mean wall time of a step (forces, integration, sort, exchange, balancing, diagnostics)
and W_1 from the scene's 1-device runs (pooled over transports, which a single device never
uses). Panel (b) shows the exchange's share: its mean time per step on n devices.

Usage: python3 plots/transports.py [--results results/transports] [--out plots/out]
(the results made under the spec's old name: --results results/reference/h200-x2/fig10)
"""
import numpy as np

import fig6
import multigpu
import sphplot
from sphplot import pd, plt

NAME = "transports"
EXPERIMENT = "transports"
COLOURS = {"staged": "#d95f02", "peer": "#1b9e77", "nccl": "#7570b3", "host": "#666666"}


def per_run(runs, steps, gpus):
    rows = []
    labels = sphplot.scene_labels(runs)
    for i, run in runs.iterrows():
        s = steps[run["run_id"]]
        sphplot.require_columns(s, ["wall_ms", "update_ms", "exchange_ms"])
        n = int(run.get("devices", 1))
        rows.append({"group": labels[i], "devices": n, "transport": str(run.get("transport", "auto")),
                     "wall_ms": s["wall_ms"].mean(), "update_ms": s["update_ms"].mean(),
                     "exchange_ms": s["exchange_ms"].mean(), "note": multigpu.shared_note(n, gpus)})
    return pd.DataFrame(rows)


def with_speedups(t):
    one = t[t.devices == 1].groupby("group")[["wall_ms", "update_ms"]].mean()
    many = t[t.devices > 1].groupby(["group", "devices", "transport"], as_index=False, sort=False).agg(
        wall_ms=("wall_ms", "mean"), update_ms=("update_ms", "mean"), exchange_ms=("exchange_ms", "mean"),
        note=("note", "first"))
    many["W1"] = many.group.map(one.wall_ms)
    many["U1"] = many.group.map(one.update_ms)
    ok = many.note.isna() & many.W1.notna()
    many["speedup"] = np.where(ok, many.W1 / many.wall_ms, np.nan)
    many["update_speedup"] = np.where(ok, many.U1 / many.update_ms, np.nan)
    return many


def main(argv=None):
    args = sphplot.parse_args(NAME, __doc__.split("\n\n")[0], argv, experiment=EXPERIMENT)
    runs, meta, steps = sphplot.load_experiment(args.results, EXPERIMENT)
    sphplot.require_columns(runs, ["scene", "devices", "transport"])
    names = multigpu.gpu_names(meta, runs)
    t = with_speedups(per_run(runs, steps, len(names)))
    if t.empty:
        raise sphplot.ResultsError(f"{args.results} holds no run on more than one device.")
    shown = pd.DataFrame({"device": ["; ".join(names) or "host"]})
    label = sphplot.provenance_label(meta, shown) + f" | {len(names)} physical GPU(s)"
    print("Transports summary, whole-step speedup W_1/W_n (mean wall time per step) per transport; "
          "update speedup (forces + integration) for reference")
    print(f"  from {args.results}: {label}")
    if not names:
        print("  no GPU: every transport fell back to host copies (the runs' metadata says so); bars are labelled "
              "with the transport asked for")
    for r in t.itertuples():
        head = f"  {r.group}, {r.devices} devices, {r.transport}: "
        if isinstance(r.note, str):
            print(head + f"{r.note} (wall {r.wall_ms:.3f} ms, exchange {r.exchange_ms:.3f} ms per step)")
        elif not np.isfinite(r.speedup):
            print(head + f"no 1-device run, so no speedup (wall {r.wall_ms:.3f} ms per step)")
        else:
            print(head + f"step speedup {r.speedup:.3f} (W_1 {r.W1:.3f} ms, W_{r.devices} {r.wall_ms:.3f} ms), "
                  f"update speedup {r.update_speedup:.3f}, exchange {r.exchange_ms:.3f} ms per step")
    sphplot.apply_style()
    fig, (a, b) = plt.subplots(1, 2, figsize=(12.0, 4.4), gridspec_kw={"width_ratios": [1.3, 1]})
    groups, transports = list(dict.fromkeys(t.group)), list(dict.fromkeys(t.transport))
    width = 0.8 / max(len(transports), 1)
    for j, tr in enumerate(transports):
        rows = t[t.transport == tr].set_index("group").reindex(groups)
        x = np.arange(len(groups)) - 0.4 + width * (j + 0.5)
        colour = COLOURS.get(tr, f"C{j}")
        vals = rows.speedup.to_numpy(dtype=float)
        bars = a.bar(x, np.nan_to_num(vals), width, color=colour, label=f"{tr}: whole step")
        a.bar_label(bars, labels=[f"{v:.2f}" if np.isfinite(v) else "" for v in vals], fontsize=7, padding=1)
        a.plot(x, rows.update_speedup, "k_", ms=10, label="update only" if j == 0 else None)
        multigpu.mark_shared(a, x, rows)
        b.bar(x, rows.exchange_ms.to_numpy(dtype=float), width, color=colour, label=tr)
    counts = sorted(t.devices.unique())
    fig6.linear_lines(a, counts, ["#444444"], "linear: {n}")
    a.set_xticks(np.arange(len(groups)), groups)
    a.set_ylim(0, 1.2 * max(counts + [float(np.nanmax(t.speedup.to_numpy(dtype=float), initial=0))]))
    a.set_ylabel("speedup W$_1$ / W$_n$ (wall time per step)")
    a.set_title("(a) whole-step speedup per transport", loc="left")
    a.legend(frameon=False, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    b.set_xticks(np.arange(len(groups)), groups)
    b.set_ylabel("exchange time per step, mean (ms)")
    b.set_title("(b) the exchange (transfer, sort, ghost marking)", loc="left")
    b.legend(frameon=False, fontsize=7)
    multigpu.finish(fig, NAME, "The transports compared: whole-step speedup per transport",
                    label, meta, args.out)
    return 0


if __name__ == "__main__":
    sphplot.main_guard(NAME, main)
