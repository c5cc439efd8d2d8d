"""`motionbus monitor modbus --ascii` on a pseudo-terminal pair made by socat: ASCII frames
written into one end, the monitor on the other; every frame reported with its direction from
the pairing, a bad LRC, a non-hex character, a missing response, an exception, the summary.

Usage: monitor_ascii_checks.py MOTIONBUS_CLI. Exit 0 when every check holds.
"""
import json
import os
import subprocess
import sys
import tempfile
import time

import serial


def frame(body, lrc=None):
    if lrc is None:
        lrc = (-sum(body)) & 0xFF
    return b":" + (bytes(body) + bytes([lrc])).hex().upper().encode() + b"\r\n"


def main():
    cli = sys.argv[1]
    failures = []

    def check(name, ok):
        print(("ok   " if ok else "FAIL ") + name)
        if not ok:
            failures.append(name)

    d = tempfile.mkdtemp()
    socat = subprocess.Popen(["socat", "pty,raw,echo=0,link=%s/tap" % d,
                              "pty,raw,echo=0,link=%s/line" % d], stderr=subprocess.DEVNULL)
    try:
        for _ in range(50):
            if os.path.exists(d + "/line"):
                break
            time.sleep(0.1)
        monitor = subprocess.Popen([cli, "monitor", "modbus", "--device", d + "/tap", "--ascii",
                                    "--parity", "N", "--response-ms", "300", "--duration", "3",
                                    "--json"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        time.sleep(0.5)
        line = serial.Serial(d + "/line", 9600)
        sent = [
            frame([1, 3, 0, 4, 0, 1]),            # request
            frame([1, 3, 2, 0x12, 0x34]),         # its response
            frame([2, 3, 0, 4, 0, 1], lrc=0x55),  # a bad LRC
            b":0203000X0001F6\r\n",                # a character that is no hex digit
            frame([2, 6, 0, 1, 0, 9]),            # request
            frame([2, 0x86, 2]),                  # its exception
            frame([3, 4, 0, 0, 0, 1]),            # request: no response
        ]
        for s in sent:
            line.write(s)
            time.sleep(0.05)
        out, _ = monitor.communicate(timeout=10)
        line.close()
    finally:
        socat.kill()
    records = [json.loads(x) for x in out.decode().splitlines() if x.strip()]
    framed = [r for r in records if "dir" in r]
    dirs = [(r.get("dir"), r.get("ok"), r.get("error")) for r in framed]
    print(dirs)
    framed += [{}] * 8  # a monitor that reported fewer fails the checks below, not the script
    dirs += [(None, None, None)] * 8
    records = framed
    check("request, then its response (paired, values 0x1234)",
          dirs[0] == ("request", True, None) and dirs[1] == ("response", True, None) and
          records[1].get("values") == [0x1234] and "latency_us" in records[1])
    check("a bad LRC: crc_mismatch", dirs[2] == ("?", False, "crc_mismatch"))
    check("a non-hex character: non_hex_character", dirs[3] == ("?", False, "non_hex_character"))
    check("an exception response paired with its request",
          dirs[4] == ("request", True, None) and dirs[5][0] == "response" and
          records[5].get("exception") == 2)
    check("a request with no response: no_response",
          dirs[6] == ("request", True, None) and dirs[7] == ("response", False, "no_response"))
    summary = json.loads(out.decode().splitlines()[-1]) if out.strip() else {}
    check("the summary counts them",
          summary.get("summary") is True and summary.get("requests") == 3 and
          summary.get("responses") == 2 and summary.get("crc_errors") == 1 and
          summary.get("missing_responses") == 1 and summary.get("exceptions") == 1)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
