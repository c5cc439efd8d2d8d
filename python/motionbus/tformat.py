"""motionbus.tformat: the T-format codec and receiver (see the stub tformat.pyi)."""

from __future__ import annotations

from . import _motionbus
from ._enums import AlmcBit, DataId, Echo
from ._export import export

__all__ = export(_motionbus.tformat, globals()) + ["AlmcBit", "DataId", "Echo"]
