"""motionbus.devices.sm_unit (see the stub sm_unit.pyi)."""

from __future__ import annotations

from .. import _motionbus
from .._enums import Channel
from .._export import export

__all__ = export(_motionbus.sm_unit, globals()) + ["Channel"]
