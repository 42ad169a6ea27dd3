"""subtgraph: procedural subterranean worlds (mines, caves, lava tubes) with controlled
topology, for robot simulation, from Python.

    import subtgraph
    world = subtgraph.generate(preset="cave", seed=7)
    world.occupancy                  # numpy uint8 [levels, rows, cols], a view, no copy
    world.to_networkx()              # the topology graph
    v, f = world.mesh.visual         # numpy float32 [n, 3], uint32 [m, 3]
    world.export("worlds/cave-7", formats=["mjcf", "usd", "ground-truth"])
    model = mujoco.MjModel.from_xml_string(world.mjcf())

Generation is the command line's own (the same pipeline files, presets, plugins, seeds and
bytes): a world made here is the one ``subtgraph generate`` makes. Errors are
:class:`subtgraph.Error` subclasses with the command line's message.
"""

from __future__ import annotations

import io
import json
import os
from typing import Any, Callable, Iterable, Mapping, TypeVar

from . import _native
from .errors import (
    CallbackError,
    ComponentError,
    ConfigError,
    Error,
    FolderError,
    GenerationError,
    OccupancyError,
    PluginError,
    TooLargeError,
)

__version__ = _native.VERSION

__all__ = [
    "CallbackError",
    "ComponentError",
    "ConfigError",
    "Error",
    "FolderError",
    "GenerationError",
    "Mesh",
    "OccupancyError",
    "PluginError",
    "Segment",
    "TooLargeError",
    "World",
    "components",
    "constraint_shape",
    "dataset",
    "generate",
    "load_plugin",
    "preset_text",
    "presets",
    "route_descriptor",
    "stats",
    "unregister",
]

Segment = _native.Segment

#: Tile kinds by the original's spatial code, as ``World.occupancy`` holds them.
KINDS = {
    0: "empty",
    1: "dead-end",
    2: "straight",
    3: "corner",
    4: "t-junction",
    5: "intersection",
    11: "shaft-up",
    111: "shaft-landing",
}


def generate(
    preset: str | None = None,
    pipeline: str | os.PathLike[str] | Mapping[str, Any] | None = None,
    seed: int | None = None,
    formats: Iterable[str] | None = None,
    mesh: bool = True,
    tileset: str | None = None,
    plugins: Iterable[str | os.PathLike[str]] | None = None,
    max_memory: str | None = None,
) -> World:
    """Generates a world, in memory.

    preset: ``"cave"`` (the default), ``"mine"`` or ``"lava-tube"`` (see :func:`presets`).
    pipeline: instead of a preset, a pipeline file's path, its TOML text (any string with a
        newline or ``=``), or a dict of the same tables (``{"world": {"seed": 3}, ...}``).
    seed: replaces the pipeline's ``world.seed`` (0 to 2**63 - 1). The same pipeline and seed
        give the same world, byte for byte, on every machine and thread count.
    formats: exporters to add, as the command line's ``--format`` (``["mjcf", "usd",
        "ground-truth"]``); :meth:`World.export` writes them.
    mesh: ``False`` makes the layout only (grids and graph, no tile set): milliseconds.
    tileset: replaces the pipeline's ``[tileset]``.
    plugins: plugin libraries to load for this run (see also :func:`load_plugin`).
    max_memory: the memory budget (``"2G"``; default three quarters of physical memory).

    Raises :class:`ConfigError` for a bad pipeline, :class:`GenerationError` when the topology
    cannot be made, :class:`TooLargeError` over the budget, :class:`CallbackError` when a
    Python route descriptor or shape fails.
    """
    if isinstance(formats, str):
        formats = [formats]
    native = _native.generate(
        preset=preset,
        pipeline=os.fspath(pipeline) if isinstance(pipeline, os.PathLike) else pipeline,
        seed=seed,
        formats=None if formats is None else list(formats),
        mesh=mesh,
        tileset=tileset,
        plugins=None if plugins is None else [os.fspath(p) for p in plugins],
        max_memory=max_memory,
    )
    return World(native)


