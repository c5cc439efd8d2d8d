#!/usr/bin/env python3
"""A bounded soak of `motionbus serve modbus` and `motionbus monitor modbus` (issue 28 §6):
not part of the test command; run it by hand and record its figures (docs/testing.md, "The
soak").

The line: a pseudo-terminal pair made by socat, `serve modbus --units 1 --points 1000` on one
end at 115200 baud 8E1 (tests/interop/gateway_load.py's Line); this script is the master on
the other end, and the tap: every byte it writes and every byte it reads is also written, in
order, onto a third pseudo-terminal where `monitor modbus` listens (tests/cli/monitor_checks.py's
Tap). FRAMES request frames (100 000 by default) from a fixed seed, each written as soon as the
line allows: t3.5 (1750 us at 115200) after the answer to the one before, or, for a frame that
gets no answer, after a quiet wait (QUIET_S) in which any answer would be seen.

The frames (in order, from the seed):
  request      a well-formed request to unit 1: FC03, FC04 (1-10 registers), FC06, FC10 (1-8
               registers), or FC03/FC04 past the 1000 points (exception 02); the script keeps
               its own model of the unit's registers, so every answer is known to the byte
  split        a read (FC03, FC04) from unit 1 written in two parts with a pause shorter
               than t3.5 (a silence that does not end a frame); one whose measured pause the
               scheduler stretched to the server's silence (6 ms) is two frames on the line:
               counted as an overrun, its answer not due
  other_unit   a well-formed FC03 to a unit the server does not have (2..247): never answered
  broadcast    FC06 to address 0: executed (the model follows), never answered
  bitflip      a request to unit 1 with one bit flipped (CRC-16 detects every single-bit error)
  cut          a request to unit 1 cut short (1 .. length-1 of its bytes)
  garbage      1..16 random bytes
A fault (bitflip, cut, garbage) is followed by a well-formed request to unit 1, either after a
silence (`silence`: the quiet wait) or at once (`glued`: less than t3.5, none at all, between
the fault's last byte and the request's first). Fault bytes are drawn again when any run of
them, alone or running into the request behind (4 bytes or more), is a CRC-valid RTU frame:
such a run would be a frame on the line (1 in 65536 a run), not a framing failure; how many
draws were refused is reported.

What a fault may cost, from the framers' guarantees (docs/modbus.md §3):
  server (rtu_framer, frame_end::silence): the silence ends whatever is held, so a fault
    followed by a silence costs itself alone; a fault with no silence behind it is held with
    the request that follows until the silence after that request, which ends them: the
    framer hands over the first frame the length rule finds past the fault's bytes. So a
    fault costs itself alone, and a request glued behind it is answered once, one silence
    late (the server's silence: t3.5 rounded up plus 4 ms, serve_modbus_command.cpp).
  monitor (rtu_listener): after a bad frame the listener drops one byte and rescans, so no
    valid frame behind it is lost; the bytes dropped between two frames are one record. So
    a fault costs one failure record ('?': crc_mismatch, truncated, modbus_pdu_length or
    garbage) and nothing else.
Expectations (each a check; the script exits 1 when one fails):
  - every well-formed request to unit 1 (request, split, and the one behind each fault) is
    answered exactly once, with the answer the model gives, byte for byte (CRC included);
  - nothing else is answered (other_unit, broadcast, faults), and no byte arrives after an
    answer or at the end;
  - the server served exactly the well-formed requests to unit 1 and the broadcasts, in order,
    once each (its --json log), and none of the faults;
  - the monitor reported every well-formed frame on the line, in order (direction, slave,
    function), each fault as one failure record, each unanswered request (other_unit) as one
    missing response, and a summary whose counts agree;
  - the server's and the monitor's resident memory (VmRSS, /proc) flat: sampled before the
    first frame, at every tenth and after the last; the last sample at most FLAT_KIB above
    the one at the first tenth (a leak of one byte a frame over the run's last nine tenths
    of 100 000 frames would be 88 KiB).

Usage: /usr/bin/python3 tools/scripts/soak.py MOTIONBUS_CLI [--frames N] [--seed S]
       [--json FILE] [--keep DIR]
"""
import argparse
import json
import os
import random
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "tests", "interop"))
sys.path.insert(0, os.path.join(ROOT, "tests", "cli"))
sys.path.insert(0, os.path.join(ROOT, "tests", "support"))
from gateway_load import BAUD, Line, rss_kib  # noqa: E402
from monitor_checks import Tap  # noqa: E402
from reference import rtu  # noqa: E402

