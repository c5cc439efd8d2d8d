"""motionbus.modbus: Modbus PDU, RTU and TCP codecs, the RTU framer and a server (see the stub
modbus.pyi and docs/python.md). RegisterBank and Server are the pure-Python layer: a device
backed by lists, and a server that frames a byte stream and answers each request."""

from __future__ import annotations

from typing import List, Sequence

from . import _motionbus
from ._enums import ExceptionCode, FrameEnd, FramerRole, FunctionCode, Parity, ReportIdFormat
from ._errors import DecodeError, ModbusException
from ._export import export
from ._types import BytesLike

__all__ = export(_motionbus.modbus, globals()) + [
    "ExceptionCode", "FrameEnd", "FramerRole", "FunctionCode", "Parity", "ReportIdFormat",
    "ModbusException", "RegisterBank", "Server"]

_rtu_framer = _motionbus.modbus.RtuFramer
_serve_rtu = _motionbus.modbus.serve_rtu


def _span(table: Sequence[object], address: int, count: int) -> None:
    if address + count > len(table):
        raise ModbusException(ExceptionCode.illegal_data_address)


class RegisterBank:
    """A Modbus device over four Python lists (coils, discrete inputs, holding and input
    registers), for modbus.serve_rtu or Server. Out-of-range accesses answer exception 02."""

    def __init__(self, coils: int = 0, discrete_inputs: int = 0, holding_registers: int = 0,
                 input_registers: int = 0) -> None:
        self.coils: List[bool] = [False] * coils
        self.discrete_inputs: List[bool] = [False] * discrete_inputs
        self.holding_registers: List[int] = [0] * holding_registers
        self.input_registers: List[int] = [0] * input_registers

    def read_coils(self, address: int, count: int) -> List[bool]:
        _span(self.coils, address, count)
        return self.coils[address:address + count]

    def read_discrete_inputs(self, address: int, count: int) -> List[bool]:
        _span(self.discrete_inputs, address, count)
        return self.discrete_inputs[address:address + count]

    def read_holding_registers(self, address: int, count: int) -> List[int]:
        _span(self.holding_registers, address, count)
        return self.holding_registers[address:address + count]

    def read_input_registers(self, address: int, count: int) -> List[int]:
        _span(self.input_registers, address, count)
        return self.input_registers[address:address + count]

    def write_coils(self, address: int, values: Sequence[bool]) -> None:
        _span(self.coils, address, len(values))
        self.coils[address:address + len(values)] = list(values)

    def write_registers(self, address: int, values: Sequence[int]) -> None:
        _span(self.holding_registers, address, len(values))
        self.holding_registers[address:address + len(values)] = list(values)


class Server:
    """An RTU server at `address` over `device` (RegisterBank or any object serve_rtu takes):
    serve() answers one request ADU; feed() frames a byte stream (a serial port's reads) and
    returns the response ADUs to send, idle() the same at the t3.5 silence."""

    def __init__(self, device: object, address: int) -> None:
        self.device = device
        self.address = address
        self._framer = _rtu_framer(FramerRole.server, address=address)

    def serve(self, request: BytesLike) -> bytes:
        return _serve_rtu(self.device, self.address, request)

    def _answers(self, events: List[object]) -> List[bytes]:
        out = []
        for e in events:
            if isinstance(e, DecodeError):
                continue  # no response to a corrupted frame
            reply = _serve_rtu(self.device, self.address,
                               _motionbus.modbus.encode_rtu(e.slave, e.pdu))  # type: ignore[attr-defined]
            if reply:
                out.append(reply)
        return out

    def feed(self, data: BytesLike) -> List[bytes]:
        return self._answers(self._framer.feed(data))

    def idle(self) -> List[bytes]:
        return self._answers(self._framer.idle())
