"""What Verlet lists of other layouts would hold, counted on snapshots (issue 25's memory target,
200 bytes a particle). No GPU: it reads the HDF5 snapshots `sphbench simulate --snapshot-every`
writes and bins the particles as the solver does (cells of reach / n, the linear index with z
fastest, so the n_stencil z-cells of one (dx, dy) column are one contiguous run of the sorted
particles).

For each particle i (a wall particle lists fluid only, as the solver's build does):
  entries   the candidates j != i within the reach (support x (1 + skin)): today's lists hold
            these, 4 bytes each, in rows of the longest list + a fifth + 8;
  run masks one bit per candidate of each stencil column (run), a 64-bit word per 64 candidates
            of the run: the list as masks over the sorted candidates, decoded j = run start + bit.
Usage: python3 bench/list_layout_memory.py SNAPSHOT.h5 [...] [--dp 0.02] [--coef-h 1] [--skin 0.1] [--n 2]
"""
import argparse
import sys

import h5py
import numpy as np

from snapshot_geometry import add_geometry_args


def count(path, dp, coef_h, skin, n, kernel_support_h=2.0):
    with h5py.File(path, "r") as f:
        pos = np.asarray(f["position"], float)
        fluid = np.asarray(f["type"]) == 0
        time = float(f.attrs.get("time", np.nan))
    h = coef_h * np.sqrt(3.0) * dp
    reach = kernel_support_h * h * (1 + skin)
    cell = reach / n
    lo = pos.min(axis=0)
    c = np.floor((pos - lo) / cell).astype(np.int64)
    dims = c.max(axis=0) + 1
    key = (c[:, 0] * dims[1] + c[:, 1]) * dims[2] + c[:, 2]
    order = np.argsort(key, kind="stable")
    pos, fluid, c, key = pos[order], fluid[order], c[order], key[order]
    ncell = int(dims.prod())
    start = np.searchsorted(key, np.arange(ncell + 1))
    # The same for the fluid alone (the candidates of a wall particle).
    fkey = key[fluid]
    fstart = np.searchsorted(fkey, np.arange(ncell + 1))
    fpos = pos[fluid]
    entries = np.zeros(len(pos), np.int64)
    words = np.zeros(len(pos), np.int64)
    longest_run = 0
    for i in range(len(pos)):
        cx, cy, cz = c[i]
        src_start, src_pos = (start, pos) if fluid[i] else (fstart, fpos)
        z0, z1 = max(cz - n, 0), min(cz + n, dims[2] - 1)
        for dx in range(-n, n + 1):
            x = cx + dx
            if x < 0 or x >= dims[0]:
                continue
            for dy in range(-n, n + 1):
                y = cy + dy
                if y < 0 or y >= dims[1]:
                    continue
                base = (x * dims[1] + y) * dims[2]
                a, b = src_start[base + z0], src_start[base + z1 + 1]
                if b <= a:
                    continue
                longest_run = max(longest_run, b - a)
                words[i] += (b - a + 63) // 64
                d2 = ((src_pos[a:b] - pos[i]) ** 2).sum(axis=1)
                entries[i] += int(np.count_nonzero(d2 < reach * reach)) - (1 if fluid[i] and a <= i < b else 0)
    row = int(entries.max() * 1.2) + 8
    return {"file": path, "time": time, "particles": len(pos), "entries_mean": entries.mean(),
            "entries_max": int(entries.max()), "rows_bytes": 4 * row, "exact_bytes": 4 * entries.mean(),
            "mask_bytes_mean": 8 * words.mean(), "mask_bytes_max": 8 * int(words.max()),
            "longest_run": int(longest_run), "runs": (2 * n + 1) ** 2}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("snapshots", nargs="+")
    add_geometry_args(p)
    a = p.parse_args(argv)
    print("time_s,particles,entries_mean,entries_max,list_rows_bytes,exact_rows_bytes,run_masks_bytes_mean,"
          "run_masks_bytes_max,longest_run")
    for path in a.snapshots:
        r = count(path, a.dp, a.coef_h, a.skin, a.n)
        print(f"{r['time']:.3f},{r['particles']},{r['entries_mean']:.1f},{r['entries_max']},{r['rows_bytes']},"
              f"{r['exact_bytes']:.0f},{r['mask_bytes_mean']:.0f},{r['mask_bytes_max']},{r['longest_run']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
