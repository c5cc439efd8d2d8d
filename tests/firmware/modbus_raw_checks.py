#!/usr/bin/python3
"""Raw-byte checks of a Modbus RTU server on a serial device (a firmware image's UART under
QEMU): no reply to a broadcast (but the write is done), none to another slave's address, the
exception for an unknown function once the line is silent, and recovery after garbage and after
a frame with a bad CRC. CRCs are computed here.

Usage: modbus_raw_checks.py DEVICE SLAVE. Exit 0 when every check holds.
"""
import os
import select
import sys
import termios
import time
import tty


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from reference import rtu  # noqa: E402  (the independent CRC-16/MODBUS of the test tools)


def adu(slave, pdu):
    return bytes(rtu(slave, pdu))


class Line:
    def __init__(self, path):
        self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(self.fd)
        termios.tcflush(self.fd, termios.TCIOFLUSH)

    def send(self, data):
        os.write(self.fd, data)

    def receive(self, seconds):
        """Every byte that arrives within `seconds` of the last one (or of the call)."""
        got = b""
        deadline = time.monotonic() + seconds
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return got
            ready, _, _ = select.select([self.fd], [], [], left)
            if ready:
                got += os.read(self.fd, 256)
                deadline = time.monotonic() + 0.3


def main():
    line = Line(sys.argv[1])
    slave = int(sys.argv[2])
    failures = []

    def check(name, condition):
        print(("ok   " if condition else "FAIL ") + name)
        if not condition:
            failures.append(name)

    def ask(pdu, to=None, wait=1.5):
        line.send(adu(slave if to is None else to, pdu))
        return line.receive(wait)

    # FC06 setting 36 := 700 as a broadcast: executed, not answered.
    check("broadcast: no reply", ask([0x06, 0x00, 36, 0x02, 0xBC], to=0, wait=0.6) == b"")
    check("broadcast: the write was done",
          ask([0x03, 0x00, 36, 0x00, 0x01]) == adu(slave, [0x03, 0x02, 0x02, 0xBC]))
    other = 5 if slave != 5 else 6
    check("another slave's address: no reply",
          ask([0x03, 0x00, 36, 0x00, 0x01], to=other, wait=0.6) == b"")
    # FC42 has no length rule: the server answers 01 once the line is silent.
    check("unknown function: exception 01 after the silence",
          ask([0x42, 0x00, 0x00, 0x00, 0x00]) == adu(slave, [0xC2, 0x01]))
    # Garbage before a request: the framer drops it and finds the frame.
    line.send(bytes([0xFF, 0x13, 0x37]))
    check("garbage, then a request: answered",
          ask([0x03, 0x00, 36, 0x00, 0x01]) == adu(slave, [0x03, 0x02, 0x02, 0xBC]))
    bad = bytearray(adu(slave, [0x03, 0x00, 36, 0x00, 0x01]))
    bad[-1] ^= 0x5A
    line.send(bytes(bad))
    check("a bad CRC: no reply", line.receive(0.6) == b"")
    check("then a good request: answered",
          ask([0x03, 0x00, 36, 0x00, 0x01]) == adu(slave, [0x03, 0x02, 0x02, 0xBC]))
    os.close(line.fd)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
