"""How many distinct cache lines does one warp-wide gather of j's data touch in the listed force
loop, and how many would it touch if the lists' rows were aligned across a warp by stencil column?
Counted on snapshots, no GPU (issue 25: the listed loop is bound by the L1's data pipe, whose
wavefronts go as the distinct lines a gather touches; docs/force-loop-notes.md, change 10).

It reads the HDF5 snapshots `sphbench simulate --snapshot-every` writes and builds the solver's
per-particle lists as bench/cluster_pair_counts.py does (the solver's grid of cells reach / n, z
fastest, particles sorted by (cell, id), a wall lists fluid only, every list in ascending j: the
stencil's columns in order, each column's z-run ascending). Each snapshot is a list rebuild's
state. j's data are 16-byte elements (a float4 position), 8 to a 128-byte line.

Designs (a warp = 32 consecutive sorted particles, one lane each):

  today           row k of a warp: every lane's k-th entry (lanes whose list is shorter idle).
                  Rows a warp: its longest list.
  column-aligned  a warp walks the stencil's (x, y) columns in turn; within column c, row r holds
                  every lane's r-th entry of that column. Rows a warp: the sum over columns of the
                  longest column part. Lanes in the same z-cell then read nearby j in a row.
  cell-aligned    the same with the stencil's cells (x, y, z) instead of its columns.
  slab-aligned    the same with the stencil's x slabs of columns (2n + 1 parts, not (2n + 1)^2):
                  fewer padded rows, lanes less close.

Per design and snapshot (over all warps, and over warps of 32 fluid particles, the bulk of large
runs): rows, body rows (rows where some lane's entry lies inside the support, so that the pair
body issues), entries, lane occupancy (entries / 32 rows), distinct lines a row, and what bounds
the loop, relative to today's: rows and body rows (issue: a row issues the entry's load, gather and
test, a body row the pair body too) and rows x lines a row (the position gather's wavefronts).
"""
import argparse
import sys

import numpy as np

from cluster_pair_counts import WARP, Setup, inside, reach_pairs, solver_order
from snapshot_geometry import add_geometry_args

LINE_ELEMENTS = 8  # 16-byte elements a 128-byte line
DESIGNS = ("today", "slab-aligned", "column-aligned", "cell-aligned")
HEADER = ("time,particles,fluid,design,scope,warps,rows,body_rows,entries,inside_entries,lane_occupancy,lines_per_row,"
          "rows_vs_today,body_rows_vs_today,wavefronts_vs_today")


def directed_entries(pos, fluid, ids, s, origin, stencil):
    """The lists as the solver builds them: entries (i, j) in sorted indices, sorted by (i, j),
    whether each lies inside the support, the sorted particles' cells and fluid flags."""
    order, c, key, dims = solver_order(pos, ids, s, origin)
    pos, fluid = pos[order], fluid[order]
    a, b, d2 = reach_pairs(pos, c, key, dims, s, stencil)
    keep = fluid[a] | fluid[b]
    a, b, d2 = a[keep], b[keep], d2[keep]
    I = np.concatenate([a, b])
    J = np.concatenate([b, a])
    hit = inside(np.concatenate([d2, d2]), s)
    srt = np.lexsort((J, I))
    return I[srt], J[srt], hit[srt], c, fluid


def rank_within(group):
    """Each entry's position within its run of equal `group` values (entries sorted by group)."""
    first = np.r_[0, np.flatnonzero(np.diff(group)) + 1]
    size = np.diff(np.r_[first, len(group)])
    return np.arange(len(group)) - np.repeat(first, size)


def design_rows(I, J, c, stencil, design):
    """Each entry's row key (unique per warp row) for a design, and the warp's rows in all."""
    warp = I // WARP
    span = 2 * stencil + 1
    d = c[J] - c[I] + stencil  # the stencil offset, 0 .. span - 1 an axis
    part = {"today": np.zeros(len(I), np.int64), "slab-aligned": d[:, 0], "column-aligned": d[:, 0] * span + d[:, 1],
            "cell-aligned": (d[:, 0] * span + d[:, 1]) * span + d[:, 2]}[design]
    # Entries sorted by (i, part, j): the lists' order (ascending j) already groups a column's and
    # a cell's entries, so the sort only checks it.
    srt = np.lexsort((J, part, I))
    assert (srt == np.arange(len(I))).all(), "a list's entries do not come grouped by stencil column"
    r = rank_within(I * (part.max() + 1) + part)
    nparts = int(part.max()) + 1
    rmax = int(r.max()) + 1
    row = (warp * nparts + part) * rmax + r
    return row


