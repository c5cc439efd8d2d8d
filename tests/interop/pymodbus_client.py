"""pymodbus (a third-party Modbus master) against `motionbus serve sm-unit` on a pty.

Usage: pymodbus_client.py DEVICE. Exit 0 when every check holds. Run with Debian's python3,
which is where python3-pymodbus installs.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from pymodbus_peer import Checks, open_master  # noqa: E402  (tests/support/pymodbus_peer.py)


def main() -> int:
    client = open_master(sys.argv[1])
    check = Checks()

    r = client.read_input_registers(100, 9, slave=1)
    check("FC04 instantaneous data: 9 registers", not r.isError() and len(r.registers) == 9)
    check("frequency register is 50 Hz", not r.isError() and r.registers[7] == 50)
    r = client.read_input_registers(300, 1, slave=1)
    check("FC04 login status: logged in (0xFF00)", not r.isError() and r.registers[0] == 0xFF00)
    r = client.write_register(36, 750, slave=1)
    check("FC06 overheat limit 75.0 degC", not r.isError())
    r = client.read_holding_registers(36, 1, slave=1)
    check("FC03 reads it back", not r.isError() and r.registers[0] == 750)
    r = client.write_register(0, 201, slave=1)
    check("FC06 out of limits: exception 03", r.isError() and getattr(r, "exception_code", 0) == 3)
    r = client.read_holding_registers(200, 1, slave=1)
    check("FC03 one address of a block: exception 02",
          r.isError() and getattr(r, "exception_code", 0) == 2)
    r = client.read_holding_registers(200, 8, slave=1)
    text = b"".join(v.to_bytes(2, "big") for v in r.registers) if not r.isError() else b""
    check("FC03 password block reads 'password'", text.rstrip(b"\0") == b"password")
    r = client.write_registers(37, [6000, 20], slave=1)
    check("FC10 two settings", not r.isError())
    r = client.write_coil(100, True, slave=1)
    check("FC05 warning reset", not r.isError())
    # Log out and in again: the password written to 100..107 toggles the login (SM unit §10).
    password = [0x7061, 0x7373, 0x776F, 0x7264, 0, 0, 0, 0]  # "password", NUL padded
    r = client.write_registers(100, password, slave=1)
    check("FC10 the password logs out", not r.isError())
    r = client.write_register(36, 700, slave=1)
    check("FC06 while logged out: exception 04",
          r.isError() and getattr(r, "exception_code", 0) == 4)
    r = client.write_registers(100, password, slave=1)
    check("FC10 the password logs in again", not r.isError())
    r = client.read_input_registers(300, 1, slave=1)
    check("FC04 login status: logged in again", not r.isError() and r.registers[0] == 0xFF00)
    r = client.read_input_registers(100, 9, slave=5)
    check("another slave stays silent", r.isError())
    client.close()
    return 1 if check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
