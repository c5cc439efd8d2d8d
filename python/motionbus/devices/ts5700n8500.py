"""motionbus.devices.ts5700n8500 (see the stub ts5700n8500.pyi)."""

from __future__ import annotations

from .. import _motionbus
from .._enums import LatchRule
from .._export import export

__all__ = export(_motionbus.ts5700n8500, globals()) + ["LatchRule"]