def count(I, J, hit, c, fluid, stencil, design, scope_warps):
    row = design_rows(I, J, c, stencil, design)
    sel = scope_warps[I // WARP]
    row, Js, hs = row[sel], J[sel], hit[sel]
    rows = len(np.unique(row))
    body_rows = len(np.unique(row[hs]))  # rows where a lane's pair is inside: the body issues there
    line = Js // LINE_ELEMENTS
    lines = len(np.unique(row * (int(line.max()) + 1) + line)) if len(row) else 0
    return dict(warps=int(scope_warps.sum()), rows=rows, body_rows=body_rows, entries=len(row), inside_entries=int(hs.sum()),
                lane_occupancy=len(row) / (WARP * rows) if rows else np.nan,
                lines_per_row=lines / rows if rows else np.nan, wavefronts=lines)


def count_snapshot(path, s, origin, stencil):
    import h5py
    with h5py.File(path, "r") as f:
        pos = np.asarray(f["position"], float)
        fluid = np.asarray(f["type"]) == 0
        ids = np.asarray(f["id"], np.int64)
        time = float(f.attrs.get("time", np.nan))
    keep = np.isfinite(pos).all(axis=1)
    pos, fluid, ids = pos[keep], fluid[keep], ids[keep]
    o = pos.min(axis=0) if origin is None else np.asarray(origin, float)
    I, J, hit, c, fluid_sorted = directed_entries(pos, fluid, ids, s, o, stencil)
    N = len(pos)
    nwarp = (N + WARP - 1) // WARP
    padded = np.zeros(nwarp * WARP, bool)
    padded[:N] = fluid_sorted
    scopes = {"all": np.ones(nwarp, bool), "fluid-warps": padded.reshape(nwarp, WARP).all(axis=1)}
    out = []
    for scope, warps in scopes.items():
        base = None
        for design in DESIGNS:
            r = count(I, J, hit, c, fluid_sorted, stencil, design, warps)
            base = base or r
            out.append(f"{time:.4g},{N},{int(fluid.sum())},{design},{scope},{r['warps']},{r['rows']},{r['body_rows']},"
                       f"{r['entries']},{r['inside_entries']},{r['lane_occupancy']:.3f},{r['lines_per_row']:.2f},"
                       f"{r['rows'] / base['rows']:.3f},{r['body_rows'] / base['body_rows']:.3f},"
                       f"{r['wavefronts'] / base['wavefronts']:.3f}")
    return out


def self_test():
    """A lattice of 4 x 4 x 40 particles, one column: every design holds the same entries, and the
    aligned rows never touch more lines than today's (the same j's, nearer together)."""
    s = Setup(0.02, 1.0, 0.1, 2)
    g = np.stack(np.meshgrid(np.arange(4), np.arange(4), np.arange(40), indexing="ij"), -1).reshape(-1, 3) * s.dp
    fluid = np.ones(len(g), bool)
    ids = np.arange(len(g))
    I, J, hit, c, fl = directed_entries(g.astype(float), fluid, ids, s, g.min(axis=0), 2)
    warps = np.ones((len(g) + WARP - 1) // WARP, bool)
    r = {d: count(I, J, hit, c, fl, 2, d, warps) for d in DESIGNS}
    ok = len({v["entries"] for v in r.values()}) == 1
    ok &= r["column-aligned"]["lines_per_row"] <= r["today"]["lines_per_row"]
    ok &= r["cell-aligned"]["rows"] >= r["column-aligned"]["rows"] >= r["slab-aligned"]["rows"] >= r["today"]["rows"]
    print("self-test:", "passes" if ok else "FAILS", {d: (v["rows"], round(v["lines_per_row"], 2)) for d, v in r.items()})
    return 0 if ok else 1


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("snapshots", nargs="*")
    add_geometry_args(p)
    p.add_argument("--origin", default=None, help="grid origin x,y,z (dsph-dambreak: -2 dp each); default: the particles' min")
    p.add_argument("--self-test", action="store_true")
    a = p.parse_args(argv)
    if a.self_test:
        return self_test()
    if not a.snapshots:
        p.error("give snapshots or --self-test")
    s = Setup(a.dp, a.coef_h, a.skin, a.n)
    origin = None if a.origin is None else [float(x) for x in a.origin.split(",")]
    print(HEADER)
    for path in a.snapshots:
        for line in count_snapshot(path, s, origin, a.n):
            print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
