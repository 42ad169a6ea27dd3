"""A networkx analysis of a dataset: per preset, how large, how looped and how deep the
networks are.

Makes a dataset of mine, cave and lava-tube layouts (no meshes: seconds), as
`subtgraph dataset` does, with the ground-truth graph in GraphML, then reads every world's
graph with networkx.

    python examples/python/networkx_dataset.py data/graphs --count 20
"""

import argparse
import json
import pathlib
import statistics

import networkx as nx

import subtgraph


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=pathlib.Path, help="the dataset folder (made, or resumed)")
    ap.add_argument("--count", type=int, default=20, help="worlds per preset")
    ap.add_argument("--seed", type=int, default=1000)
    args = ap.parse_args()
    summary = subtgraph.dataset(
        args.out, presets=["mine", "cave", "lava-tube"], count=args.count, seed=args.seed,
        mesh=False, formats=["graph"],
    )
    print(f"dataset {args.out}: made {summary['made']}, kept {summary['skipped']}")
    index = json.loads((args.out / "index.json").read_text())
    worlds = index["worlds"] if isinstance(index, dict) else index
    by_preset = {}
    for w in worlds:
        name = w["name"] if isinstance(w, dict) else w
        g = nx.read_graphml(args.out / name / "ground_truth" / "graph.graphml")
        g = nx.MultiGraph(g)
        preset = name.rsplit("-", 1)[0]
        loops = g.number_of_edges() - g.number_of_nodes() + nx.number_connected_components(g)
        simple = nx.Graph(g)
        by_preset.setdefault(preset, []).append(
            (g.number_of_nodes(), g.number_of_edges(), loops, nx.diameter(simple))
        )
    print(f"{'preset':<10} {'worlds':>6} {'nodes':>7} {'edges':>7} {'loops':>7} {'hops across':>12}")
    for preset, rows in by_preset.items():
        cols = list(zip(*rows))
        print(
            f"{preset:<10} {len(rows):>6} "
            + " ".join(f"{statistics.mean(c):>7.1f}" for c in cols[:3])
            + f" {statistics.mean(cols[3]):>12.1f}"
        )


if __name__ == "__main__":
    main()
