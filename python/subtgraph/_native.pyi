"""Type hints of the compiled half of subtgraph (`python/src`, PyO3). Use the package's own
API (`subtgraph.generate`, `subtgraph.World`), which wraps this module."""

from typing import Any

import numpy as np
import numpy.typing as npt

VERSION: str

Cell = tuple[int, int, int]

class Segment:
    """The straight segment a route descriptor bends, in cells."""

    start: tuple[float, float]
    end: tuple[float, float]
    rows: int
    cols: int
    side: float
    def length(self) -> float: ...
    def point(self, t: float, offset: float) -> tuple[float, float]: ...

class World:
    occupancy: npt.NDArray[np.uint8]
    tiles: npt.NDArray[np.uint8]
    shape: tuple[int, int, int]
    seed: int
    tile_pitch: float
    level_height: float
    start: Cell | None
    shafts: list[tuple[Cell, Cell]]
    has_mesh: bool
    def cell_position(self, level: int, row: int, col: int) -> tuple[float, float, float]: ...
    def graph_json(self) -> str: ...
    def levels_json(self) -> str: ...
    def world_toml(self) -> str: ...
    def mesh(self, which: str) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.uint32]]: ...
    def mesh_normals(self, which: str) -> npt.NDArray[np.float32]: ...
    def mesh_materials(self, which: str) -> npt.NDArray[np.uint8]: ...
    def material_names(self) -> list[str]: ...
    def raycast(
        self, origins: npt.NDArray[np.float64], directions: npt.NDArray[np.float64], max_range: float = ...
    ) -> npt.NDArray[np.float64]: ...
    def lidar_scan(
        self, pose: npt.NDArray[np.float64], model: str = "os1-32", noise: bool = False, seed: int = 0
    ) -> npt.NDArray[np.float64]: ...
    def render(
        self,
        pose: npt.NDArray[np.float64],
        camera: str = "stereo",
        index: int = 0,
        noise: bool = False,
        seed: int = 0,
        lamp_lumens: float | None = None,
        ambient: float = 0.0,
        platform: str = "ground",
    ) -> dict[str, npt.NDArray[Any]]: ...
    def legend(self) -> str: ...
    def files(self, formats: list[str] | None = None) -> dict[str, bytes]: ...
    def mjcf(self, visual: bool = False) -> tuple[str, dict[str, bytes]]: ...
    def export(self, folder: str, formats: list[str] | None = None, force: bool = False) -> None: ...

def generate(
    preset: str | None = None,
    pipeline: str | dict[str, Any] | None = None,
    seed: int | None = None,
    formats: list[str] | None = None,
    mesh: bool = True,
    tileset: str | None = None,
    plugins: list[str] | None = None,
    max_memory: str | None = None,
) -> World: ...
def presets() -> list[tuple[str, str]]: ...
def preset_text(name: str) -> str: ...
def components() -> list[tuple[str, str, str, str]]: ...
def load_plugin(path: str) -> list[str]: ...
def register(kind: str, name: str, object: Any) -> None: ...
def unregister(name: str) -> bool: ...
def dataset(
    out: str,
    presets: list[str] | None = None,
    pipelines: list[str] | None = None,
    count: int = 1,
    seed: int = 0,
    jobs: int | None = None,
    formats: list[str] | None = None,
    mesh: bool = True,
    tileset: str | None = None,
    plugins: list[str] | None = None,
    max_memory: str | None = None,
) -> dict[str, int]: ...
def stats(inputs: list[str], out: str, crop: str = "common") -> str: ...
