"""`motionbus serve modbus` on an RTU line (a pseudo-terminal) executes broadcasts.

A write to unit 0 (FC06 and FC10) is executed by every unit served and never answered (MODBUS
over Serial Line V1.02 §2.1); a read of unit 1 afterwards shows the values. The frames are
written on the pty's other end by this script, each after more than t3.5 of silence, and every
byte the server sends is read back and checked.

Usage: serve_broadcast_checks.py MOTIONBUS_CLI. Exit 0 when every check holds.
"""
import json
import os
import select
import subprocess
import sys
import time
import tty

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import reference  # noqa: E402

failures = []


def check(name, condition, detail=""):
    print(("ok   " if condition else "FAIL ") + name + ("" if condition else f": {detail}"))
    if not condition:
        failures.append(name)


def rtu(unit, pdu):
    """The RTU ADU as bytes (tests/support/reference.py's independent CRC)."""
    return bytes(reference.rtu(unit, pdu))


def heard(fd, seconds, want=None):
    """Every byte the server sends within `seconds`, or, with `want`, until that many bytes and
    0.1 s more (anything after them is read too)."""
    out = b""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        ready, _, _ = select.select([fd], [], [], 0.02)
        if ready:
            out += os.read(fd, 512)
            if want is not None and len(out) >= want:
                end = min(end, time.monotonic() + 0.1)
    return out


def main():
    cli = sys.argv[1]
    master, slave = os.openpty()
    tty.setraw(slave)
    tty.setraw(master)
    server = subprocess.Popen([cli, "serve", "modbus", "--device", os.ttyname(slave), "--units",
                               "1-2", "--json"], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)
    try:
        time.sleep(0.5)  # the server opens and sets up the line
        # a read first: the server answers on this line at all
        read = rtu(1, [0x03, 0x00, 0x05, 0x00, 0x03])
        os.write(master, read)
        before = heard(master, 2.0, 11)
        check("unit 1 answers a read (registers 5-7 at 0)",
              before == rtu(1, [0x03, 0x06, 0, 0, 0, 0, 0, 0]), before.hex())
        # FC06 to unit 0: register 5 = 0x1234, no answer
        os.write(master, rtu(0, [0x06, 0x00, 0x05, 0x12, 0x34]))
        got = heard(master, 0.4)
        check("a broadcast FC06 gets no answer", got == b"", got.hex())
        # FC10 to unit 0: registers 6-7 = 0xABCD 0x0102, no answer
        os.write(master, rtu(0, [0x10, 0x00, 0x06, 0x00, 0x02, 0x04, 0xAB, 0xCD, 0x01, 0x02]))
        got = heard(master, 0.4)
        check("a broadcast FC10 gets no answer", got == b"", got.hex())
        # each unit served executed both
        for unit in (1, 2):
            os.write(master, rtu(unit, [0x03, 0x00, 0x05, 0x00, 0x03]))
            after = heard(master, 2.0, 11)
            check(f"unit {unit} executed both broadcasts (registers 5-7 read back)",
                  after == rtu(unit, [0x03, 0x06, 0x12, 0x34, 0xAB, 0xCD, 0x01, 0x02]),
                  after.hex())
    finally:
        server.terminate()
        out, err = server.communicate(timeout=10)
        os.close(master)
        os.close(slave)
    lines = [json.loads(l) for l in out.splitlines() if l.strip()]
    print("\n".join("  " + json.dumps(l) for l in lines))
    check("the server logged the five requests it served, the broadcasts without an answer",
          [(l.get("unit"), l.get("function"), l.get("answer") != "none") for l in lines] ==
          [(1, 3, True), (0, 6, False), (0, 16, False), (1, 3, True), (2, 3, True)],
          f"{lines} {err}")
    if failures:
        print(f"{len(failures)} checks failed")
        return 1
    print("serve modbus broadcasts: every check holds")
    return 0


if __name__ == "__main__":
    sys.exit(main())