CHAR_S = 11 / BAUD          # 8E1: start, 8 data, parity, stop
T35_S = 1750e-6             # t3.5 above 19200 baud (Serial Line V1.02 §2.5.1.1)
T15_S = 750e-6
# The silence after which `serve modbus` ends a frame: t3.5 rounded up to the millisecond, and
# 4 ms (serve_modbus_command.cpp). A split whose pause the scheduler stretched to it is two
# frames on the line, not a pause inside one: counted apart (overrun), its answer not due. So
# that such a loss cannot change the unit, splits are reads.
SERVER_SILENCE_S = 0.006
QUIET_S = 0.015             # a frame with no answer: the server's silence and more
ANSWER_TIMEOUT_S = 1.0      # a frame that must be answered
POINTS = 1000
FLAT_KIB = 16
FAULTS = ("bitflip", "cut", "garbage")
# Shares of the frames (the rest are plain requests); a fault counts one frame, its request
# behind it another.
SHARES = (("split", 0.02), ("other_unit", 0.02), ("broadcast", 0.005),
          ("bitflip", 0.02), ("cut", 0.02), ("garbage", 0.02))


def crc_table():
    table = []
    for i in range(256):
        c = i
        for _ in range(8):
            c = (c >> 1) ^ 0xA001 if c & 1 else c >> 1
        table.append(c)
    return table


TABLE = crc_table()


def crc_valid_run(data, starts):
    """Whether a run data[i:j] (i < starts, j - i >= 4) ends in its own CRC (low byte first)."""
    for i in range(min(starts, len(data))):
        crc = 0xFFFF
        for j in range(i, len(data)):
            # crc is the CRC of data[i:j]; data[j:j+2] would be its CRC
            if j - i >= 2 and j + 2 <= len(data) and data[j] == crc & 0xFF and \
                    data[j + 1] == crc >> 8:
                return True
            crc = (crc >> 8) ^ TABLE[(crc ^ data[j]) & 0xFF]
    return False


def crc_valid_prefix(data):
    """Whether a proper prefix of data (4 bytes or more) ends in its own CRC."""
    crc = 0xFFFF
    for j, b in enumerate(data):
        if 2 <= j <= len(data) - 3 and data[j] == crc & 0xFF and data[j + 1] == crc >> 8:
            return True
        crc = (crc >> 8) ^ TABLE[(crc ^ b) & 0xFF]
    return False


class Unit:
    """The script's model of `serve modbus`'s unit 1 (serve_modbus_command.cpp): holding
    registers as written (0 at start), input register i reading 1000 * unit + i."""

    def __init__(self):
        self.holding = [0] * POINTS
        self.redrawn = 0

    def request(self, rng, apply=True):
        """A random well-formed request to unit 1: (pdu, expected answer ADU), neither with a
        CRC-valid proper prefix (see plan())."""
        while True:
            saved = self.holding[:]
            pdu, answer = self.draw(rng, apply)
            if not (crc_valid_prefix(bytes(rtu(1, pdu))) or crc_valid_prefix(answer)):
                return pdu, answer
            self.holding = saved
            self.redrawn += 1

    def draw(self, rng, apply):
        r = rng.random()
        if r < 0.05:  # past the points: exception 02
            fc = rng.choice((3, 4))
            a = rng.randrange(POINTS - 9, POINTS)
            pdu = bytes([fc, a >> 8, a & 0xFF, 0, 10])
            return pdu, bytes(rtu(1, [fc | 0x80, 2]))
        if r < 0.40:
            fc = 3
        elif r < 0.60:
            fc = 4
        elif r < 0.85:
            fc = 6
        else:
            fc = 0x10
        a = rng.randrange(POINTS)
        if fc in (3, 4):
            q = rng.randint(1, min(10, POINTS - a))
            values = (self.holding[a:a + q] if fc == 3
                      else [(1000 + a + i) & 0xFFFF for i in range(q)])
            pdu = bytes([fc, a >> 8, a & 0xFF, 0, q])
            body = [fc, 2 * q] + [b for v in values for b in (v >> 8, v & 0xFF)]
            return pdu, bytes(rtu(1, body))
        if fc == 6:
            v = rng.randrange(65536)
            pdu = bytes([6, a >> 8, a & 0xFF, v >> 8, v & 0xFF])
            if apply:
                self.holding[a] = v
            return pdu, bytes(rtu(1, pdu))
        q = rng.randint(1, min(8, POINTS - a))
        values = [rng.randrange(65536) for _ in range(q)]
        pdu = bytes([0x10, a >> 8, a & 0xFF, 0, q, 2 * q] +
                    [b for v in values for b in (v >> 8, v & 0xFF)])
        if apply:
            self.holding[a:a + q] = values
        return pdu, bytes(rtu(1, pdu[:5]))


