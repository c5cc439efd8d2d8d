"""pymodbus's ASCII client (ModbusAsciiFramer) against `motionbus serve modbus --ascii
--units 1-4` on a pty (tests/interop/run_ascii_interop.sh), then raw ASCII frames: a bad LRC
and a character that is no hex digit get no answer, and the next good frame is answered.

Usage: pymodbus_ascii_client.py DEVICE. Exit 0 when every check holds. Debian's python3.
"""
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from pymodbus_peer import Checks  # noqa: E402
from pymodbus.client import ModbusSerialClient  # noqa: E402
from pymodbus.transaction import ModbusAsciiFramer  # noqa: E402
import serial  # noqa: E402


def ascii_frame(body, lrc=None):
    """':' body LRC CR LF for the bytes `body` (address, PDU)."""
    if lrc is None:
        lrc = (-sum(body)) & 0xFF
    return b":" + (bytes(body) + bytes([lrc])).hex().upper().encode() + b"\r\n"


def main():
    check = Checks()
    client = ModbusSerialClient(port=sys.argv[1], framer=ModbusAsciiFramer, baudrate=9600,
                                parity="N", stopbits=1, bytesize=8, timeout=1, strict=False)
    check("pymodbus opens the port", client.connect())
    for u in range(1, 5):
        r = client.read_input_registers(3, 1, slave=u)
        check("ASCII: unit %d answers as its own device (%d)" % (u, 1000 * u + 3),
              not r.isError() and r.registers == [1000 * u + 3])
    check("ASCII: FC06", not client.write_register(4, 77, slave=2).isError())
    r = client.read_holding_registers(4, 1, slave=2)
    check("ASCII: FC03 reads it back", not r.isError() and r.registers == [77])
    check("ASCII: FC0F", not client.write_coils(0, [True, True], slave=1).isError())
    r = client.read_coils(0, 2, slave=1)
    check("ASCII: FC01", not r.isError() and r.bits[:2] == [True, True])
    r = client.read_holding_registers(99, 2, slave=1)
    check("ASCII: past the points: exception 02", r.isError() and r.exception_code == 2)
    client.close()
    port = serial.Serial(sys.argv[1], 9600, timeout=0.5)
    good = ascii_frame([1, 3, 0, 4, 0, 1])
    port.write(ascii_frame([1, 3, 0, 4, 0, 1], lrc=0x00))
    check("a bad LRC: no answer", port.read(64) == b"")
    port.write(b":0103000X0001F7\r\n")
    check("a character that is no hex digit: no answer", port.read(64) == b"")
    port.write(good)
    time.sleep(0.3)
    check("the next good frame is answered",
          port.read(64) == ascii_frame([1, 3, 2, 0, 0]))
    port.close()
    return 1 if check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
