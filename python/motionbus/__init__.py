"""motionbus: T-format, Modbus and BiSS-C codecs for Python, from the library's C++ headers.

Subpackages: motionbus.crc, motionbus.tformat, motionbus.modbus, motionbus.biss and the device
profiles motionbus.devices.ts5700n8500, .sm_unit, .absys. Bytes-like in, bytes out; failures
raise motionbus.DecodeError / EncodeError (motionbus.Error, ValueError) with their evidence.
"""

from __future__ import annotations

from . import _motionbus
from ._enums import *  # noqa: F401,F403  (Errc and the protocol enums)
from ._enums import __all__ as _enum_names
from ._errors import DecodeError, EncodeError, Error, IncompleteError, _install_repr

for _cls in _motionbus._result_classes:
    _install_repr(_cls)

__version__: str = _motionbus.__version__

from . import crc, tformat, modbus, biss, devices  # noqa: E402

__all__ = ["Error", "DecodeError", "IncompleteError", "EncodeError", "crc", "tformat",
           "modbus", "biss", "devices", *_enum_names]
