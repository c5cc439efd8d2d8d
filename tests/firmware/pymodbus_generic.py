"""pymodbus (a third-party Modbus master) against the generic Modbus server image on its UART's
pty: reads and writes of each table, and the exceptions for bad addresses and quantities.

Usage: pymodbus_generic.py DEVICE (a pty, or tcp:PORT for a gateway in front of the image: then
an unserved function's exception 01 as well). Exit 0 when every check holds. Run with Debian's
python3.
"""
import os
import socket
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from pymodbus_peer import Checks, open_master  # noqa: E402  (tests/support/pymodbus_peer.py)


def main() -> int:
    client = open_master(sys.argv[1])
    check = Checks()

    r = client.write_registers(0, [100 + i for i in range(20)], slave=1)
    check("FC10 holding 0..19", not r.isError())
    r = client.read_holding_registers(0, 20, slave=1)
    check("FC03 reads them back", not r.isError() and r.registers == [100 + i for i in range(20)])
    r = client.read_input_registers(95, 5, slave=1)
    check("FC04 input registers 95..99", not r.isError() and r.registers == [1095 + i for i in
                                                                              range(5)])
    r = client.write_coils(50, [True, False, True], slave=1)
    check("FC0F coils 50..52", not r.isError())
    r = client.read_coils(50, 3, slave=1)
    check("FC01 reads them back", not r.isError() and r.bits[:3] == [True, False, True])
    r = client.read_discrete_inputs(3, 3, slave=1)
    check("FC02 inputs 3..5", not r.isError() and r.bits[:3] == [True, False, False])
    r = client.read_holding_registers(100, 1, slave=1)
    check("FC03 at address 100: exception 02",
          r.isError() and getattr(r, "exception_code", 0) == 2)
    r = client.read_coils(0, 2001, slave=1)
    check("FC01 of 2001 coils: exception 03",
          r.isError() and getattr(r, "exception_code", 0) == 3)
    r = client.read_holding_registers(0, 1, slave=9)
    check("another slave stays silent", r.isError())
    client.close()
    if sys.argv[1].startswith("tcp:"):
        # through the gateway: a function the image does not serve reaches it (the image ends
        # the request at the line's silence) and its exception 01 comes back
        with socket.create_connection(("127.0.0.1", int(sys.argv[1][4:])), timeout=5) as s:
            s.sendall(struct.pack(">HHHB", 0x4101, 0, 3, 1) + b"\x41\x00")
            answer = b""
            while len(answer) < 9:
                got = s.recv(64)
                if not got:
                    break
                answer += got
        check("function 0x41 (not served): exception 01 from the image",
              answer == struct.pack(">HHHB", 0x4101, 0, 3, 1) + b"\xc1\x01")
    return 1 if check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
