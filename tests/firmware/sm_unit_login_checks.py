#!/usr/bin/python3
"""The SM unit's login, in raw bytes, on a serial device (the SM unit image's UART): writing the
password to holding registers 100..107 toggles login and logout, input register 300 reads the
state (0xFF00 in, 0x0000 out), and a write while logged out is a login error, exception 04 (SM
Unit Communication Guidelines §5, §6, §9, §10; docs/modbus.md §4). CRCs are computed here.

Usage: sm_unit_login_checks.py DEVICE. Exit 0 when every check holds. Run on a unit logged in
(at power-on); it leaves the unit logged in.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from modbus_raw_checks import Line, adu  # noqa: E402


def main():
    line = Line(sys.argv[1])
    failures = []

    def check(name, condition):
        print(("ok   " if condition else "FAIL ") + name)
        if not condition:
            failures.append(name)

    def ask(pdu):
        line.send(adu(1, pdu))
        return line.receive(1.5)

    password = list(b"password") + [0] * 8  # 16 bytes, NUL padded: registers 100..107
    toggle = [0x10, 0x00, 100, 0x00, 8, 16] + password
    status = [0x04, 0x01, 0x2C, 0x00, 0x01]  # FC04 input register 300
    check("logged in at power-on", ask(status) == adu(1, [0x04, 0x02, 0xFF, 0x00]))
    check("the password logs out", ask(toggle) == adu(1, [0x10, 0x00, 100, 0x00, 8]))
    check("status: logged out", ask(status) == adu(1, [0x04, 0x02, 0x00, 0x00]))
    check("a write while logged out: exception 04",
          ask([0x06, 0x00, 36, 0x02, 0xEE]) == adu(1, [0x86, 0x04]))
    check("the password logs in again", ask(toggle) == adu(1, [0x10, 0x00, 100, 0x00, 8]))
    check("status: logged in", ask(status) == adu(1, [0x04, 0x02, 0xFF, 0x00]))
    check("a write while logged in: done",
          ask([0x06, 0x00, 36, 0x02, 0xEE]) == adu(1, [0x06, 0x00, 36, 0x02, 0xEE]))
    os.close(line.fd)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
