"""What the physics checks share: which corridor cell of a world they drop or drive at.

Imported by mujoco_check.py and pybullet_check.py (run by path, so this folder is on sys.path).
"""


def corridor_cell(topology):
    """The straight cell nearest the middle of the longest corridor of level 0 (a cave's corner
    bends round, away from its cell centre), and its nominal floor position."""
    edges = [e for e in topology["edges"] if e["kind"] == "corridor" and e["cells"][0]["level"] == 0]

    def straight(cells, i):
        a, b = cells[i - 1], cells[i + 1]
        return 0 < i < len(cells) - 1 and (a["row"] == b["row"] or a["col"] == b["col"])

    def middle_straight(e):
        cells, mid = e["cells"], len(e["cells"]) // 2
        ok = [i for i in range(1, len(cells) - 1) if straight(cells, i)]
        return min(ok, key=lambda i: (abs(i - mid), i)) if ok else mid

    edge = max(edges, key=lambda e: (any(straight(e["cells"], i) for i in range(1, len(e["cells"]) - 1)), len(e["cells"]), -e["id"]))
    cell = edge["cells"][middle_straight(edge)]
    pitch = topology["tile_pitch_m"]
    x = cell["col"] * pitch
    y = (topology["rows"] - 1 - cell["row"]) * pitch
    z = cell["level"] * topology["level_height_m"]
    return cell, [x, y, z]