def plan(frames, seed):
    """The frames to write, in order: dicts with kind, bytes, answer (None: none expected),
    and for a fault's request the fault's kind and how it follows it."""
    rng = random.Random(seed)
    unit = Unit()
    out = []
    redrawn = 0
    while len(out) < frames:
        r = rng.random()
        kind = "request"
        for name, share in SHARES:
            if r < share:
                kind = name
                break
            r -= share
        if kind in FAULTS and len(out) + 2 > frames:
            kind = "request"
        if kind == "other_unit":
            frame = None
            while frame is None or crc_valid_prefix(frame):
                a = rng.randrange(POINTS)
                frame = bytes(rtu(rng.randint(2, 247), [3, a >> 8, a & 0xFF, 0, 1]))
            out.append({"kind": kind, "bytes": frame, "answer": None})
        elif kind == "broadcast":
            frame = None
            while frame is None or crc_valid_prefix(frame):
                a, v = rng.randrange(POINTS), rng.randrange(65536)
                frame = bytes(rtu(0, [6, a >> 8, a & 0xFF, v >> 8, v & 0xFF]))
            unit.holding[a] = v
            out.append({"kind": kind, "bytes": frame, "answer": None})
        elif kind in FAULTS:
            follow = rng.choice(("silence", "glued"))
            pdu, answer = unit.request(rng)
            behind = bytes(rtu(1, pdu))
            while True:
                bad = fault(kind, rng, unit)
                if not crc_valid_run(bad + behind, len(bad)):
                    break
                redrawn += 1
            out.append({"kind": kind, "bytes": bad, "answer": None, "follow": follow})
            out.append({"kind": "request", "bytes": behind, "answer": answer,
                        "after": kind, "follow": follow, "pdu": pdu, "fault": bad.hex()})
        else:
            pdu, answer = unit.request(rng, apply=kind != "split")
            while kind == "split" and pdu[0] not in (3, 4):  # a read: see SERVER_SILENCE_S
                pdu, answer = unit.request(rng, apply=False)
            item = {"kind": kind, "bytes": bytes(rtu(1, pdu)), "answer": answer, "pdu": pdu}
            if kind == "split":
                item["cut_at"] = rng.randint(1, len(item["bytes"]) - 1)
            out.append(item)
    # A rule read from inside a fault may want up to 256 bytes, running into the frames and
    # answers behind it: no such run may be CRC-valid either (the line's bytes are known).
    for k, item in enumerate(out):
        if item["kind"] not in FAULTS:
            continue
        after = b""
        for later in out[k + 1:]:
            after += later["bytes"] + (later["answer"] or b"")
            if len(after) >= 256:
                break
        while crc_valid_run(item["bytes"] + after[:256], len(item["bytes"])):
            item["bytes"] = fault(item["kind"], rng, unit)
            redrawn += 1
    return out, {"faults": redrawn, "frames": unit.redrawn}


