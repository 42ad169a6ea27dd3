"""A route descriptor and a constraint shape written in Python, no compiler involved.

`spiral` bends every corridor into two waves whose amplitude grows along it; `l-bend` is a
corner with two arms. Both are registered at run time and named by the pipeline like any
built-in; the world is exported as a folder.

    python examples/python/custom_route.py worlds/spiral
"""

import argparse
import math

import subtgraph


@subtgraph.route_descriptor("spiral")
class Spiral:
    """Two waves whose amplitude grows from start to end."""

    def __init__(self, amplitude=3.0, waves=2):
        self.amplitude = amplitude
        self.waves = waves

    def offset(self, t, segment):
        # 0 at both ends, so routes meet their nodes; `side` is drawn per route.
        return segment.side * self.amplitude * t * math.sin(self.waves * math.pi * t)


@subtgraph.constraint_shape("l-bend")
class LBend:
    """A corner with an arm east and an arm south."""

    footprint = [(0, 0), (0, 1), (1, 0)]
    arms = [((0, 1), "east"), ((1, 0), "south")]


PIPELINE = {
    "world": {"seed": 7, "levels": 2, "rows": 48, "cols": 48},
    "topology": {"t_junctions": 2, "structure": [{"type": "l-bend", "count": 2}]},
    "route": {"type": "spiral", "amplitude": 4.0, "waves": 3},
    "tileset": {"type": "cave"},
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="the world folder to write (must not exist)")
    args = ap.parse_args()
    world = subtgraph.generate(pipeline=PIPELINE)
    for level in world.levels:
        print(f"level {level['level']}: asked {level['requested']}, has {level['achieved']}")
    world.export(args.out)
    print(f"wrote {args.out}; its world.toml names type = \"spiral\": register it again to regenerate")


if __name__ == "__main__":
    main()
