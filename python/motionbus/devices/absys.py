"""motionbus.devices.absys (see the stub absys.pyi)."""

from __future__ import annotations

from .. import _motionbus
from .._enums import Command, PresetMode, SensorError
from .._export import export

__all__ = export(_motionbus.absys, globals()) + ["Command", "PresetMode", "SensorError"]
