"""Compare two rodsim output files bit for bit.

    /usr/bin/python3 scripts/h5_bitwise_diff.py A.h5 B.h5 [--ignore-attr NAME ...]

Every dataset must have the same shape, dtype and bytes (NaN compared by bit
pattern); every attribute must be equal, except the ones named with
--ignore-attr (e.g. git_revision, wall_seconds). Exit status 0 when equal, 1
with a list of the differences otherwise. Used for the one-time check that a
refactoring leaves rodsim's output unchanged (docs/architecture.md).
"""
import argparse
import sys

import h5py
import numpy as np


def _items(f):
    out = {}
    f.visititems(lambda name, obj: out.__setitem__(name, obj))
    return out


def _attr_equal(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.kind in "fc" and b.dtype.kind in "fc":
        return a.shape == b.shape and a.tobytes() == b.tobytes()
    return a.shape == b.shape and bool(np.all(a == b))


def diff(path_a, path_b, ignore=()):
    problems = []
    with h5py.File(path_a, "r") as fa, h5py.File(path_b, "r") as fb:
        ia, ib = _items(fa), _items(fb)
        for name in sorted(set(ia) ^ set(ib)):
            problems.append(f"{name}: only in {'A' if name in ia else 'B'}")
        objs = [("/", fa, fb)] + [(n, ia[n], ib[n]) for n in sorted(set(ia) & set(ib))]
        for name, oa, ob in objs:
            if isinstance(oa, h5py.Dataset):
                if not isinstance(ob, h5py.Dataset):
                    problems.append(f"{name}: dataset in A, group in B")
                    continue
                va, vb = oa[()], ob[()]
                if isinstance(va, np.ndarray):
                    same = (va.shape == vb.shape and va.dtype == vb.dtype and va.tobytes() == vb.tobytes())
                else:
                    same = va == vb
                if not same:
                    problems.append(f"{name}: dataset differs")
            for key in sorted(set(oa.attrs) | set(ob.attrs)):
                if key in ignore:
                    continue
                if key not in oa.attrs or key not in ob.attrs:
                    problems.append(f"{name}@{key}: attribute only in {'A' if key in oa.attrs else 'B'}")
                elif not _attr_equal(oa.attrs[key], ob.attrs[key]):
                    problems.append(f"{name}@{key}: {oa.attrs[key]!r} != {ob.attrs[key]!r}")
    return problems


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("a")
    p.add_argument("b")
    p.add_argument("--ignore-attr", action="append", default=[])
    args = p.parse_args(argv)
    problems = diff(args.a, args.b, set(args.ignore_attr))
    for line in problems:
        print(line)
    print(f"{args.a} vs {args.b}: {'EQUAL' if not problems else f'{len(problems)} difference(s)'}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
