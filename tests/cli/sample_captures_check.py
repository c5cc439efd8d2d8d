"""The sample recordings shipped in examples/captures/ decode with the CLI to the frames they
hold (docs/cli.md, "Sample recordings"), in each of the three formats, and stay small.

The expected frames are written here from what the samples were made of (the Modbus
Application Protocol's FC03 example registers 555, 0, 100; the T-format and BiSS-C positions
chosen by examples/captures/make_captures.py), not read back from the CLI.

Usage: sample_captures_check.py MOTIONBUS_CLI SOURCE_DIR. Exit 0 when every check holds.
"""
import json
import os
import subprocess
import sys

failures = []

MODBUS = [
    ("request", True, {"slave": 17, "function": 3, "address": 107, "quantity": 3}),
    ("response", True, {"slave": 17, "function": 3, "values": [555, 0, 100]}),
    ("request", True, {"slave": 17, "function": 6, "address": 1, "value": 3}),
    ("response", True, {"slave": 17, "function": 6, "address": 1, "value": 3}),
    ("request", True, {"slave": 17, "function": 3, "address": 0x0FFF, "quantity": 2}),
    ("response", True, {"slave": 17, "function": 3, "exception": 2,
                        "exception_name": "illegal_data_address"}),
]
TFORMAT = [
    ("request", True, {"data_id": 0, "cf": 0x02}),
    ("response", True, {"data_id": 0, "abs": 123456}),
    ("request", True, {"data_id": 3, "cf": 0x1A}),
    ("response", True, {"data_id": 3, "abs": 0x012345, "abm": 0x1234, "enid": 0x11,
                        "alarms": ["BE", "BA"]}),
    ("request", True, {"data_id": 13, "address": 5}),
    ("response", True, {"data_id": 13, "address": 5, "edf": 0x12}),
]
BISS = [
    (None, True, {"position": 123456, "ne": 1, "nw": 1}),
    (None, True, {"position": 123460, "ne": 1, "nw": 1}),
    (None, True, {"position": 123470, "ne": 1, "nw": 0}),
]
SAMPLES = [
    ("modbus", ["--line", "line"], MODBUS),
    ("tformat", ["--line", "line"], TFORMAT),
    ("biss", ["--clock", "MA", "--data", "SLO"], BISS),
]
MAX_SIZE = 16 * 1024


def check(name, condition, detail=""):
    print(("ok   " if condition else "FAIL ") + name + ("" if condition else f": {detail}"))
    if not condition:
        failures.append(name)


def matches(frame, want):
    direction, ok, fields = want
    return ((direction is None or frame.get("dir") == direction) and frame.get("ok") == ok
            and all(frame.get(k) == v for k, v in fields.items()))


def main():
    cli, source = sys.argv[1], sys.argv[2]
    folder = os.path.join(source, "examples", "captures")
    for protocol, channels, expected in SAMPLES:
        for ext in ("sr", "vcd", "csv"):
            path = os.path.join(folder, f"{protocol}.{ext}")
            name = f"examples/captures/{protocol}.{ext}"
            if not os.path.exists(path):
                check(name + " exists", False, path)
                continue
            check(name + " is small", os.path.getsize(path) <= MAX_SIZE,
                  f"{os.path.getsize(path)} bytes")
            p = subprocess.run([cli, "decode", protocol, "capture", path, *channels, "--json"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               timeout=60)
            lines = [json.loads(line) for line in p.stdout.splitlines() if line.strip()]
            frames = [l for l in lines if "summary" not in l]
            check(f"{name}: every frame found, in order, with its fields",
                  len(frames) == len(expected) and all(
                      matches(f, w) for f, w in zip(frames, expected)),
                  f"{frames} {p.stderr}")
            check(f"{name}: exit status 0 (every frame sound)", p.returncode == 0,
                  f"{p.returncode} {p.stderr}")
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
