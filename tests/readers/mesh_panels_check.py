"""Mesh panels and half-barrel marks of a mine world, measured on its exported OBJ and its
texture images, apart from the tile sets' code.

    python mesh_panels_check.py WORLD --mesh-from M [--plain OTHER_WORLD]

Geometry (numpy over the OBJ through obj_reader, heights above a floor fitted per straight
cell as wall_relief_check.py does):
- `meshed_low_m`: the 1st percentile of the height above the floor of the `meshed-wall`
  triangles' centroids, `wall_high_m` the 99th of the `*-wall` ones without mesh: the mesh
  ends at M metres up, give or take a lattice cell;
- `back_meshed_share`: of the area of the triangles facing down (the back, normal z < -0.5)
  in straight cells, the share that is meshed;
- with --plain (the same world with mesh_from = 0): `same_geometry` is whether both files hold
  the same triangles (sorted vertex coordinates), the materials aside, `plain_meshed` how
  many meshed triangles the plain one has and `plain_mark_correlation` its wall's (no marks
  without mesh).

Textures (Pillow and numpy's FFT over mesh/textures/):
- `grid_cycles`: the fundamental frequency, in cycles per image, of the meshed wall's albedo
  averaged over rows and over columns: the wire grid's (30 cells per 3 m repeat);
- `mark_correlation`: how much the mine wall's albedo has thin lines running along u (the
  half-barrel marks; see `along_u`).
Prints one JSON line.
"""

import argparse
import json
import sys

import numpy as np
from PIL import Image

import obj_reader
from wall_relief_check import buckets, floor_fit, straight_cells


def heights(obj, topology):
    """Per straight cell: (material name per triangle, centroid height above the floor,
    triangle area, normal z) for the cell's triangles."""
    v = obj.vertices
    groups = obj.by_material()
    pitch = topology["tile_pitch_m"]
    rows = topology["rows"]
    all_by = buckets(v, topology)
    names, tris = [], []
    for n, t in groups.items():
        names += [n] * len(t)
        tris.append(t)
    tris = np.concatenate(tris)
    names = np.array(names)
    a, b, c = v[tris[:, 0]], v[tris[:, 1]], v[tris[:, 2]]
    cen = (a + b + c) / 3.0
    cross = np.cross(b - a, c - a)
    area = 0.5 * np.linalg.norm(cross, axis=1)
    nz = cross[:, 2] / np.maximum(2.0 * area, 1e-12)
    out = []
    for cell, axis in straight_cells(topology):
        k = cell["level"] * 1_000_000 + cell["row"] * 1000 + cell["col"]
        if k not in all_by:
            continue
        centre = np.array([cell["col"] * pitch, (rows - 1 - cell["row"]) * pitch])
        lh = topology["level_height_m"]
        inside = (
            (np.abs(cen[:, 0] - centre[0]) < 0.5 * pitch)
            & (np.abs(cen[:, 1] - centre[1]) < 0.5 * pitch)
            & (np.abs(cen[:, 2] - cell["level"] * lh - 0.25 * lh) < 0.75 * lh)
        )
        along = cen[inside, axis] - centre[axis]
        z = cen[inside, 2] - floor_fit(all_by[k], axis, centre)(along)
        out.append((names[inside], z, area[inside], nz[inside]))
    return out


def fundamental(profile):
    """The fundamental frequency (cycles per image) of a profile, its mean removed: the lowest
    whose amplitude is at least half the strongest's (a comb of thin lines has harmonics as
    strong as its fundamental)."""
    p = np.asarray(profile, float)
    spectrum = np.abs(np.fft.rfft(p - p.mean()))
    spectrum[:3] = 0.0
    return int(np.argmax(spectrum >= 0.5 * spectrum.max()))


def along_u(img):
    """How much thin features across `v` run on along `u`: the image high-passed across its
    rows (each pixel less the mean of those a 85th of the image above and below), correlated
    with itself a 16th of the image along `u`. Lines along `u` keep it high; rock's cracks,
    which run every way, near 0."""
    n = img.shape[0]
    k, lag = max(2, n // 85), n // 16
    hp = img - 0.5 * (np.roll(img, k, axis=0) + np.roll(img, -k, axis=0))
    return float(np.corrcoef(hp.ravel(), np.roll(hp, lag, axis=1).ravel())[0, 1])


def luminance(path):
    return np.asarray(Image.open(path).convert("L"), float)


def triangles(obj):
    """The triangles as a sorted list of their corners' coordinates (mm), each triangle's
    corners sorted: the same for two files that hold the same triangles in any order."""
    t = np.round(obj.vertices[obj.triangles] * 1000).astype(np.int64).tolist()
    return sorted(tuple(sorted(map(tuple, tri))) for tri in t)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("world")
    ap.add_argument("--mesh-from", type=float, required=True)
    ap.add_argument("--plain")
    args = ap.parse_args()
    topology = json.load(open(f"{args.world}/topology.json"))
    obj = obj_reader.read_obj(f"{args.world}/mesh/world.obj")
    meshed_z, wall_z, back, back_meshed = [], [], 0.0, 0.0
    for names, z, area, nz in heights(obj, topology):
        meshed = names == "meshed-wall"
        wall = np.char.endswith(names.astype(str), "-wall") & ~meshed
        meshed_z.append(z[meshed])
        wall_z.append(z[wall])
        down = (nz < -0.5) & (meshed | wall)
        back += area[down].sum()
        back_meshed += area[down & meshed].sum()
    meshed_z = np.concatenate(meshed_z)
    wall_z = np.concatenate(wall_z)
    if meshed_z.size == 0:
        sys.exit(f"FAIL: no meshed-wall triangles in the straight cells of {args.world}")
    textures = f"{args.world}/mesh/textures"
    mesh_img = luminance(f"{textures}/meshed-wall-albedo.png")
    wall_img = luminance(f"{textures}/mine-wall-albedo.png")
    out = {
        "meshed_triangles": int(meshed_z.size),
        "meshed_low_m": float(np.percentile(meshed_z, 1)),
        "wall_high_m": float(np.percentile(wall_z, 99)),
        "back_meshed_share": float(back_meshed / back),
        "grid_cycles": [fundamental(mesh_img.mean(axis=0)), fundamental(mesh_img.mean(axis=1))],
        "texture_pixels": int(mesh_img.shape[1]),
        "mark_correlation": along_u(wall_img),
    }
    if args.plain:
        plain = obj_reader.read_obj(f"{args.plain}/mesh/world.obj")
        out["same_geometry"] = triangles(obj) == triangles(plain)
        plain_wall = luminance(f"{args.plain}/mesh/textures/mine-wall-albedo.png")
        out["plain_mark_correlation"] = along_u(plain_wall)
        out["plain_meshed"] = int(len(plain.by_material().get("meshed-wall", [])))
    print(json.dumps(out))


if __name__ == "__main__":
    main()
