"""Would a symmetric cluster-pair force loop (GROMACS' NBNXM in miniature) cut the work of today's
per-particle Verlet lists? Counted on snapshots, no GPU: it reads the HDF5 snapshots
`sphbench simulate --snapshot-every` writes and bins the particles as bench/list_layout_memory.py
does (the solver's grid: cells of reach / n, linear index z fastest, particles sorted by (cell, id);
fluid is type 0, a wall lists fluid only; h = coef_h sqrt(3) dp, support 2h, reach support x
(1 + skin)). Each snapshot's positions are taken as the state of a list rebuild.

One CSV row per design and snapshot, all figures per particle (every particle, walls included):

  full-lists      today: i lists every j within the reach (both directions), one thread a
                  particle, a warp = 32 consecutive sorted particles walking their lists in the
                  solver's order (stencil cells ascending, sorted order within a cell: ascending j).
                  A warp runs max(list length) iterations; the body runs at iteration k where any
                  lane's k-th entry is inside the support.
  cluster8-column clusters of <= 8 consecutive sorted particles cut along each (x, y) column's
                  segments (runs of non-empty cells), as solver/neighbours/particle_clusters.hpp
                  (branch experiment/cluster-lists) does.
  cluster8-cube   compact clusters in the manner of GROMACS' grid: columns 2 dp x 2 dp in (x, y)
                  (edges half a dp off the lattice, so a particle at rest on it falls squarely
                  inside), each column's particles sorted by z, cut in 8s, a new cluster also where
                  z jumps by more than 2 dp (no box across empty space). At rest every cluster is a
                  2 x 2 x 2 block of the lattice.

For the cluster designs: cluster pairs I <= J whose axis-aligned boxes are closer than the reach
(strict, as the solver's box_distance2 < reach2; two wall-only clusters are not listed); each
unordered particle pair is evaluated once (I < J: |I| x |J| candidates, I = J: the i < j ones);
warp model: one warp a tile of the 8 i's of I x 4 j's of J (J's slots 0-3 and 4-7: ceil(|J| / 4)
tiles a pair), 32 lane-slots of body where any of the tile's pairs is inside the support (and not
wall-wall), the distance test only where none is. List bytes: 4 an entry (I, J), no mask
modelled; j loads: the j's a tile reads (once for its 8 i's).

Columns:
  clusters, cluster_fill       cluster count and particles per cluster (full-lists: none)
  cluster_pairs_pp             listed cluster pairs (I <= J) per particle
  candidates_pp                pair evaluations issued to the distance test: list entries (full
                               lists), or the |I| x |J| (I < J) and i < j (I = J) pairs (clusters)
  inside_unordered_pp          unordered pairs inside the support, each once (equal for all designs)
  body_needed_pp               body evaluations the design needs: inside pairs from both sides for
                               full lists, once per unordered pair for the symmetric designs
  steps_pp                     warp steps (full lists: warp iterations; clusters: tiles) x 32 / N
  body_lane_slots_pp           32 x (steps running the body) / N
  test_only_lane_slots_pp      32 x (steps with no body: distance test only) / N
  useful_fraction              body_needed / body_lane_slots
  lane_occupancy               lanes holding a candidate over all lane-slots (loop-length and
                               partial-cluster waste; the full lists' counterpart of ncu's lanes active
                               before the support test)
  body_slots_vs_full           body_lane_slots_pp over the full lists' of the same snapshot
  list_bytes_pp                4 bytes a list entry (full lists: exact rows, no padding)
  j_loads_pp                   j positions read: one per entry (full lists), 4 a tile (clusters)
  useful_fraction_fluid        useful_fraction over fluid only: warps of 32 fluid particles (full
                               lists), tiles whose i's and j's are all fluid (clusters): the bulk of
                               the water, which dominates large runs (walls are 45% of the particles
                               at dp 0.02, ~15% on the 1.04M dam break)

j's side of a symmetric loop (cluster designs only; 0 for the full lists, which sum i alone). A
warp owns cluster I and walks its list: i's sums stay in registers in a fixed order and are stored
plainly into a buffer of its own at the end; what the pairs give j must reach j from other warps.
Order-independent (so that results do not depend on thread timing) means integer fixed-point
additions, 64-bit, one per quantity: 4 for a fluid j (acceleration and d rho / dt), 1 for a wall j
(density only).
  j_atomics_tile_pp            global atomics if each tile adds its j's sums once (after reducing
                               them over its 8 i lanes by shuffles): sum over tiles with a body of
                               the width of each j with at least one pair inside the support
  j_atomics_block4_pp          the same if a block of 4 warps (4 consecutive clusters I) first
                               gathers j's sums in shared memory (integer shared atomics) and adds
                               each distinct j once: sum over blocks of the width of each distinct j
  j_atomics_block8_pp          the same for blocks of 8 consecutive clusters
  block8_union_max             the most distinct clusters J the 8 consecutive clusters of a block
                               list (what its shared-memory slots must hold: 8 particles x 4
                               quantities x 8 bytes a cluster)

Asserted on every snapshot: all designs find the same set of inside-support unordered pairs (by
particle id), the cluster designs each exactly once, and the full lists each twice. --self-test
checks every design against an O(N^2) brute force on 2,000 random particles (--break shrinks the
box test or the stencil on purpose, to see the check fail).

Usage: python3 bench/cluster_pair_counts.py SNAPSHOT.h5 [...] --dp DP [--coef-h 1] [--skin 0.1] [--n 2]
                                             [--origin X,Y,Z]
       python3 bench/cluster_pair_counts.py --self-test [--break box|stencil|atomics]
"""
import argparse
import sys

