"""The package's one failure convention: every decoder raises DecodeError (IncompleteError
when the input ends too early), every encoder raises EncodeError, both subclasses of
motionbus.Error and of ValueError, carrying the library's error code and its evidence.
Stream objects (tformat.Receiver, modbus.RtuFramer) do not raise for a rejected frame: they
return the same DecodeError objects among their events and go on."""

from __future__ import annotations

from typing import Any, Tuple

from . import _motionbus
from ._enums import Errc

__all__ = ["Error", "DecodeError", "IncompleteError", "EncodeError"]


class Error(Exception):
    """Base of the package's errors: `code` (Errc) and `name` (the tools' snake_case name)."""

    code: Errc
    name: str
    context: str

    def __init__(self, code: int, context: str = "", detail: str = "") -> None:
        self.code = Errc(code)
        self.name = _motionbus._errc_name(int(code))
        self.context = context
        self.detail = detail
        super().__init__(self._message())

    def _message(self) -> str:
        head = f"{self.context}: {self.name}" if self.context else self.name
        return f"{head} ({self.detail})" if self.detail else head


class DecodeError(Error, ValueError):
    """A decoder rejected its input. `expected`/`received`: the evidence (e.g. the CRC the data
    calls for and the CRC sent; the request's and the response's field), 0 where the error
    has none. `offset`: input units (`unit`, "bytes" or "bits") the caller may drop before
    trying again (for a stream: units of the chunk taken)."""

    expected: int
    received: int
    offset: int
    needed: int
    unit: str

    def __init__(self, code: int, context: str = "", offset: int = 0, expected: int = 0,
                 received: int = 0, needed: int = 0, unit: str = "bytes") -> None:
        self.offset = offset
        self.expected = expected
        self.received = received
        self.needed = needed
        self.unit = unit
        parts = []
        if expected or received:
            parts.append(f"expected 0x{expected:X}, received 0x{received:X}")
        if needed:
            parts.append(f"{needed} more {unit} needed")
        elif offset:
            parts.append(f"offset {offset} {unit}")
        super().__init__(code, context, ", ".join(parts))

    def __repr__(self) -> str:
        return (f"{type(self).__name__}({self.code.name}, expected=0x{self.expected:X}, "
                f"received=0x{self.received:X}, offset={self.offset}, needed={self.needed})")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, DecodeError):
            return NotImplemented
        return (type(self), self.code, self.expected, self.received, self.offset,
                self.needed) == (type(other), other.code, other.expected, other.received,
                                 other.offset, other.needed)

    __hash__ = Exception.__hash__


class IncompleteError(DecodeError):
    """The input ends before the frame does: `needed` more units at least (code: truncated)."""


class EncodeError(Error, ValueError):
    """An encoder refused its arguments (out of range, wrong layout, too many values...)."""


def _install_repr(cls: Any) -> None:
    """Gives a bound result class a readable repr and field-wise equality (its `_fields`)."""
    fields: Tuple[str, ...] = cls._fields

    def __repr__(self: Any) -> str:
        body = ", ".join(f"{f}={_show(getattr(self, f))}" for f in fields)
        return f"{cls.__name__}({body})"

    def __eq__(self: Any, other: Any) -> Any:
        if type(other) is not type(self):
            return NotImplemented
        return all(getattr(self, f) == getattr(other, f) for f in fields)

    cls.__repr__ = __repr__
    cls.__eq__ = __eq__
    cls.__hash__ = None


def _show(v: Any) -> str:
    if isinstance(v, bool) or v is None:
        return repr(v)
    if hasattr(v, "name") and hasattr(v, "value") and isinstance(v, int):
        return f"{type(v).__name__}.{v.name}"
    if isinstance(v, bytes):
        return v.hex(" ") and f"bytes.fromhex('{v.hex(' ')}')" or "b''"
    return repr(v)




class ModbusException(Exception):
    """Raised by a modbus server device's method to answer with a Modbus exception code
    (ExceptionCode: 2 illegal address, 3 illegal value, 4 device failure...)."""

    def __init__(self, exception_code: int, message: str = "") -> None:
        self.exception_code = int(exception_code)
        super().__init__(message or f"Modbus exception {self.exception_code:#04x}")