class Mesh:
    """A world's meshes: metres, x east, y north, z up; arrays are read-only views."""

    __slots__ = ("_w",)

    def __init__(self, native: Any) -> None:
        self._w = native

    @property
    def visual(self) -> tuple[Any, Any]:
        """``(vertices float32 [n, 3], triangles uint32 [m, 3])``: what is rendered."""
        return self._w.mesh("visual")

    @property
    def collision(self) -> tuple[Any, Any]:
        """``(vertices float32 [n, 3], triangles uint32 [m, 3])``: what physics collides with."""
        return self._w.mesh("collision")

    @property
    def normals(self) -> Any:
        """Per-vertex unit normals of the visual mesh, ``float32 [n, 3]``, into the passage."""
        return self._w.mesh_normals("visual")

    @property
    def materials(self) -> Any:
        """Per-triangle material index of the visual mesh, ``uint8 [m]``, into
        :attr:`material_names`."""
        return self._w.mesh_materials("visual")

    @property
    def material_names(self) -> list[str]:
        """The tile set's material names."""
        return self._w.material_names()

    def __repr__(self) -> str:
        v, f = self.visual
        c, g = self.collision
        return f"Mesh(visual={len(v)} vertices / {len(f)} triangles, collision={len(c)} / {len(g)})"


