# Our host runs of experiments/spheric2-diffusion-walls.toml (dp 0.02, DensityDT 2: the solver of 484bc4b, and
# full-physics-to-2s/, the solver of 1318c4d with DualSPHysics' forms and tensile correction too) against
# DualSPHysics at dp 0.02 and our H100 run of the same spacing before the changes (024c77a, DensityDT 3):
# RMS of our water height less theirs by window (mm), and each series against the MARIN measurements
# (RMS over 0-2 s, % of 0.55 m). Run from the repository root: python3 results/reference/host/spheric2-diffusion-walls/compare_with_dualsphysics.py
import sys; sys.path.insert(0,'plots')
import spheric2 as S, numpy as np
from pathlib import Path
meas = S.read_measured(S.MEASURED)
ours = S.read_our_gauges(Path('results/reference/host/spheric2-diffusion-walls/dp0.02-fourtakas_gauges.csv'))
full = S.read_our_gauges(Path('results/reference/host/spheric2-diffusion-walls/full-physics-to-2s/dp0.02-fourtakas_gauges.csv'))
old = S.read_our_gauges(Path('results/reference/h100/spheric2/dp0.02-wendland-lists_gauges.csv'))
d = Path('results/reference/h100/spheric2-dualsphysics')
dsph = {p: S.read_dsph_gauge(d / f"dp0.02.GaugesSWL_{p}.csv") for p in S.PROBES}
H = {("ours","dp0.02-host-fourtakas-484bc4b"): ours, ("ours","dp0.02-host-full-1318c4d"): full, ("ours","dp0.02-h100-024c77a"): old, ("DualSPHysics","dp0.02"): dsph}
for g in S.series_gaps(H):
    print(f"{g['run']:<32}", "  ".join(f"{p} {a:g}-{b:g} {1e3*g[f'{p}_{a:g}-{b:g}']:5.1f}" for p in S.PROBES for a,b in S.GAP_WINDOWS))
for name, ser in (("host DDT2 484bc4b", ours), ("host full 1318c4d", full), ("H100 024c77a", old), ("DualSPHysics", dsph)):
    e = S.run_errors(ser, meas, 2.0, 2.0)
    rms = {p: 100 * e[p + "_rms"] for p in S.PROBES}
    print(f"{name:<20}", "  ".join(f"{p} {rms[p]:.2f}" for p in S.PROBES), f"mean {np.mean(list(rms.values())):.2f}")