def fault(kind, rng, unit):
    """A fault's bytes: 1..16 random bytes, or a request to unit 1 (never executed: the model
    is left as it is) with one bit flipped, or cut short."""
    if kind == "garbage":
        return bytes(rng.randrange(256) for _ in range(rng.randint(1, 16)))
    victim = bytes(rtu(1, unit.request(rng, apply=False)[0]))
    if kind == "bitflip":
        bad = bytearray(victim)
        bad[rng.randrange(len(victim))] ^= 1 << rng.randrange(8)
        return bytes(bad)
    return victim[:rng.randint(1, len(victim) - 1)]


class Master:
    """The master's end of the line, and the tap: what it writes and reads is copied onto the
    monitor's pseudo-terminal."""

    def __init__(self, path, tap):
        self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
        self.tap = tap
        self.pause_max = 0.0

    def write(self, data, cut_at=None):
        if cut_at is None:
            os.write(self.fd, data)
            self.tap.noise(data)
            return None
        os.write(self.fd, data[:cut_at])
        self.tap.noise(data[:cut_at])
        t0 = time.perf_counter()
        time.sleep(T15_S)  # a pause shorter than t3.5 (measured: the largest is reported)
        os.write(self.fd, data[cut_at:])
        pause = time.perf_counter() - t0
        self.pause_max = max(self.pause_max, pause)
        self.tap.noise(data[cut_at:])
        return pause

    def read(self, want, timeout):
        """Up to `want` bytes (None: any) within `timeout`; what arrived is copied to the tap."""
        got = b""
        end = time.perf_counter() + timeout
        while want is None or len(got) < want:
            left = max(0.0, end - time.perf_counter())
            if not select.select([self.fd], [], [], left)[0]:
                break
            got += os.read(self.fd, 4096 if want is None else want - len(got))
        if got:
            self.tap.noise(got)
        return got

    def close(self):
        os.close(self.fd)


def run(cli, frames, seed, keep=None):
    items, redrawn = plan(frames, seed)
    result = {"frames": len(items), "seed": seed, "redrawn": redrawn}
    with tempfile.TemporaryDirectory() as scratch:
        line = Line(cli, scratch)
        monitor = None
        master = None
        try:
            server = line.procs[-1]
            tap = Tap()  # its thread is not started: its monitor pty only
            monitor_log = os.path.join(scratch, "monitor.jsonl")
            with open(monitor_log, "w", encoding="ascii") as log:
                monitor = subprocess.Popen(
                    [cli, "monitor", "modbus", "--device", tap.path("monitor"), "--baud",
                     str(BAUD), "--response-ms", "500", "--json"], stdout=log,
                    stderr=subprocess.STDOUT)
            time.sleep(0.5)
            master = Master(line.master, tap)
            result.update(drive(master, items, server.pid, monitor.pid))
            time.sleep(0.3)
            result["bytes_after_the_end"] = len(master.read(None, 0.2))
            result["split_pause_max_us"] = round(master.pause_max * 1e6)
            monitor.send_signal(signal.SIGINT)
            monitor.wait(timeout=30)
            with open(monitor_log, encoding="utf-8", errors="replace") as f:
                records = [json.loads(x) for x in f if x.strip()]
            with open(line.serve_log, encoding="utf-8", errors="replace") as f:
                served = [json.loads(x) for x in f if '"request"' in x]
            if keep:
                shutil.copy(monitor_log, keep)
                shutil.copy(line.serve_log, keep)
        finally:
            if master:
                master.close()
            if monitor and monitor.poll() is None:
                monitor.kill()
                monitor.wait()
            line.close()
    return items, result, records, served


