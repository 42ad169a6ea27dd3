"""An OBJ file's vertices, triangles and materials, read with numpy: the reader shared by the
centreline, wall-relief, floor, refuge-bay and services checks (each had its own; the
line-by-line ones took seconds on a mine's visual mesh of 3.6 M triangles).

The `v`, `f` and `usemtl` lines are found by numpy over the file's bytes, and the numbers of
each run of `v` or `f` lines are parsed by numpy's own text parser: no Python object per
number or per line. References may be `v`, `v/vt`, `v/vt/vn` or `v//vn`, 1-based or negative
from the end; polygons are fanned into triangles (0, k, k + 1). Independent of our writer:
only the OBJ format's rules are used."""
import re
from pathlib import Path

import numpy as np


class Obj:
    """What `read_obj` gives.

    vertices: (n, 3) float; triangles: (m, 3) zero-based vertex indices; materials: the
    `usemtl` names in the order they first appear; material: (m,) index into `materials` of
    each triangle's material (-1 before any `usemtl`); faces: how many `f` lines each material
    has (a polygon counts once)."""

    def __init__(self, vertices, triangles, materials, material, faces):
        self.vertices = vertices
        self.triangles = triangles
        self.materials = materials
        self.material = material
        self.faces = faces

    def by_material(self):
        """`{name: (k, 3) triangles}` (None for triangles before any `usemtl`)."""
        out = {}
        for i in np.unique(self.material):
            name = self.materials[i] if i >= 0 else None
            out[name] = self.triangles[self.material == i]
        return out

    def corners(self):
        """The triangles' corners, (m, 3, 3)."""
        return self.vertices[self.triangles]


def read_obj(path):
    data = Path(path).read_bytes()
    buf = np.frombuffer(data + b"\n", dtype=np.uint8)
    ends = np.flatnonzero(buf == ord("\n"))
    starts = np.r_[0, ends[:-1] + 1]
    first = buf[starts]
    second = buf[np.minimum(starts + 1, len(buf) - 1)]

    def lines_of(letter):
        """The lines starting `letter` and a blank, less that word, their line numbers. Lines
        of a kind come in runs (all vertices, then faces by material): one slice a run."""
        pick = (first == ord(letter)) & (second == ord(" "))
        edges = np.flatnonzero(np.diff(np.r_[0, pick.astype(np.int8), 0]))
        runs = [data[starts[a] : ends[b - 1]] for a, b in zip(edges[::2], edges[1::2])]
        prefix = b"\n" + letter.encode() + b" "
        return (b"\n" + b"\n".join(runs)).replace(prefix, b"\n "), np.flatnonzero(pick)

    vtext, vertex_lines = lines_of("v")
    # numpy's own text parser: no Python object per number. `v` lines may carry a colour
    # after x y z: the numbers per line then differ from 3, read line by line instead.
    v = np.fromstring(vtext, sep=" ")
    if len(v) != 3 * len(vertex_lines):
        v = np.array([l.split()[:3] for l in vtext.split(b"\n") if l.strip()], dtype=float)
    v = v.reshape(-1, 3)
    ftext, face_lines = lines_of("f")
    nfaces = len(face_lines)
    flat = None
    if b"/" not in ftext:
        flat = np.fromstring(ftext, dtype=np.int64, sep=" ")
    elif b"//" not in ftext:
        # `v/vt/vn` (or `v/vt`): with every reference in the first one's form, the slashes
        # made blanks give each reference's numbers in turn. Each line is a newline and a
        # blank before each reference, so the blanks count the references; anything else
        # (mixed forms, extra blanks) fails the counts and is read the slow way.
        parts = ftext.split(None, 1)[0].count(b"/") + 1
        refs = ftext.count(b" ")
        blanks = ftext.translate(bytes.maketrans(b"/", b" "))
        numbers = np.fromstring(blanks, dtype=np.int64, sep=" ")
        if ftext.count(b"/") == refs * (parts - 1) and len(numbers) == refs * parts:
            flat = numbers[::parts]
    if flat is None or len(flat) != 3 * nfaces:
        # The slow way: each reference's `/...` cut off, and each face's count (polygons).
        ftext = re.sub(rb"/\S*", b"", ftext)
        flat = np.array(ftext.split()).astype(np.int64)
        counts = np.array([len(l.split()) for l in ftext.split(b"\n") if l.strip()], dtype=np.int64)
    else:
        # Every face has three vertices or more: this many means triangles only.
        counts = np.full(nfaces, 3)
    flat = np.where(flat < 0, flat + len(v), flat - 1)

    # Each face's material: the last `usemtl` line above it (there are few: a Python loop).
    names, use_lines, use_index = [], [], []
    for i in np.flatnonzero(first == ord("u")):
        line = data[starts[i] : ends[i]].split()
        if len(line) >= 2 and line[0] == b"usemtl":
            name = line[1].decode()
            if name not in names:
                names.append(name)
            use_lines.append(i)
            use_index.append(names.index(name))
    at = np.searchsorted(np.asarray(use_lines, dtype=np.int64), face_lines, side="right") - 1
    face_material = np.where(at >= 0, np.asarray(use_index + [-1], dtype=np.int64)[at], -1)

    # Fans, faces of each size at a time; `face_of` says whose each triangle is.
    tris, face_of = [], []
    fstarts = np.cumsum(counts) - counts
    for n in np.unique(counts):
        which = np.flatnonzero(counts == n)
        idx = flat[fstarts[which][:, None] + np.arange(n)]
        for k in range(1, n - 1):
            tris.append(np.stack([idx[:, 0], idx[:, k], idx[:, k + 1]], axis=1))
            face_of.append(which)
    if tris:
        # Back in the file's order: by face, a face's fan in order (the sort is stable).
        face = np.concatenate(face_of)
        order = np.argsort(face, kind="stable")
        triangles = np.concatenate(tris)[order]
        material = face_material[face[order]]
    else:
        triangles = np.zeros((0, 3), dtype=np.int64)
        material = np.zeros(0, dtype=np.int64)
    faces = {
        (names[i] if i >= 0 else None): int(c)
        for i, c in zip(*np.unique(face_material, return_counts=True))
    }
    return Obj(v, triangles, names, material, faces)
