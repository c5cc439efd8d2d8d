"""The library's enumerations as Python IntEnums, built from the tables the extension module
exports (one statement of each value: the C++ headers)."""

from __future__ import annotations

import enum
from typing import Dict, List, Tuple

from . import _motionbus

_tables: Dict[str, List[Tuple[str, int]]] = _motionbus._enum_table()

Errc = enum.IntEnum("Errc", [(name, value) for name, value, _ in _motionbus._errc_table])  # type: ignore[misc]
Errc.__doc__ = "The library's error codes (motionbus/core/errc.hpp); .name is the C++ name."
Errc.__module__ = "motionbus"

__all__ = ["Errc"]
for _name, _members in _tables.items():
    _cls = enum.IntEnum(_name, _members)  # type: ignore[misc]
    _cls.__module__ = "motionbus"
    globals()[_name] = _cls
    __all__.append(_name)
