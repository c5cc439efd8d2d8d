"""pymodbus against the multi-address server image (examples/firmware/modbus_units.cpp): units
1-4 answer as four devices (their own registers, sizes, functions and identity), unit 5 does
not answer.

Usage: pymodbus_units.py DEVICE   (a pty, or tcp:PORT for a gateway in front of the image).
Exit 0 when every check holds. Run with Debian's python3 (python3-pymodbus).
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from pymodbus_peer import Checks, open_master  # noqa: E402  (tests/support/pymodbus_peer.py)
from pymodbus.other_message import ReportSlaveIdRequest  # noqa: E402


def exception_code(r):
    return getattr(r, "exception_code", 0) if r.isError() else 0


def main() -> int:
    through_gateway = sys.argv[1].startswith("tcp:")
    client = open_master(sys.argv[1])
    check = Checks()
    for u in range(1, 5):
        r = client.read_input_registers(0, 8, slave=u)
        check(f"unit {u}: FC04 inputs 0..7 read {1000 * u}..",
              not r.isError() and r.registers == [1000 * u + i for i in range(8)])
        values = [100 * u + i for i in range(8 * u)]
        r = client.write_registers(0, values, slave=u)
        check(f"unit {u}: FC10 its {8 * u} holding registers", not r.isError())
        r = client.read_holding_registers(8 * u, 1, slave=u)
        check(f"unit {u}: FC03 at address {8 * u}, past its registers: exception 02",
              exception_code(r) == 2)
        r = client.execute(ReportSlaveIdRequest(unit=u))  # pymodbus 3.0: unit=, not slave=
        check(f"unit {u}: FC11 server id {u}, run indicator on, \"unit {u}\"",
              not r.isError() and bytes(r.identifier) == bytes([u, 0xFF]) + f"unit {u}".encode())
        r = client.read_coils(0, 4, slave=u)
        if u < 3:
            check(f"unit {u}: no coils: FC01 exception 01", exception_code(r) == 1)
        else:
            check(f"unit {u}: FC01 coils 0..3", not r.isError() and len(r.bits) >= 4)
    for u in range(1, 5):
        r = client.read_holding_registers(0, 8 * u, slave=u)
        check(f"unit {u}: FC03 reads its own writes, not another unit's",
              not r.isError() and r.registers == [100 * u + i for i in range(8 * u)])
    r = client.write_coils(0, [True, True, False, False], slave=4)
    check("unit 4: FC0F coils 0..3", not r.isError())
    r = client.write_coils(0, [False, True, False, True], slave=3)
    check("unit 3: FC0F coils 0..3", not r.isError())
    r = client.read_coils(0, 4, slave=3)
    check("unit 3: FC01 reads them back", not r.isError() and r.bits[:4] == [False, True, False,
                                                                            True])
    r = client.read_coils(0, 4, slave=4)
    check("unit 4: its own coils, not unit 3's",
          not r.isError() and r.bits[:4] == [True, True, False, False])
    r = client.read_holding_registers(0, 1, slave=5)
    if through_gateway:
        check("unit 5 does not answer: the gateway's 0B", exception_code(r) == 0x0B)
    else:
        check("unit 5 does not answer", r.isError())
    client.close()
    return 1 if check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
