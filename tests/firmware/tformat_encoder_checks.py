#!/usr/bin/python3
"""The T-format encoder image (examples/firmware/tformat_encoder.cpp) on a serial device, read by
the motionbus CLI (`motionbus read tformat`) for every Data ID, EEPROM writes read back on a
user page and on page 7, the reset sequences; and abnormal requests in raw bytes (a wrong sync
code, a parity error, an unknown Data ID, a bad CRC, a request cut short). Expected values come
from the image's fixed shaft (single-turn 123456, turn 77) and the TS5700N8500 specification
(docs/tformat.md §7); CRCs are computed here.

Usage: tformat_encoder_checks.py DEVICE MOTIONBUS_CLI. Exit 0 when every check holds.
"""
import json
import os
import select
import subprocess
import sys
import termios
import time
import tty

failures = []


def check(name, condition):
    print(("ok   " if condition else "FAIL ") + name)
    if not condition:
        failures.append(name)


def read(cli, device, data_id, address=None, data=None):
    cmd = [cli, "read", "tformat", "--device", device, "--id", data_id, "--timeout-ms", "1000",
           "--json"]
    if address is not None:
        cmd += ["--address", str(address)]
    if data is not None:
        cmd += ["--data", str(data)]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        return json.loads(p.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        return {"ok": False, "raw": p.stdout}


def wait_ready(cli, device):
    """Reads until the EEPROM is no longer busy (18 ms after a write, a page change or an ID8
    reset, in the image's own time, which runs behind the host's when QEMU is kept waiting)."""
    for _ in range(100):
        r = read(cli, device, "D", 4)  # open for reading on every page, page 7 included
        if r.get("ok") and r.get("busy") == 0:
            return
        time.sleep(0.02)


def xor(data):
    x = 0
    for b in data:
        x ^= b
    return x


def cf(code):
    parity = bin(code).count("1") & 1
    return 0x02 | (code << 3) | (parity << 7)


def raw(device, data, expect=None, wait=0.5):
    """The reply to `data`: what arrives within `wait` seconds, or as soon as `expect` bytes have
    (a loaded host can keep QEMU's answer waiting longer than a silent line's `wait`)."""
    fd = os.open(device, os.O_RDWR | os.O_NOCTTY)
    try:
        tty.setraw(fd)
        termios.tcflush(fd, termios.TCIOFLUSH)
        os.write(fd, bytes(data))
        got = b""
        deadline = time.monotonic() + wait
        while time.monotonic() < deadline and (expect is None or len(got) < expect):
            ready, _, _ = select.select([fd], [], [], deadline - time.monotonic())
            if ready:
                got += os.read(fd, 64)
        return got
    finally:
        os.close(fd)


def is_id3_reply(reply):
    return len(reply) == 11 and reply[0] == cf(3) and xor(reply[:10]) == reply[10]


def main():
    device, cli = sys.argv[1], sys.argv[2]
    # Every Data ID that reads, with the fields the layout carries.
    r = read(cli, device, "0")
    check("ID0: ABS 123456", r.get("ok") and r.get("abs") == 123456)
    r = read(cli, device, "1")
    check("ID1: ABM 77", r.get("ok") and r.get("abm") == 77)
    r = read(cli, device, "2")
    check("ID2: ENID 0x11", r.get("ok") and r.get("enid") == 0x11)
    r = read(cli, device, "3")
    check("ID3: ABS, ABM, ENID, no alarm",
          r.get("ok") and r.get("abs") == 123456 and r.get("abm") == 77 and r.get("enid") == 0x11
          and r.get("almc") == 0)
    # EEPROM, user page 2: select it, write 0x5A at 5, select it again, read it back.
    for step in (("6", 127, 2), ("6", 5, 0x5A), ("6", 127, 2)):
        r = read(cli, device, step[0], step[1], step[2])
        check(f"ID6 address {step[1]} data {step[2]}: echoed",
              r.get("ok") and r.get("address") == step[1] and r.get("edf") == step[2])
        wait_ready(cli, device)  # the EEPROM is busy 18 ms after a write or a page change
    r = read(cli, device, "D", 5)
    check("IDD page 2 address 5 reads 0x5A", r.get("ok") and r.get("edf") == 0x5A)
    # Page 7: the over-heat threshold (factory 0xDA = 90 degC), written and read back.
    read(cli, device, "6", 127, 7)
    wait_ready(cli, device)
    r = read(cli, device, "D", 4)
    check("page 7 address 4: over-heat threshold 0xDA (90 degC)", r.get("edf") == 0xDA)
    read(cli, device, "6", 4, 0xC0)
    wait_ready(cli, device)
    read(cli, device, "6", 127, 7)
    wait_ready(cli, device)
    r = read(cli, device, "D", 4)
    check("page 7 address 4 written 0xC0 (64 degC), read back", r.get("edf") == 0xC0)
    # Resets: 10 requests each (the CLI's requests are far more than 40 us apart in the image's
    # clock too: the Cortex-M4 board's clock no longer stands still under load, issue 27), each
    # answered with ID0's layout and the single-turn value as received (`abs`), the reset acting
    # after the 10th.
    def resets(data_id, check_id, field, single_turn):
        answers = [read(cli, device, data_id) for _ in range(10)]
        if data_id == "8":
            wait_ready(cli, device)  # ID8 writes the EEPROM: 18 ms
        r = read(cli, device, check_id)
        ok = (all(a.get("ok") and a.get("data_id") == int(data_id, 16) and a.get("abs") == single_turn
                  for a in answers) and r.get("ok") and r.get(field) == 0)
        if not ok:
            print(f"     ID{data_id} x10 answers: {answers}; then ID{check_id}: {r}")
        return ok

    check("ID8 x10: single-turn reads 0", resets("8", "0", "abs", 123456))
    check("IDC x10: multi-turn reads 0", resets("C", "1", "abm", 0))
    answers = [read(cli, device, "7") for _ in range(10)]
    check("ID7 x10 (reset errors): each answered with ID0's layout, no error flag",
          all(a.get("ok") and a.get("data_id") == 7 and a.get("abs") == 0 and a.get("ea0") == 0
              and a.get("ea1") == 0 for a in answers))
    # Abnormal requests, in raw bytes.
    check("a wrong sync code: no reply", raw(device, [0x00]) == b"")
    reply = raw(device, [cf(3) ^ 0x80], 11, 3.0)
    check("a parity error: ID3 data with ca0", is_id3_reply(reply) and (reply[1] & 0x40) != 0)
    check("an unknown Data ID (4): ID3 data", is_id3_reply(raw(device, [cf(4)], 11, 3.0)))
    bad = [cf(0xD), 5]
    check("an EEPROM read with a bad CRC: ID3 data",
          is_id3_reply(raw(device, bad + [xor(bad) ^ 0xFF], 11, 3.0)))
    check("an EEPROM write cut short: ID3 data once the line is silent",
          is_id3_reply(raw(device, [cf(6)], 11, 3.0)))  # the image's silence: 500 ms
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