class World:
    """A generated world. Arrays are numpy views of the world's own memory (read-only)."""

    __slots__ = ("_w", "_graph")

    def __init__(self, native: Any) -> None:
        self._w = native
        self._graph: dict[str, Any] | None = None

    @property
    def occupancy(self) -> Any:
        """``uint8 [levels, rows, cols]``: the original's spatial codes (see :data:`KINDS`),
        as ``occupancy.npy`` holds them."""
        return self._w.occupancy

    @property
    def tiles(self) -> Any:
        """``uint8 [levels, rows, cols, 3]``: per cell its spatial code, its openings (bit 0
        east, 1 north, 2 west, 3 south) and its quarter turns counter-clockwise."""
        return self._w.tiles

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(levels, rows, cols)``."""
        return self._w.shape

    @property
    def seed(self) -> int:
        """The world's seed."""
        return self._w.seed

    @property
    def tile_pitch(self) -> float:
        """Metres between tile centres."""
        return self._w.tile_pitch

    @property
    def level_height(self) -> float:
        """Metres between levels."""
        return self._w.level_height

    @property
    def start(self) -> tuple[int, int, int] | None:
        """Where a robot starts: ``(level, row, col)``, a dead end of level 0."""
        return self._w.start

    @property
    def shafts(self) -> list[tuple[tuple[int, int, int], tuple[int, int, int]]]:
        """Shafts as ``(foot, landing)`` cells ``(level, row, col)``."""
        return self._w.shafts

    def cell_position(self, level: int, row: int, col: int) -> tuple[float, float, float]:
        """The world-frame position in metres of a cell's centre on its floor."""
        return self._w.cell_position(level, row, col)

    def raycast(self, origins: Any, directions: Any, max_range: float = float("inf")) -> Any:
        """Distances in metres from each origin (``float64 [n, 3]``, world frame) along each
        direction (``[n, 3]``, normalised here) to the first triangle of the visual surface (the
        visual mesh, and in a mine its services): ``float64 [n]``, ``inf`` where nothing is within ``max_range``. Uses the same ray
        caster as ``subtgraph sense``, built once per world, in parallel without the GIL.
        """
        import numpy as np

        o = np.ascontiguousarray(origins, dtype=np.float64).reshape(-1, 3)
        d = np.ascontiguousarray(directions, dtype=np.float64).reshape(-1, 3)
        return self._w.raycast(o, d, float(max_range))

    def lidar_scan(self, pose: Any, model: str = "os1-32", noise: bool = False,
                   seed: int = 0) -> Any:
        """One scan of a LiDAR model standing still at ``pose`` (a 4 x 4 world-from-sensor
        matrix): its returns as ``float64 [n, 3]`` in the sensor's frame (x forward, z up).
        ``model`` is ``os1-32``, ``os1-64``, ``os1-128``, ``vlp-16``, ``mid-360`` or a LiDAR
        table's path, as ``subtgraph sense --lidar`` takes; range noise only with ``noise``
        (drawn from ``seed``)."""
        import numpy as np

        p = np.ascontiguousarray(pose, dtype=np.float64)
        return self._w.lidar_scan(p, model, bool(noise), int(seed))

    def render(self, pose: Any, camera: str = "stereo", index: int = 0, noise: bool = False,
               seed: int = 0, lamp_lumens: float | None = None, ambient: float = 0.0,
               platform: str = "ground") -> dict[str, Any]:
        """One lamp-lit frame of a camera model (``mono``, ``stereo``, ``fisheye-stereo``,
        ``d435i`` or a camera table's path, as ``subtgraph sense --camera`` takes) whose
        camera ``index`` has its optical frame at ``pose`` (a 4 x 4 world-from-camera matrix,
        OpenCV's axes: x right, y down, z forward): ``{"rgb", "depth", "labels",
        "instances"}`` as numpy arrays (``uint8 [h, w, 3]`` or ``[h, w]`` for a monochrome
        camera, ``float32`` metres along the optical axis, ``uint16`` class ids, ``uint32``
        instance ids). Lit by the ``platform``'s lamps beside the lens (``lamp_lumens`` each
        instead, 0 for none) and ``ambient`` lux; shot and read noise only with ``noise``.
        ``legend()`` says what the ids are."""
        import numpy as np

        p = np.ascontiguousarray(pose, dtype=np.float64)
        lumens = None if lamp_lumens is None else float(lamp_lumens)
        return self._w.render(p, camera, int(index), bool(noise), int(seed), lumens,
                              float(ambient), platform)

    def legend(self) -> dict[str, Any]:
        """What ``render``'s ids are: ``{"legend": [...], "instances": {...}}``, each class
        with its ``id``, ``surface`` (rock, service, artifact), tile kind, features, part or
        artifact class, and material, as a sequence's ``sequence.json`` gives them."""
        import json

        return json.loads(self._w.legend())

    @property
    def graph(self) -> dict[str, Any]:
        """The topology graph as ``topology.json`` writes it: ``{"nodes": [...], "edges":
        [...]}``; a node has ``id``, ``kind``, ``cell`` and ``position`` (metres), an edge
        ``id``, ``kind`` (corridor or shaft), ``from``, ``to``, ``cells``, ``length_cells`` and
        ``length_m``."""
        if self._graph is None:
            self._graph = json.loads(self._w.graph_json())
        return self._graph

    @property
    def levels(self) -> list[dict[str, Any]]:
        """Per level what was requested and what the final grid has (junctions, loops, ...)."""
        return json.loads(self._w.levels_json())

    def to_networkx(self) -> Any:
        """The graph as a ``networkx.MultiGraph`` (two corridors may join the same nodes):
        node attributes ``kind``, ``cell``, ``pos`` (metres); edge attributes ``id``,
        ``kind``, ``length`` (metres), ``length_cells``, ``cells``."""
        import networkx as nx

        g = nx.MultiGraph()
        for n in self.graph["nodes"]:
            c = n["cell"]
            g.add_node(
                n["id"],
                kind=n["kind"],
                cell=(c["level"], c["row"], c["col"]),
                pos=tuple(n["position"]),
            )
        for e in self.graph["edges"]:
            g.add_edge(
                e["from"],
                e["to"],
                key=e["id"],
                id=e["id"],
                kind=e["kind"],
                length=e["length_m"],
                length_cells=e["length_cells"],
                cells=[(c["level"], c["row"], c["col"]) for c in e["cells"]],
            )
        return g

    @property
    def mesh(self) -> Mesh | None:
        """The meshes, or ``None`` for a world made with ``mesh=False``."""
        return Mesh(self._w) if self._w.has_mesh else None

    @property
    def pipeline(self) -> str:
        """The resolved pipeline, as ``world.toml`` holds it: ``generate(pipeline=...)`` of
        it makes this world again."""
        return self._w.world_toml()

    def files(self, formats: Iterable[str] | None = None) -> dict[str, bytes]:
        """The files the exporters for ``formats`` write (the world's own when ``None``), in
        memory: ``{path: bytes}``, paths relative to the world folder."""
        if isinstance(formats, str):
            formats = [formats]
        return self._w.files(None if formats is None else list(formats))

    def export(
        self,
        folder: str | os.PathLike[str],
        formats: Iterable[str] | None = None,
        force: bool = False,
    ) -> None:
        """Writes the world folder, as ``subtgraph generate --out`` does: into a hidden
        temporary folder moved into place at the end, so it is complete or absent. An
        existing ``folder`` is an error unless ``force``, which replaces only a world folder
        subtgraph wrote (never one holding files of yours). ``formats`` replaces the
        exporters given to :func:`generate`; ``world.toml`` records what was written."""
        if isinstance(formats, str):
            formats = [formats]
        self._w.export(os.fspath(folder), None if formats is None else list(formats), force)

    def mjcf(self, visual: bool = False) -> str:
        """The MuJoCo model as one XML string, for ``mujoco.MjModel.from_xml_string``: the
        collision height fields inline, so it needs no files. With ``visual``, the visual
        meshes are referenced as files: use :meth:`mjcf_with_assets` to get them."""
        xml, assets = self._w.mjcf(visual)
        return xml

    def mjcf_with_assets(self) -> tuple[str, dict[str, bytes]]:
        """``(xml, assets)`` with the visual meshes:
        ``mujoco.MjModel.from_xml_string(xml, assets)``."""
        return self._w.mjcf(True)

    def _main(self, fmt: str, path: str) -> str:
        return self.files([fmt])[path].decode()

    def sdf(self) -> str:
        """The Gazebo SDFormat world (``gazebo/world.sdf``); its meshes are in
        ``files(["sdf"])``."""
        return self._main("sdf", "gazebo/world.sdf")

    def urdf(self) -> str:
        """The URDF (``urdf/world.urdf``); its meshes are in ``files(["urdf"])``."""
        return self._main("urdf", "urdf/world.urdf")

    def usd(self) -> str:
        """The USD root layer (``usd/world.usda``); its part layers are in
        ``files(["usd"])``."""
        return self._main("usd", "usd/world.usda")

    def ground_truth(self, formats: Iterable[str] = ("ground-truth",)) -> dict[str, Any]:
        """The ground truth, decoded: ``{path: value}`` with JSON files parsed, ``.npy``
        files and the ROS maps (``.pgm``, row 0 north) as numpy arrays, and other files
        (YAML, CSV, GraphML) as bytes. ``formats`` picks the parts (``"graph"``,
        ``"ros-map"``, ``"free-space"``, ``"semantic-labels"``, ``"spawn-poses"``)."""
        import numpy as np

        out: dict[str, Any] = {}
        for path, data in self.files(list(formats)).items():
            if path.endswith(".json"):
                out[path] = json.loads(data)
            elif path.endswith(".npy"):
                out[path] = np.load(io.BytesIO(data))
            elif path.endswith(".pgm"):
                out[path] = _pgm(data)
            else:
                out[path] = data
        return out

    def __repr__(self) -> str:
        return repr(self._w)


