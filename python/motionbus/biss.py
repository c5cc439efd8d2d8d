"""motionbus.biss: BiSS-C frames, register access and EDS (see the stub biss.pyi)."""

from __future__ import annotations

from . import _motionbus
from ._enums import BitOrder, ControlState, CrcOutput, EncoderType
from ._export import export

__all__ = export(_motionbus.biss, globals()) + ["BitOrder", "ControlState", "CrcOutput",
                                                "EncoderType"]