def drive(master, items, server_pid, monitor_pid):
    """Writes every frame, reads every answer; what happened to each frame is kept in it."""
    rss = {"server": [], "monitor": []}

    def sample(at):
        rss["server"].append((at, rss_kib(server_pid)))
        rss["monitor"].append((at, rss_kib(monitor_pid)))

    sample(0)
    tenth = max(1, len(items) // 10)
    t0 = time.perf_counter()
    for k, item in enumerate(items):
        early = master.read(None, 0)  # bytes before the frame: an answer too many
        if early:
            item["early_bytes"] = early.hex()
        pause = master.write(item["bytes"], item.get("cut_at"))
        if pause is not None:
            item["pause_us"] = round(pause * 1e6)
        if item["kind"] in FAULTS and item["follow"] == "glued":
            pass  # the request behind it at once: no silence
        elif item["answer"] is None:
            item["got"] = master.read(None, QUIET_S)
        else:
            item["got"] = master.read(len(item["answer"]), ANSWER_TIMEOUT_S)
            if item["got"] == item["answer"]:
                time.sleep(T35_S)  # the line's silence before the next frame
        if (k + 1) % tenth == 0:
            sample(k + 1)
    elapsed = time.perf_counter() - t0
    time.sleep(0.2)
    sample(len(items))
    return {"seconds": round(elapsed, 1), "rss_kib": rss}


def request_rule_8(data):
    """Whether data[:8] is CRC-valid as a whole (6 bytes and their CRC, low byte first)."""
    crc = 0xFFFF
    for b in data[:6]:
        crc = (crc >> 8) ^ TABLE[(crc ^ b) & 0xFF]
    return data[6] == crc & 0xFF and data[7] == crc >> 8


def expected_monitor(items):
    """The monitor's well-formed frames, in order, from what went over the line."""
    frames = []
    faults = 0
    missing = 0
    chance = []
    for item in items:
        b = item["bytes"]
        if item["kind"] in FAULTS:
            faults += 1
            continue
        frames.append(("request", b[0], b[1]))
        got = item.get("got", b"")
        if item["kind"] == "other_unit" or (b[0] != 0 and not got):
            missing += 1
        if len(got) > 8 and got[1] in (3, 4) and request_rule_8(got):
            # the documented chance (docs/modbus.md §3, the listener: "a request rule reading a
            # response's bytes needs a CRC match by chance, 1 in 65536"): its first 8 bytes are a
            # CRC-valid FC03/04 request, which ends the frame before the response rule's length;
            # the rest is one failure record, the request and that phantom each unanswered
            chance.append(got.hex())
            frames.append(("request", got[0], got[1]))
            faults += 1
            missing += 2
        elif got and len(got) >= 2:
            frames.append(("response", got[0], got[1] & 0x7F))
    return frames, faults, missing, chance


def check(items, result, records, served):
    checks = {}
    overrun = [i for i in items if i.get("pause_us", 0) >= SERVER_SILENCE_S * 1e6]
    result["split_overruns"] = len(overrun)
    result["split_overruns_answered"] = sum(1 for i in overrun if i.get("got") == i["answer"])
    for i in overrun:
        if i.get("got") != i["answer"]:
            i["answer"] = None  # two frames on the line: no answer due
            i["kind"] = "split_overrun"
    want_answer = [i for i in items if i["answer"] is not None]
    answered = [i for i in want_answer if i.get("got") == i["answer"]]
    wrong = [i for i in want_answer if i.get("got") and i["got"] != i["answer"]]
    unanswered = [i for i in want_answer if not i.get("got")]
    spurious = [i for i in items if i["answer"] is None and i.get("got")]
    early = [i for i in items if "early_bytes" in i]

    def cause(i):
        if "after" in i:
            return f"request after {i['after']} ({i['follow']})"
        return i["kind"]

    lost = {}
    for i in unanswered + wrong:
        lost[cause(i)] = lost.get(cause(i), 0) + 1
    kinds = {}
    for i in items:
        key = i["kind"] + (f" ({i['follow']})" if i["kind"] in FAULTS else "")
        kinds[key] = kinds.get(key, 0) + 1
    result["by_kind"] = kinds
    result["answers_expected"] = len(want_answer)
    result["answered"] = len(answered)
    result["lost_by_cause"] = lost
    result["lost_details"] = [{"cause": cause(i), "frame": i["bytes"].hex(),
                               "got": i.get("got", b"").hex(), "pause_us": i.get("pause_us"),
                               "behind_fault": i.get("fault")}
                              for i in unanswered + wrong][:10]
    result["answered_when_none_was_due"] = [(i["kind"], i["bytes"].hex(), i["got"].hex())
                                            for i in spurious][:10]
    checks["every well-formed request to unit 1 answered once, byte for byte"] = \
        len(answered) == len(want_answer)
    checks["nothing else answered (other units, broadcasts, faults)"] = not spurious
    checks["no byte after an answer, none at the end"] = \
        not early and result["bytes_after_the_end"] == 0

    # the server's log: what it served, in order
    want_served = [(1 if i["bytes"][0] == 1 else 0, i["bytes"][1:-2].hex())
                   for i in items if i["answer"] is not None or i["kind"] == "broadcast"]
    got_served = [(s.get("unit"), s.get("request")) for s in served]
    result["served"] = len(got_served)
    checks["the server served each well-formed request to it once, in order, no fault"] = \
        got_served == want_served

    # the monitor
    frames, faults, missing, chance = expected_monitor(items)
    result["monitor_chance_requests"] = chance
    summary = [r for r in records if r.get("summary")]
    s = summary[0] if summary else {}
    seen = [(r.get("dir"), r.get("slave"), r.get("function")) for r in records
            if r.get("ok") and r.get("dir") in ("request", "response")]
    failures = [r for r in records if r.get("dir") == "?"]
    no_response = [r for r in records if r.get("error") == "no_response"]
    others = [r for r in records if not r.get("summary") and not r.get("ok")
              and r.get("dir") != "?" and r.get("error") != "no_response"]
    result["monitor"] = {"frames": s.get("frames"), "requests": s.get("requests"),
                         "responses": s.get("responses"),
                         "missing_responses": s.get("missing_responses"),
                         "failure_records": len(failures), "crc_errors": s.get("crc_errors"),
                         "other_errors": s.get("other_errors"),
                         "garbage_bytes": s.get("garbage_bytes")}
    first_difference = next((k for k in range(min(len(seen), len(frames)))
                             if seen[k] != frames[k]), None)
    if first_difference is not None:
        result["monitor"]["first_difference"] = {"at": first_difference,
                                                 "seen": seen[first_difference],
                                                 "sent": frames[first_difference]}
    checks["the monitor: every well-formed frame on the line, in order"] = seen == frames
    checks["the monitor: each fault one failure record, nothing else failed"] = \
        len(failures) == faults and not others
    checks["the monitor: each unanswered request one missing response"] = \
        len(no_response) == missing
    checks["the monitor's summary agrees"] = bool(summary) and \
        s.get("frames") == len(frames) + faults and \
        s.get("requests") == sum(1 for f in frames if f[0] == "request") and \
        s.get("responses") == sum(1 for f in frames if f[0] == "response") and \
        s.get("missing_responses") == missing and \
        s.get("crc_errors", 0) + s.get("other_errors", 0) + \
        sum(1 for r in failures if r.get("error") == "garbage") == faults

    # memory
    for who, samples in result["rss_kib"].items():
        tenth = samples[1][1] if len(samples) > 2 else samples[0][1]
        checks[f"the {who}'s memory flat (last sample - first tenth's <= {FLAT_KIB} KiB)"] = \
            samples[-1][1] - tenth <= FLAT_KIB
    result["checks"] = checks
    return checks


def line_time(items):
    """The time the same frames take on a real line at BAUD: every byte's character time and
    t3.5 before each frame (the requests and the answers)."""
    t = 0.0
    for i in items:
        t += len(i["bytes"]) * CHAR_S + T35_S
        if i.get("got"):
            t += len(i["got"]) * CHAR_S + T35_S
    return t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("cli")
    ap.add_argument("--frames", type=int, default=100000)
    ap.add_argument("--seed", type=int, default=0x50A4)
    ap.add_argument("--json", help="write the result there too")
    ap.add_argument("--keep", help="a directory to copy the monitor's and the server's logs to")
    a = ap.parse_args()
    items, result, records, served = run(a.cli, a.frames, a.seed, a.keep)
    checks = check(items, result, records, served)
    result["per_second"] = round(len(items) / result["seconds"], 1)
    result["line_seconds_at_115200"] = round(line_time(items), 1)
    result["load_average"] = os.getloadavg()
    for k, v in result.items():
        if k != "checks":
            print(f"{k}: {v}")
    for k, v in checks.items():
        print(("ok   " if v else "FAIL ") + k)
    if a.json:
        with open(a.json, "w", encoding="utf-8") as f:
            json.dump(result, f, indent=1)
    return 0 if all(checks.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