def _pgm(data: bytes) -> Any:
    """A binary (P5) PGM as a numpy uint8 array [height, width]."""
    import numpy as np

    fields: list[bytes] = []
    pos = 0
    while len(fields) < 4:
        while data[pos : pos + 1].isspace():
            pos += 1
        if data[pos : pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end : end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    if fields[0] != b"P5" or fields[3] != b"255":
        raise ValueError("not an 8-bit binary PGM")
    width, height = int(fields[1]), int(fields[2])
    pixels = np.frombuffer(data, dtype=np.uint8, count=width * height, offset=pos + 1)
    return pixels.reshape(height, width)


def presets() -> dict[str, str]:
    """The presets: ``{name: summary}``."""
    return dict(_native.presets())


def preset_text(name: str) -> str:
    """A preset's pipeline text (TOML): a starting point for ``generate(pipeline=...)``."""
    return _native.preset_text(name)


def components() -> list[dict[str, str]]:
    """Every component a pipeline can name (built-ins, loaded plugins, Python ones), as
    ``subtgraph list`` shows them: ``{"kind", "name", "origin", "summary"}``."""
    return [
        {"kind": k, "name": n, "origin": o, "summary": s} for k, n, o, s in _native.components()
    ]


def load_plugin(path: str | os.PathLike[str]) -> list[str]:
    """Loads a plugin library (a ``cdylib`` built with ``subtgraph-plugins`` by the same
    compiler) for every later run; returns the component names it adds."""
    return _native.load_plugin(os.fspath(path))


F = TypeVar("F", bound=Callable[..., Any])


def route_descriptor(name: str) -> Callable[[F], F]:
    """Registers a route descriptor written in Python under ``name`` (``[route] type = NAME``).

    Decorate a function ``offset(t, segment) -> float``, the sideways offset in cells at
    ``t`` in [0, 1] (0 at both ends), ``segment`` a :class:`Segment` (``start``, ``end``,
    ``rows``, ``cols``, ``side``, ``length()``, ``point(t, offset)``); or a class whose
    ``__init__`` takes the ``[route]`` table's keys and whose method ``offset(self, t,
    segment)`` does the same. It must be a pure function of its arguments: it is called from
    the generator's threads, each call taking the GIL alone, and the same seed must give the
    same world. An exception, a value that is not a finite number, or an offset that would
    take the route outside its level raises :class:`CallbackError` naming it.
    """

    def register(obj: F) -> F:
        _native.register("route descriptor", name, obj)
        return obj

    return register


def constraint_shape(name: str) -> Callable[[F], F]:
    """Registers a constraint shape written in Python under ``name``.

    A pipeline asks for it by name in a ``[[topology.structure]]`` table, with its count and
    its own keys (``topology.structure = [{ type = "NAME", count = 2 }]``), or fixes its
    count on each level in ``[topology] per_level`` (``topology.per_level = [{ NAME = 2 }]``,
    one table per level). ``[topology]`` takes no other names: its keys are the built-in
    counts, so a misspelt one is an error rather than a request for a shape of that name.

    Decorate a class whose ``__init__`` takes the structure's keys (other than ``count``),
    or a function of no arguments, whose result has (as attributes, methods or dict keys)
    ``footprint``: ``[(d_row, d_col), ...]`` 4-connected cells around the centre; ``arms``:
    ``[((d_row, d_col), heading), ...]`` with a heading ``"north"``, ``"east"``, ``"south"``,
    ``"west"`` or a perpendicular pair like ``("south", "east")``; and optionally
    ``rotations`` (1, 2 or 4; default 4) and ``clearance`` (cells; default 2). It is read
    once per run; a bad answer raises :class:`ConfigError` naming it.
    """

    def register(obj: F) -> F:
        _native.register("constraint shape", name, obj)
        return obj

    return register


def unregister(name: str) -> bool:
    """Removes a Python route descriptor or shape; returns whether one had that name."""
    return _native.unregister(name)


def dataset(
    out: str | os.PathLike[str],
    presets: Iterable[str] | None = None,
    pipelines: Iterable[str | os.PathLike[str]] | None = None,
    count: int = 1,
    seed: int = 0,
    jobs: int | None = None,
    formats: Iterable[str] | None = None,
    mesh: bool = True,
    tileset: str | None = None,
    plugins: Iterable[str | os.PathLike[str]] | None = None,
    max_memory: str | None = None,
) -> dict[str, int]:
    """Makes a dataset folder as ``subtgraph dataset`` does (resumable: complete worlds are
    kept; ``index.json`` lists them); returns ``{"made", "skipped", "indexed"}``."""
    return _native.dataset(
        os.fspath(out),
        presets=None if presets is None else list(presets),
        pipelines=None if pipelines is None else [os.fspath(p) for p in pipelines],
        count=count,
        seed=seed,
        jobs=jobs,
        formats=None if formats is None else list(formats),
        mesh=mesh,
        tileset=tileset,
        plugins=None if plugins is None else [os.fspath(p) for p in plugins],
        max_memory=max_memory,
    )


def stats(
    inputs: Iterable[str | os.PathLike[str]],
    out: str | os.PathLike[str],
    crop: str = "common",
) -> str:
    """Writes the paper's variability statistics of world or dataset folders to the report
    folder ``out``, as ``subtgraph stats`` does; returns the summary text."""
    return _native.stats([os.fspath(p) for p in inputs], os.fspath(out), crop)


def _register_gymnasium_env() -> None:
    """Registers ``subtgraph/Explore-v0`` with Gymnasium when it is installed (the closed
    loop, :mod:`subtgraph.explore`); without it, ``subtgraph`` works as before."""
    try:
        import gymnasium  # noqa: F401
    except ImportError:
        return
    from .explore import register

    register()


_register_gymnasium_env()
