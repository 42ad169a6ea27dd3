"""Triangles by the squares of the plane their bounding boxes cover, for the readers that follow
vertical lines (or short segments) through a surface: a line meets only the triangles of its
own square, so a check asks a few hundred triangles per point instead of every one of a
million. Shared by the ground-truth, artifact, rubble, tasks and centreline checks."""
import numpy as np


def plane_squares(lo, hi, size, keep=None):
    """`{(i, j): triangle indices}` for the squares `size` metres a side that the boxes from
    `lo` to `hi` ((T, 2) arrays of x, y in metres; grow them first for a margin) cover, the
    indices ascending within a square; only the triangles `keep` (ascending indices) when given.
    Built without a Python loop over the triangles."""
    idx = np.arange(len(lo)) if keep is None else np.asarray(keep)
    blo = np.floor(lo[idx] / size).astype(np.int64)
    bhi = np.floor(hi[idx] / size).astype(np.int64)
    ny = bhi[:, 1] - blo[:, 1] + 1
    count = (bhi[:, 0] - blo[:, 0] + 1) * ny
    # Every (triangle, square) pair: triangle r's k-th square, row by row.
    r = np.repeat(np.arange(len(idx)), count)
    k = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    bx = blo[r, 0] + k // ny[r]
    by = blo[r, 1] + k % ny[r]
    t = idx[r]
    order = np.lexsort((t, by, bx))
    t, bx, by = t[order], bx[order], by[order]
    starts = np.nonzero(np.r_[True, (bx[1:] != bx[:-1]) | (by[1:] != by[:-1])])[0]
    ends = np.r_[starts[1:], len(t)]
    return {(int(bx[s]), int(by[s])): t[s:e] for s, e in zip(starts, ends)}
