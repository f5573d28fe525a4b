"""Per-window summary of a steps CSV (sphbench simulate --out): rebuilds, the rebuild and
listed steps' wall times, the list phase, forces; and the whole run's seconds per simulated
second. Usage: step_windows.py LABEL=STEPS_CSV ... (prints CSV on stdout)."""
import sys

import pandas as pd

WINDOWS = [(0, 0.05), (0.05, 0.3), (0.3, 0.6), (0.6, 1.0)]
print("run,window_s,steps,rebuilds,steps_per_rebuild,rebuild_step_ms,list_phase_ms,listed_step_ms,forces_ms,s_per_sim_s")
for arg in sys.argv[1:]:
    label, path = arg.split("=", 1)
    d = pd.read_csv(path, comment="#")
    # The run's end time as its spec gave it (the last step passes it by less than a step):
    # windows that start there hold one step, not a window; the last row is the whole run.
    end = round(float(d.time.iloc[-1]), 2)
    for lo, hi in [(lo, hi) for lo, hi in WINDOWS if lo < end] + [(0, end)]:
        w = d[(d.time >= lo) & (d.time < hi)] if hi < end else d[d.time >= lo]
        if w.empty:
            continue
        r = w.neighbour_list_ms > 0
        span = w.time.iloc[-1] - (d.time[w.index[0] - 1] if w.index[0] > 0 else 0.0)
        print(f"{label},{lo:g}-{min(hi, end):g},{len(w)},{int(r.sum())},{len(w) / max(int(r.sum()), 1):.2f},"
              f"{w.wall_ms[r].mean():.3f},{w.neighbour_list_ms[r].mean():.3f},{w.wall_ms[~r].mean():.3f},"
              f"{w.forces_ms.mean():.3f},{w.wall_ms.sum() / 1e3 / span:.2f}")
