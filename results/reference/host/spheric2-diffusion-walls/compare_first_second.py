# Our host run of the current solver (45814dd: DensityDT 2 and DualSPHysics' forms), SPHERIC Test 2
# at dp 0.02 from rest to 1 s, against DualSPHysics (H100, dp 0.02), beside the 0-2 s run of 484bc4b
# (DensityDT 2, old forms) and the H100's run before both (024c77a): RMS of our water height less
# DualSPHysics' (mm) over 0-0.5 and 0.5-1 s. Run from the repository root.
import sys; sys.path.insert(0, 'plots')
import spheric2 as S
from pathlib import Path
here = Path('results/reference/host/spheric2-diffusion-walls')
runs = {"dp0.02-45814dd-to-1s": here / 'head-to-1s' / 'dp0.02-fourtakas_gauges.csv',
        "dp0.02-484bc4b": here / 'dp0.02-fourtakas_gauges.csv',
        "dp0.02-h100-024c77a": Path('results/reference/h100/spheric2/dp0.02-wendland-lists_gauges.csv')}
d = Path('results/reference/h100/spheric2-dualsphysics')
H = {("ours", k): S.read_our_gauges(v) for k, v in runs.items()}
H[("DualSPHysics", "dp0.02")] = {p: S.read_dsph_gauge(d / f"dp0.02.GaugesSWL_{p}.csv") for p in S.PROBES}
W = ((0.0, 0.5), (0.5, 1.0))
for g in S.series_gaps(H, W):
    print(f"{g['run']:<22}", "  ".join(f"{p} {a:g}-{b:g} {1e3 * g[f'{p}_{a:g}-{b:g}']:5.2f}" for p in S.PROBES for a, b in W))
