"""An Isaac Lab style terrain list: a curriculum of worlds on disk, each a USD stage with
UsdPhysics colliders, and a JSON list of them with difficulty and spawn poses.

Isaac Lab's terrain importer takes a USD file per terrain (`TerrainImporterCfg(
terrain_type="usd", usd_path=...)`); a curriculum walks the list from easy to hard. Here the
difficulty grows with the number of levels and structures.

    python examples/python/isaac_terrains.py worlds/terrains --count 4
"""

import argparse
import json
import pathlib

import subtgraph


def terrain(k, count, max_levels, max_length):
    """The k-th terrain's pipeline: from one small level to several larger ones."""
    d = k / max(count - 1, 1)
    return {
        "world": {
            "seed": 100 + k,
            "levels": 1 + round((max_levels - 1) * d),
            "min_length": 1500 + round((max_length - 1500) * d),
        },
        "topology": {"loops": round(2 * d), "t_junctions": 1 + round(2 * d), "intersections": 1},
        "route": {"type": "harmonic", "harmonics": 3},
        "tileset": {"type": "lava-tube" if d > 0.5 else "cave"},
    }, d


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=pathlib.Path, help="folder for the terrains and terrains.json")
    ap.add_argument("--count", type=int, default=4)
    ap.add_argument("--max-levels", type=int, default=3, help="levels of the hardest terrain")
    ap.add_argument("--max-length", type=int, default=4000,
                    help="world.min_length (metres of passages) of the hardest terrain")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    terrains = []
    for k in range(args.count):
        pipeline, difficulty = terrain(k, args.count, args.max_levels, args.max_length)
        world = subtgraph.generate(pipeline=pipeline, formats=["usd", "spawn-poses"])
        folder = args.out / f"terrain-{k:02d}"
        world.export(folder)
        poses = json.loads((folder / "ground_truth" / "spawn_poses.json").read_text())
        terrains.append({
            "name": folder.name,
            "usd_path": str((folder / "usd" / "world.usda").resolve()),
            "difficulty": round(difficulty, 3),
            "levels": world.shape[0],
            "spawn_poses": poses,
        })
        print(f"{folder}: difficulty {difficulty:.2f}, {world.shape[0]} level(s)")
    listing = args.out / "terrains.json"
    listing.write_text(json.dumps({"terrains": terrains}, indent=2) + "\n")
    print(f"wrote {listing}")


if __name__ == "__main__":
    main()
