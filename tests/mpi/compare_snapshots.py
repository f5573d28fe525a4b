"""Compares two snapshot series (folders of HDF5 files, as sphbench --snapshot-every writes
them) particle by particle, by id: positions, velocities and densities must be bitwise equal
and every id held once. Exit 0 when they are; 1, naming the first file that differs."""
import pathlib
import sys

import h5py
import numpy as np


def by_id(path):
    with h5py.File(path, "r") as f:
        ids = f["id"][:]
        order = np.argsort(ids, kind="stable")
        return ids[order], {k: f[k][:][order] for k in ("position", "velocity", "density")}


def main(a_dir, b_dir):
    a_files = sorted(pathlib.Path(a_dir).glob("*.h5"))
    b_files = sorted(pathlib.Path(b_dir).glob("*.h5"))
    if not a_files or [p.name for p in a_files] != [p.name for p in b_files]:
        print(f"the snapshot series differ: {len(a_files)} files in {a_dir}, {len(b_files)} in {b_dir}")
        return 1
    for pa, pb in zip(a_files, b_files):
        ida, a = by_id(pa)
        idb, b = by_id(pb)
        if len(np.unique(idb)) != len(idb) or not np.array_equal(ida, idb):
            print(f"{pb.name}: the particle ids differ (lost, duplicated or extra)")
            return 1
        for k in a:
            # NaN marks a particle outside the domain; equal_nan keeps those equal.
            if not np.array_equal(a[k], b[k], equal_nan=True):
                print(f"{pb.name}: {k} differs for {int(np.sum(a[k] != b[k]))} values")
                return 1
    print(f"{len(a_files)} snapshots bitwise equal by id")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
