"""motionbus.crc (see the stub crc.pyi and docs/python.md)."""

from __future__ import annotations

from . import _motionbus
from ._export import export

__all__ = export(_motionbus.crc, globals())
