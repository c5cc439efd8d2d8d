from typing import Any

from . import DecodeError as DecodeError, EncodeError as EncodeError, Error as Error
from . import IncompleteError as IncompleteError

class ModbusException(Exception):
    exception_code: int
    def __init__(self, exception_code: int, message: str = ...) -> None: ...

def _install_repr(cls: Any) -> None: ...
