"""Checks that a `sense --route shaft|edge:N|node:N` sequence goes straight to its target,
against the world's ground-truth graph read with networkx (its own shortest paths):

    route_target_check.py GRAPH_JSON SEQUENCE TARGET

- shaft: the shaft whose foot (lower end) is nearest the graph's start over every edge: the
  sequence starts within 2.5 m of that foot (in the plane), its LiDAR is 3 m above the foot
  within 10 s, and climbs at least 80 % of the shaft's height;
- edge:N: the sequence starts within 2.5 m of the end of edge N nearer the start (shafts
  left out: a ground robot), and within 12 s is within 3 m of the edge's polyline
  everywhere it goes;
- node:N: it starts within 2.5 m of the far end of N's shortest edge (ground platform: no
  shafts), and passes within 3 m of N.

Prints one JSON line with what it measured.
"""
import json
import sys
from pathlib import Path

import networkx as nx
import numpy as np

graph = json.loads(Path(sys.argv[1]).read_text())
seq = Path(sys.argv[2])
target = sys.argv[3]
tum = np.loadtxt(seq / "ground_truth.tum", ndmin=2)
t, p = tum[:, 0], tum[:, 1:4]
nodes = {n["id"]: np.array(n["position"], dtype=float) for n in graph["nodes"]}
start = graph.get("start", 0)


def shortest(allow_shafts):
    g = nx.Graph()
    g.add_nodes_from(nodes)
    for e in graph["edges"]:
        if e["kind"] == "shaft" and not allow_shafts:
            continue
        w = max(e["length_m"], 0.001)
        if g.has_edge(e["from"], e["to"]) and g[e["from"]][e["to"]]["weight"] <= w:
            continue
        g.add_edge(e["from"], e["to"], weight=w)
    return nx.single_source_dijkstra(g, start)


def plane(a, b):
    return float(np.hypot(a[0] - b[0], a[1] - b[1]))


def near_line(q, line):
    line = np.asarray(line, dtype=float)
    best = np.inf
    for a, b in zip(line[:-1], line[1:]):
        ab = b[:2] - a[:2]
        f = np.clip(np.dot(q[:2] - a[:2], ab) / max(np.dot(ab, ab), 1e-12), 0, 1)
        best = min(best, float(np.linalg.norm(q[:2] - (a[:2] + f * ab))))
    return best


out = {"target": target}
if target == "shaft":
    dist, _ = shortest(True)
    shafts = [e for e in graph["edges"] if e["kind"] == "shaft"]
    assert shafts, "the world has no shaft"

    def foot(e):
        return e["from"] if nodes[e["from"]][2] <= nodes[e["to"]][2] else e["to"]

    e = min(shafts, key=lambda e: (dist.get(foot(e), np.inf), e["id"]))
    f = nodes[foot(e)]
    height = abs(nodes[e["from"]][2] - nodes[e["to"]][2])
    start_gap = plane(p[0], f)
    above = np.nonzero(p[:, 2] > f[2] + 3.0)[0]
    assert start_gap < 2.5, f"starts {start_gap:.1f} m from shaft {e['id']}'s foot"
    assert len(above) and t[above[0]] - t[0] < 10.0, "not in the shaft within 10 s"
    climbed = float(p[:, 2].max() - p[0, 2])
    assert climbed > 0.8 * height - 1.0, f"climbed {climbed:.1f} m of {height:.1f}"
    out.update(shaft=e["id"], start_gap_m=start_gap, in_shaft_after_s=float(t[above[0]] - t[0]),
               climbed_m=climbed, height_m=height)
elif target.startswith("edge:"):
    n = int(target[5:])
    e = graph["edges"][n]
    dist, _ = shortest(False)
    first = e["from"] if dist.get(e["from"], np.inf) <= dist.get(e["to"], np.inf) else e["to"]
    gap = plane(p[0], nodes[first])
    assert gap < 2.5, f"starts {gap:.1f} m from edge {n}'s near end"
    off = max(near_line(q, e["polyline"]) for q in p[t - t[0] < 12.0])
    assert off < 3.0, f"strays {off:.1f} m from edge {n}"
    out.update(start_gap_m=gap, farthest_from_edge_m=off)
else:
    n = int(target[5:])
    incident = [e for e in graph["edges"] if n in (e["from"], e["to"]) and e["kind"] != "shaft"]
    shortest_edge = min(incident, key=lambda e: (e["length_m"], e["id"]))
    far_end = shortest_edge["to"] if shortest_edge["from"] == n else shortest_edge["from"]
    gap = plane(p[0], nodes[far_end])
    assert gap < 2.5, f"starts {gap:.1f} m from the far end of node {n}'s shortest edge"
    closest = min(plane(q, nodes[n]) for q in p)
    assert closest < 3.0, f"passes {closest:.1f} m from node {n}"
    out.update(start_gap_m=gap, closest_to_node_m=closest)
print(json.dumps(out))