import numpy as np

from snapshot_geometry import add_geometry_args

CLUSTER = 8
TILE_J = 4
WARP = 32


class Setup:
    def __init__(self, dp, coef_h, skin, n, kernel_support_h=2.0):
        self.dp = dp
        self.h = coef_h * np.sqrt(3.0) * dp
        self.support = kernel_support_h * self.h
        self.reach = self.support * (1 + skin)
        self.n = n
        self.cell = self.reach / n
        self.support2 = self.support ** 2
        self.near2 = 1e-18 * self.support2  # the solver's "itself" threshold
        self.reach2 = self.reach ** 2


def pair_key(a, b, n):
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    return lo.astype(np.int64) * n + hi.astype(np.int64)


# ---------------------------------------------------------------------------------------------
# The solver's grid and sorted order

def solver_order(pos, ids, s, origin):
    c = np.floor((pos - origin) / s.cell).astype(np.int64)
    if (c < 0).any():
        raise SystemExit("a particle lies below the grid origin; give --origin lower")
    dims = c.max(axis=0) + 1
    key = (c[:, 0] * dims[1] + c[:, 1]) * dims[2] + c[:, 2]
    order = np.lexsort((ids, key))  # (cell, id), as sort_by_cell
    return order, c[order], key[order], dims


def reach_pairs(pos, c, key, dims, s, stencil):
    """Unordered pairs (a < b, sorted indices) closer than the reach, found through the cell
    stencil of `stencil` cells each side (the half stencil: offsets after (0, 0, 0) in index
    order, plus the same cell). Returns a, b, d2."""
    ncell = int(dims.prod())
    start = np.searchsorted(key, np.arange(ncell + 1))
    occupied = np.unique(key)
    cnt_all = start[1:] - start[:-1]
    cx = occupied // (dims[1] * dims[2])
    cy = (occupied // dims[2]) % dims[1]
    cz = occupied % dims[2]
    out_a, out_b, out_d = [], [], []
    r = range(-stencil, stencil + 1)
    for dx in r:
        for dy in r:
            for dz in r:
                if (dx, dy, dz) < (0, 0, 0):
                    continue
                x, y, z = cx + dx, cy + dy, cz + dz
                ok = (x >= 0) & (x < dims[0]) & (y >= 0) & (y < dims[1]) & (z >= 0) & (z < dims[2])
                A = occupied[ok]
                B = ((x * dims[1] + y) * dims[2] + z)[ok]
                nb = cnt_all[B]
                keep = nb > 0
                A, B, nb = A[keep], B[keep], nb[keep]
                na = cnt_all[A]
                # every particle of cell A against every particle of cell B
                ai = np.repeat(np.arange(len(A)), na)
                a = start[A][ai] + (np.arange(len(ai)) - np.repeat(np.cumsum(na) - na, na))
                m = nb[ai]
                aa = np.repeat(a, m)
                bi = np.repeat(ai, m)
                b = start[B][bi] + (np.arange(len(aa)) - np.repeat(np.cumsum(m) - m, m))
                if (dx, dy, dz) == (0, 0, 0):
                    sel = aa < b
                    aa, b = aa[sel], b[sel]
                d2 = ((pos[aa] - pos[b]) ** 2).sum(axis=1)
                sel = d2 < s.reach2
                out_a.append(aa[sel])
                out_b.append(b[sel])
                out_d.append(d2[sel])
    return np.concatenate(out_a), np.concatenate(out_b), np.concatenate(out_d)


def inside(d2, s):
    return (d2 < s.support2) & (d2 > s.near2)


# ---------------------------------------------------------------------------------------------
# Design 1: full lists

def full_lists(pos, fluid, ids, s, origin, stencil):
    order, c, key, dims = solver_order(pos, ids, s, origin)
    pos, fluid, ids = pos[order], fluid[order], ids[order]
    N = len(pos)
    a, b, d2 = reach_pairs(pos, c, key, dims, s, stencil)
    keep = fluid[a] | fluid[b]  # a wall lists fluid only: wall-wall pairs are in no list
    a, b, d2 = a[keep], b[keep], d2[keep]
    # Directed entries i -> j, both directions; a list is visited in ascending j.
    I = np.concatenate([a, b])
    J = np.concatenate([b, a])
    hit = inside(np.concatenate([d2, d2]), s)
    srt = np.lexsort((J, I))
    I, J, hit = I[srt], J[srt], hit[srt]
    length = np.bincount(I, minlength=N)
    first = np.cumsum(length) - length
    k = np.arange(len(I)) - first[I]  # position of the entry in i's list
    nwarp = (N + WARP - 1) // WARP
    padded = np.zeros(nwarp * WARP, np.int64)
    padded[:N] = length
    iterations = int(padded.reshape(nwarp, WARP).max(axis=1).sum())
    kmax = int(length.max()) + 1
    body_keys = np.unique((I[hit] // WARP) * kmax + k[hit])
    body_iterations = len(body_keys)
    # the same over the warps of 32 fluid particles (the bulk of the water)
    fluid_warp = np.zeros(nwarp * WARP, bool)
    fluid_warp[:N] = fluid
    fluid_warp = fluid_warp.reshape(nwarp, WARP).all(axis=1)
    inside_fluid_warps = int(fluid_warp[I[hit] // WARP].sum())
    body_fluid_warps = int(fluid_warp[body_keys // kmax].sum())
    n_inside_directed = int(hit.sum())
    inside_set = np.unique(pair_key(ids[I[hit]], ids[J[hit]], int(ids.max()) + 1))
    # Every unordered pair exactly twice among the directed entries.
    assert n_inside_directed == 2 * len(inside_set), "full lists: an inside pair not listed from both sides"
    r = dict(design="full-lists", clusters=0, cluster_fill=np.nan, cluster_pairs=0, candidates=len(I),
             inside_unordered=len(inside_set), body_needed=n_inside_directed, steps=iterations,
             body_steps=body_iterations, lane_candidates=len(I), list_entries=len(I), j_loads=len(I),
             inside_fluid=inside_fluid_warps, body_steps_fluid=body_fluid_warps, j_atomics_tile=0,
             j_atomics_block4=0, j_atomics_block8=0, block8_union_max=0)
    return r, inside_set


# ---------------------------------------------------------------------------------------------
# Clusterings: lists of particle index arrays in a cluster order (members ascending in it)

def column_clusters(pos, ids, s, origin):
    """particle_clusters.hpp: the solver's sorted order; each (x, y) column's runs of non-empty
    cells cut into 8s from their start."""
    order, c, key, dims = solver_order(pos, ids, s, origin)
    column = c[:, 0] * dims[1] + c[:, 1]
    # a new segment starts at a new column or where the z-cell jumps by more than one
    new = np.ones(len(order), bool)
    new[1:] = (column[1:] != column[:-1]) | (c[1:, 2] - c[:-1, 2] > 1)
    return order, segments_to_clusters(new)


def cube_clusters(pos, ids, s):
    """GROMACS-like: 2 dp x 2 dp columns in (x, y), sorted by z, cut in 8s, and at z gaps > 2 dp."""
    w = 2 * s.dp
    lo = pos.min(axis=0) - 0.5 * s.dp
    cx = np.floor((pos[:, 0] - lo[0]) / w).astype(np.int64)
    cy = np.floor((pos[:, 1] - lo[1]) / w).astype(np.int64)
    column = cx * (cy.max() + 1) + cy
    order = np.lexsort((ids, pos[:, 2], column))
    col, z = column[order], pos[order, 2]
    new = np.ones(len(order), bool)
    new[1:] = (col[1:] != col[:-1]) | (z[1:] - z[:-1] > w)
    return order, segments_to_clusters(new)


def segments_to_clusters(new_segment):
    """Cluster index of each particle (in the order): segments cut into CLUSTER from their start."""
    n = len(new_segment)
    seg = np.cumsum(new_segment) - 1
    seg_start = np.flatnonzero(new_segment)
    rank = np.arange(n) - seg_start[seg]
    new_cluster = rank % CLUSTER == 0
    return np.cumsum(new_cluster) - 1


# ---------------------------------------------------------------------------------------------
# Designs 2 and 3: symmetric cluster pairs, 8 x 4 tiles

def cluster_design(name, pos, fluid, ids, s, order, cluster_of, shrink_box=1.0):
    pos, fluid, ids = pos[order], fluid[order], ids[order]
    N = len(pos)
    nc = int(cluster_of[-1]) + 1
    size = np.bincount(cluster_of, minlength=nc)
    assert size.max() <= CLUSTER
    begin = np.cumsum(size) - size
    slot = np.arange(N) - begin[cluster_of]
    M = -np.ones((nc, CLUSTER), np.int64)  # members, -1 where the cluster is short
    M[cluster_of, slot] = np.arange(N)
    lo = np.full((nc, 3), np.inf)
    hi = np.full((nc, 3), -np.inf)
    np.minimum.at(lo, cluster_of, pos)
    np.maximum.at(hi, cluster_of, pos)
    has_fluid = np.zeros(nc, bool)
    has_fluid[cluster_of[fluid]] = True
    all_fluid = np.ones(nc, bool)
    all_fluid[cluster_of[~fluid]] = False
    # Listed cluster pairs I <= J: every pair of boxes tested (no search structure to get wrong).
    box_reach2 = (s.reach * shrink_box) ** 2
    PI, PJ = [], []
    step = 256
    for i0 in range(0, nc, step):
        I = np.arange(i0, min(i0 + step, nc))
        gap = np.maximum(0.0, np.maximum(lo[None, :, :] - hi[I, None, :], lo[I, None, :] - hi[None, :, :]))
        d2 = (gap ** 2).sum(axis=2)
        ok = (d2 < box_reach2) & (np.arange(nc)[None, :] >= I[:, None])
        ok &= has_fluid[I][:, None] | has_fluid[None, :]
        ii, jj = np.nonzero(ok)
        PI.append(I[ii])
        PJ.append(jj)
    PI, PJ = np.concatenate(PI), np.concatenate(PJ)
    # Every listed pair: 8 x 8 slots.
    candidates = tiles = body_tiles = lane_candidates = j_loads = inside_fluid = body_tiles_fluid = 0
    j_atomics_tile = 0
    block_keys = {4: [], 8: []}
    width = np.where(fluid, 4, 1)  # integer additions a j takes: acceleration and density, or density
    n_inside = 0
    keys = []
    nid = int(ids.max()) + 1
    tri = np.triu(np.ones((CLUSTER, CLUSTER), bool), 1)  # i slot < j slot, for I = J
    chunk = 20000
    for p0 in range(0, len(PI), chunk):
        I, J = PI[p0:p0 + chunk], PJ[p0:p0 + chunk]
        mi, mj = M[I], M[J]
        exist = (mi >= 0)[:, :, None] & (mj >= 0)[:, None, :]
        valid = exist & np.where((I == J)[:, None, None], tri[None], True)
        mi0, mj0 = np.maximum(mi, 0), np.maximum(mj, 0)
        d2 = ((pos[mi0][:, :, None, :] - pos[mj0][:, None, :, :]) ** 2).sum(axis=3)
        acts = valid & (fluid[mi0][:, :, None] | fluid[mj0][:, None, :])  # wall-wall does nothing
        hit = acts & inside(d2, s)
        candidates += int(valid.sum())
        n_inside += int(hit.sum())
        e = np.nonzero(hit)
        keys.append(pair_key(ids[mi0[e[0], e[1]]], ids[mj0[e[0], e[2]]], nid))
        # tiles: J's slots 0-3 and 4-7
        for t in range(CLUSTER // TILE_J):
            sl = slice(t * TILE_J, (t + 1) * TILE_J)
            present = (mj[:, sl] >= 0).any(axis=1)
            tiles += int(present.sum())
            tile_hit = hit[:, :, sl].any(axis=(1, 2))
            body_tiles += int(tile_hit.sum())
            # tiles of fluid only (every present i and j): the bulk of the water
            fl = all_fluid[I] & (fluid[mj0[:, sl]] | (mj[:, sl] < 0)).all(axis=1)
            inside_fluid += int(hit[fl][:, :, sl].sum())
            body_tiles_fluid += int((tile_hit & fl).sum())
            lane_candidates += int(valid[:, :, sl].sum())
            j_loads += int((mj[:, sl] >= 0).sum())
            j_hit = hit[:, :, sl].any(axis=1)  # (pairs, 4): j has a pair inside in this tile
            j_atomics_tile += int((j_hit * width[mj0[:, sl]]).sum())
        p_hit, js_hit = np.nonzero(hit.any(axis=1))
        for b in block_keys:
            block_keys[b].append((I[p_hit] // b) * N + mj0[p_hit, js_hit])
    keys = np.concatenate(keys)
    inside_set = np.unique(keys)
    assert len(inside_set) == len(keys), f"{name}: an inside pair evaluated twice"
    j_atomics_block = {}
    for b, k in block_keys.items():
        distinct = np.unique(np.concatenate(k)) if k else np.zeros(0, np.int64)
        j_atomics_block[b] = int(width[distinct % N].sum())
    union = np.unique((PI // max(block_keys)) * nc + PJ)
    block8_union_max = int(np.bincount(union // nc).max()) if len(union) else 0
    r = dict(design=name, clusters=nc, cluster_fill=N / nc, cluster_pairs=len(PI), candidates=candidates,
             inside_unordered=n_inside, body_needed=n_inside, steps=tiles, body_steps=body_tiles,
             lane_candidates=lane_candidates, list_entries=len(PI), j_loads=j_loads,
             inside_fluid=inside_fluid, body_steps_fluid=body_tiles_fluid, j_atomics_tile=j_atomics_tile,
             j_atomics_block4=j_atomics_block[4], j_atomics_block8=j_atomics_block[8],
             block8_union_max=block8_union_max)
    return r, inside_set


# ---------------------------------------------------------------------------------------------

def run_designs(pos, fluid, ids, s, origin, shrink_box=1.0, stencil=None):
    stencil = s.n if stencil is None else stencil
    rows, sets = [], []
    r, st = full_lists(pos, fluid, ids, s, origin, stencil)
    rows.append(r)
    sets.append(st)
    o, cl = column_clusters(pos, ids, s, origin)
    r, st = cluster_design("cluster8-column", pos, fluid, ids, s, o, cl, shrink_box)
    rows.append(r)
    sets.append(st)
    o, cl = cube_clusters(pos, ids, s)
    r, st = cluster_design("cluster8-cube", pos, fluid, ids, s, o, cl, shrink_box)
    rows.append(r)
    sets.append(st)
    return rows, sets


def check_same(rows, sets, truth=None):
    """The designs find the same inside pairs (and the brute force's, when given). Returns the
    list of failures (empty: all agree)."""
    fails = []
    ref = truth if truth is not None else sets[0]
    for r, st in zip(rows, sets):
        if not (len(st) == len(ref) and np.array_equal(st, ref)):
            missing = len(np.setdiff1d(ref, st))
            extra = len(np.setdiff1d(st, ref))
            fails.append(f"{r['design']}: {len(st)} inside pairs, {missing} missing, {extra} extra")
    full = rows[0]
    if full["body_needed"] != 2 * len(ref):
        fails.append(f"full-lists: {full['body_needed']} directed inside entries, not 2 x {len(ref)}")
    for r in rows[1:]:
        if r["body_needed"] != len(ref):
            fails.append(f"{r['design']}: {r['body_needed']} inside evaluations, not {len(ref)}")
    return fails


HEADER = ("time_s,particles,fluid,design,clusters,cluster_fill,cluster_pairs_pp,candidates_pp,inside_unordered_pp,"
          "body_needed_pp,steps_pp,body_lane_slots_pp,test_only_lane_slots_pp,useful_fraction,lane_occupancy,"
          "body_slots_vs_full,list_bytes_pp,j_loads_pp,useful_fraction_fluid,j_atomics_tile_pp,j_atomics_block4_pp,"
          "j_atomics_block8_pp,block8_union_max")


def format_rows(time, N, nfluid, rows):
    out = []
    full_slots = WARP * rows[0]["body_steps"] / N
    for r in rows:
        body_slots = WARP * r["body_steps"] / N
        test_slots = WARP * (r["steps"] - r["body_steps"]) / N
        fill = "" if np.isnan(r["cluster_fill"]) else f"{r['cluster_fill']:.2f}"
        out.append(f"{time:.3f},{N},{nfluid},{r['design']},{r['clusters']},{fill},{r['cluster_pairs'] / N:.2f},"
                   f"{r['candidates'] / N:.1f},{r['inside_unordered'] / N:.2f},{r['body_needed'] / N:.2f},"
                   f"{WARP * r['steps'] / N:.1f},{body_slots:.1f},{test_slots:.1f},"
                   f"{r['body_needed'] / (WARP * r['body_steps']):.3f},"
                   f"{r['lane_candidates'] / (WARP * r['steps']):.3f},{body_slots / full_slots:.3f},"
                   f"{4 * r['list_entries'] / N:.1f},{r['j_loads'] / N:.1f},"
                   f"{r['inside_fluid'] / max(1, WARP * r['body_steps_fluid']):.3f},"
                   f"{r['j_atomics_tile'] / N:.2f},{r['j_atomics_block4'] / N:.2f},{r['j_atomics_block8'] / N:.2f},"
                   f"{r['block8_union_max']}")
    return out


def count_snapshot(path, s, origin):
    import h5py
    with h5py.File(path, "r") as f:
        pos = np.asarray(f["position"], float)
        fluid = np.asarray(f["type"]) == 0
        ids = np.asarray(f["id"], np.int64)
        time = float(f.attrs.get("time", np.nan))
    keep = np.isfinite(pos).all(axis=1)  # out-of-domain particles are written as NaN
    pos, fluid, ids = pos[keep], fluid[keep], ids[keep]
    o = pos.min(axis=0) if origin is None else np.asarray(origin, float)
    rows, sets = run_designs(pos, fluid, ids, s, o)
    fails = check_same(rows, sets)
    assert not fails, f"{path}: designs disagree: " + "; ".join(fails)
    return format_rows(time, len(pos), int(fluid.sum()), rows)


def j_side_atomics_by_pairs(a, b, fluid, order, cluster_of, blocks):
    """j's integer additions counted from a list of inside pairs (original indices a, b), not from
    the tiles: of each pair the particle later in the cluster order is j (I < J, or I = J with i's
    slot below j's), and a j takes its width once per distinct (cluster of i // blocks, j)."""
    rank = np.empty(len(order), np.int64)
    rank[order] = np.arange(len(order))
    ra, rb = rank[a], rank[b]
    i_side, j_side = np.minimum(ra, rb), np.maximum(ra, rb)
    width = np.where(fluid[order], 4, 1)
    distinct = np.unique((cluster_of[i_side] // blocks) * len(order) + j_side)
    return int(width[distinct % len(order)].sum())


def self_test(s, broken):
    rng = np.random.default_rng(25)
    N = 2000
    side = N ** (1 / 3) * s.dp  # the lattice's density, positions random
    pos = rng.uniform(0, side, (N, 3))
    pos[:40] = pos[40:80] + rng.normal(0, 1e-3 * s.dp, (40, 3))  # a few very close pairs
    fluid = pos[:, 2] > 2 * s.dp  # a floor of walls
    ids = rng.permutation(N).astype(np.int64) + 7  # ids unrelated to the order
    d2 = ((pos[:, None, :] - pos[None, :, :]) ** 2).sum(axis=2)
    a, b = np.nonzero(np.triu(inside(d2, s), 1))
    acts = fluid[a] | fluid[b]
    truth = np.unique(pair_key(ids[a[acts]], ids[b[acts]], int(ids.max()) + 1))
    ra, rb = np.nonzero(np.triu(d2 < s.reach2, 1))
    reach_listed = int((fluid[ra] | fluid[rb]).sum())  # within the reach, not wall-wall
    rows, sets = run_designs(pos, fluid, ids, s, pos.min(axis=0),
                             shrink_box=0.8 if broken == "box" else 1.0,
                             stencil=1 if broken == "stencil" else None)
    fails = check_same(rows, sets, truth)
    # j's side against the brute force's pairs (a tile adds each j once, like blocks of one cluster)
    o, cl = column_clusters(pos, ids, s, pos.min(axis=0))
    if broken == "atomics":
        cl = cl // 2  # clusters counted twice as large: every count below must then differ
    for key, blocks in (("j_atomics_tile", 1), ("j_atomics_block4", 4), ("j_atomics_block8", 8)):
        want = j_side_atomics_by_pairs(a[acts], b[acts], fluid, o, cl, blocks)
        if rows[1][key] != want:
            fails.append(f"cluster8-column: {key} {rows[1][key]}, the brute force's pairs give {want}")
    if rows[0]["candidates"] != 2 * reach_listed:
        fails.append(f"full-lists: {rows[0]['candidates']} entries, not 2 x {reach_listed} pairs within the reach")
    print(f"self-test: {N} random particles ({int(fluid.sum())} fluid), {len(truth)} inside pairs by brute force"
          + (f", broken on purpose: {broken}" if broken else ""))
    for r in rows:
        print(f"  {r['design']}: {r['inside_unordered']} inside pairs, {r['body_needed']} body evaluations")
    for line in format_rows(0.0, N, int(fluid.sum()), rows):
        print("  " + line)
    if fails:
        print("self-test FAILED: " + "; ".join(fails))
        return 1
    print("self-test passed: every design finds exactly the brute force's inside pairs")
    return 0


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("snapshots", nargs="*")
    add_geometry_args(p)
    p.add_argument("--origin", default=None,
                   help="grid origin x,y,z (the scene's lo; dsph-dambreak: -2 dp each); default: the particles' min")
    p.add_argument("--self-test", action="store_true")
    p.add_argument("--break", dest="broken", choices=["box", "stencil", "atomics"], default=None,
                   help="self-test only: shrink the cluster box test to 0.8 x reach, search one cell each side, "
                        "or count j's additions from wrong clusters")
    a = p.parse_args(argv)
    s = Setup(a.dp, a.coef_h, a.skin, a.n)
    if a.self_test:
        return self_test(s, a.broken)
    if not a.snapshots:
        p.error("give snapshots or --self-test")
    origin = None if a.origin is None else [float(x) for x in a.origin.split(",")]
    print(HEADER)
    for path in a.snapshots:
        for line in count_snapshot(path, s, origin):
            print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
