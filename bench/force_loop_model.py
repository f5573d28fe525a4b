#!/usr/bin/env python3
"""A model of the GPU force loop's divergence (docs/force-loop-notes.md, change 6).

Counts, per warp of 32 consecutive particles in (cell, id) order, how often the warp runs the
pair body when its lanes walk their stencil candidate by candidate (once per candidate that any
lane of the same cell has as a neighbour) and with hit masks (per chunk of 32 candidates of a
range, as often as the lane with most neighbours in it), on a jittered lattice of DualSPHysics'
dam-break resolution (h = sqrt(3) dp, cells of the support). Interior warps only.

    python3 bench/force_loop_model.py
"""
import numpy as np

DP = 1.0
H = np.sqrt(3) * DP
SUPPORT = 2 * H
CELL = SUPPORT
LATTICE = 40  # points per axis
WARP = 32


def main():
    g = np.arange(LATTICE) * DP + 0.5
    x, y, z = np.meshgrid(g, g, g, indexing="ij")
    pos = np.stack([x.ravel(), y.ravel(), z.ravel()], 1)  # id order: the lattice's
    pos += np.random.default_rng(1).normal(0, 0.05, pos.shape)
    nc = int(np.ceil(LATTICE * DP / CELL))
    cell = np.clip(np.floor(pos / CELL).astype(int), 0, nc - 1)
    linear = cell[:, 0] + nc * (cell[:, 1] + nc * cell[:, 2])  # x fastest, as GridView::encode
    order = np.lexsort((np.arange(len(pos)), linear))  # the (cell, id) sort
    pos, cell, linear = pos[order], cell[order], linear[order]
    start = np.searchsorted(linear, np.arange(nc**3 + 1))

    warps = candidates = by_candidate = by_mask = 0
    for w0 in range(0, len(pos) - WARP, WARP * 7):  # every 7th warp is enough
        lanes = np.arange(w0, w0 + WARP)
        if cell[lanes].min() < 1 or cell[lanes].max() > nc - 2:
            continue
        warps += 1
        groups = {}  # lanes in one cell walk the same ranges together
        for lane in lanes:
            groups.setdefault(tuple(cell[lane]), []).append(lane)
        for c, members in groups.items():
            members = np.array(members)
            for dz in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    for dx in (-1, 0, 1):
                        cc = (c[0] + dx) + nc * ((c[1] + dy) + nc * (c[2] + dz))
                        js = np.arange(start[cc], start[cc + 1])
                        if len(js) == 0:
                            continue
                        d2 = ((pos[members][:, None, :] - pos[js][None, :, :]) ** 2).sum(-1)
                        hit = (d2 < SUPPORT * SUPPORT) & (d2 > 1e-12)
                        candidates += len(js)
                        by_candidate += hit.any(0).sum()
                        for k in range(0, len(js), 32):
                            by_mask += hit[:, k:k + 32].sum(1).max()
    print(f"{warps} warps: {candidates / warps:.0f} candidate steps a warp; body runs a warp: "
          f"{by_candidate / warps:.0f} candidate by candidate, {by_mask / warps:.0f} with hit masks")


if __name__ == "__main__":
    main()
