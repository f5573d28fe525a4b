# Our host runs of experiments/spheric2-diffusion-walls.toml at dp 0.02 against DualSPHysics (the H100's
# run at dp 0.02) and our H100 run of the same spacing before changes 23-25 (024c77a, DensityDT 3):
#   484bc4b          DensityDT 2, the old continuity and momentum forms, 0-2 s
#   1318c4d          the whole current physics (DensityDT 2, DualSPHysics' forms, the cubic's tensile
#                    correction), 0-2 s (full-physics-to-2s/)
#   45814dd to 1 s   changes 23-25 before the cubic shape's refactor, 0-1 s (head-to-1s/)
# Prints the RMS of our water height less DualSPHysics' (mm) over 0-1 and 1-2 s and over 0-0.5 and
# 0.5-1 s, and each 2 s series' RMS against the MARIN measurements (0-2 s, % of 0.55 m).
# Run from the repository root: python3 results/reference/host/spheric2-diffusion-walls/compare_with_dualsphysics.py
import sys; sys.path.insert(0, 'plots')
import spheric2 as S, numpy as np
from pathlib import Path
here = Path('results/reference/host/spheric2-diffusion-walls')
to_2s = {"dp0.02-host-fourtakas-484bc4b": here / 'dp0.02-fourtakas_gauges.csv',
         "dp0.02-host-full-1318c4d": here / 'full-physics-to-2s' / 'dp0.02-fourtakas_gauges.csv',
         "dp0.02-h100-024c77a": Path('results/reference/h100/spheric2/dp0.02-wendland-lists_gauges.csv')}
to_1s = {"dp0.02-host-45814dd-to-1s": here / 'head-to-1s' / 'dp0.02-fourtakas_gauges.csv'}
d = Path('results/reference/h100/spheric2-dualsphysics')
dsph = {p: S.read_dsph_gauge(d / f"dp0.02.GaugesSWL_{p}.csv") for p in S.PROBES}
ours = {k: S.read_our_gauges(v) for k, v in {**to_2s, **to_1s}.items()}


def gaps(names, windows, digits):
    H = {("ours", k): ours[k] for k in names}
    H[("DualSPHysics", "dp0.02")] = dsph
    for g in S.series_gaps(H, windows):
        print(f"{g['run']:<32}", "  ".join(f"{p} {a:g}-{b:g} {1e3 * g[f'{p}_{a:g}-{b:g}']:5.{digits}f}"
                                           for p in S.PROBES for a, b in windows))


gaps(to_2s, S.GAP_WINDOWS, 1)
gaps({**to_1s, **to_2s}, ((0.0, 0.5), (0.5, 1.0)), 2)
meas = S.read_measured(S.MEASURED)
for name, ser in [*((k, ours[k]) for k in to_2s), ("DualSPHysics", dsph)]:
    e = S.run_errors(ser, meas, 2.0, 2.0)
    rms = {p: 100 * e[p + "_rms"] for p in S.PROBES}
    print(f"{name:<32}", "  ".join(f"{p} {rms[p]:.2f}" for p in S.PROBES), f"mean {np.mean(list(rms.values())):.2f}")
