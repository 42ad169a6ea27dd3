"""The exceptions subtgraph raises.

Every error is a :class:`Error` carrying the message the command line prints for the same
mistake, and, where the command line points into a pipeline file, the same ``file``, ``line``,
``column`` and ``key``.
"""

from __future__ import annotations


class Error(Exception):
    """Something subtgraph cannot do as asked; the message says what to change."""

    def __init__(
        self,
        message: str,
        file: str | None = None,
        line: int | None = None,
        column: int | None = None,
        key: str | None = None,
    ) -> None:
        super().__init__(message)
        self.message = message
        self.file = file
        self.line = line
        self.column = column
        self.key = key


class ConfigError(Error, ValueError):
    """A pipeline (file, TOML text, dict or argument) that cannot be used as written: an
    unknown key or name, a value out of range, a wrong type. ``file``, ``line``, ``column``
    and ``key`` say where (``<dict>`` and ``<string>`` for pipelines given from Python)."""


class GenerationError(Error):
    """A requested structure did not fit or its routes could not be laid: use a larger grid,
    fewer structures, or ``exact = false``."""


class TooLargeError(Error, MemoryError):
    """The world would need more memory than ``max_memory`` allows; the message gives the
    estimate and the knob to change."""


class OccupancyError(Error, ValueError):
    """An imported occupancy grid has a shape, type or value subtgraph cannot read."""


class ComponentError(Error):
    """A route descriptor, shape, tile set or exporter failed."""


class PluginError(Error):
    """A plugin library was refused (missing, not a plugin, built for another API)."""


class FolderError(Error):
    """A world folder could not be written (it exists, it holds files subtgraph did not
    write, the disk is full); nothing was left half-written."""


class CallbackError(Error):
    """A route descriptor or constraint shape written in Python failed: it raised (the
    exception is the ``__cause__``), returned something other than a finite number, or
    returned offsets that would take a route outside its level. The message names it."""
