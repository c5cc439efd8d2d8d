"""`motionbus monitor modbus|tformat` on a tapped line made of pseudo-terminals.

A tap (this script) joins a client's pty to an emulator's pty and copies every byte of both
directions onto a third pty, where the monitor listens; it can corrupt the copy, drop a
response, or put line noise on the monitor's side only. The clients are the CLI's own `read`
commands; the emulators are the CLI's `serve` commands. Every line the monitor prints (with
--json) is checked: each request paired with its response, each injected fault flagged as what
it is, and the summary's counts.

Usage: monitor_checks.py MOTIONBUS_CLI modbus|tformat. Exit 0 when every check holds.
"""
import json
import os
import select
import signal
import subprocess
import sys
import threading
import time
import tty

failures = []


def check(name, condition, detail=""):
    print(("ok   " if condition else "FAIL ") + name + ("" if condition else f": {detail}"))
    if not condition:
        failures.append(name)


class Tap(threading.Thread):
    """Client pty <-> emulator pty, every byte also copied onto the monitor's pty."""

    def __init__(self):
        super().__init__(daemon=True)
        self.ends = {}
        for side in ("client", "device", "monitor"):
            master, slave = os.openpty()
            tty.setraw(slave)
            self.ends[side] = (master, slave, os.ttyname(slave))
        self.lock = threading.Lock()
        self.corrupt_next_request = False   # flips the last byte, towards device and monitor
        self.corrupt_next_response = False  # flips a byte of the monitor's copy only
        self.drop_next_response = False     # the monitor never sees the next response
        self.running = True

    def path(self, side):
        return self.ends[side][2]

    def noise(self, data):
        os.write(self.ends["monitor"][0], bytes(data))

    def run(self):
        client, device, monitor = (self.ends[s][0] for s in ("client", "device", "monitor"))
        while self.running:
            ready, _, _ = select.select([client, device], [], [], 0.05)
            for fd in ready:
                data = bytearray(os.read(fd, 512))
                with self.lock:
                    if fd == client:
                        if self.corrupt_next_request:
                            data[-1] ^= 0x01
                            self.corrupt_next_request = False
                        os.write(device, data)
                        os.write(monitor, data)
                    else:
                        os.write(client, data)
                        if self.drop_next_response:
                            self.drop_next_response = False
                            continue
                        copy = bytearray(data)
                        if self.corrupt_next_response:
                            copy[len(copy) // 2] ^= 0x10
                            self.corrupt_next_response = False
                        os.write(monitor, copy)


def start(cmd):
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)


def wait_open(*pairs):
    """Waits until each (process, device) pair's CLI holds its device open (it is listening),
    10 s at most each: a fixed sleep was not always enough on a loaded machine (a monitor
    that opened its pty after the first request timed it before its own start)."""
    for proc, path in pairs:
        target = os.path.realpath(path)
        deadline = time.monotonic() + 10
        held = False
        while not held and proc.poll() is None and time.monotonic() < deadline:
            try:
                fds = os.listdir(f"/proc/{proc.pid}/fd")
                held = any(os.path.realpath(f"/proc/{proc.pid}/fd/{fd}") == target for fd in fds)
            except OSError:
                pass
            time.sleep(0.02)
        check(f"the CLI (pid {proc.pid}) opened {path}", held, "not within 10 s")
    time.sleep(0.1)  # (its line settings follow the open)


def run(cmd):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                          timeout=20).stdout


def stop_server(server):
    """Stops an emulator; the lines it printed (one per request it served)."""
    server.terminate()
    out, _ = server.communicate(timeout=10)
    return [l for l in out.splitlines() if l.strip()]


def stop_monitor(monitor):
    time.sleep(0.3)
    monitor.send_signal(signal.SIGINT)
    out, _ = monitor.communicate(timeout=10)
    lines = [json.loads(line) for line in out.splitlines() if line.strip()]
    return [l for l in lines if not l.get("summary")], [l for l in lines if l.get("summary")]


def modbus(cli):
    tap = Tap()
    tap.start()
    server = start([cli, "serve", "sm-unit", "--device", tap.path("device"), "--json"])
    monitor = start([cli, "monitor", "modbus", "--device", tap.path("monitor"), "--json",
                     "--response-ms", "300"])
    wait_open((server, tap.path("device")), (monitor, tap.path("monitor")))
    client = [cli, "read", "modbus", "--device", tap.path("client"), "--json"]

    def ask(*args):
        out = run(client + list(args))
        time.sleep(0.15)  # the SM unit wants 0.1 s between commands
        return out

    ask("--slave", "1", "--function", "3", "--address", "36", "--quantity", "1")  # 1: a pair
    ask("--slave", "1", "--function", "3", "--address", "200", "--quantity", "1")  # 2: exception 02
    tap.corrupt_next_request = True
    ask("--slave", "1", "--function", "4", "--address", "0", "--quantity", "2",
        "--timeout-ms", "300")  # 3: a request with a bad CRC, never answered
    tap.noise([0xFF, 0x00, 0x55])  # 4: line noise on the tap
    time.sleep(0.2)
    ask("--slave", "5", "--function", "3", "--quantity", "1", "--timeout-ms", "400")  # 5: nobody
    tap.corrupt_next_response = True
    ask("--slave", "1", "--function", "3", "--address", "36", "--quantity", "1")  # 6: bad copy
    ask("--slave", "1", "--function", "4", "--address", "0", "--quantity", "2")  # 7: a pair
    frames, summary = stop_monitor(monitor)
    served = stop_server(server)
    tap.running = False
    for f in frames:
        print("  " + json.dumps(f))
    check("modbus: the emulator printed the four requests it answered (--json)",
          [(json.loads(l).get("function"), json.loads(l).get("answer", "none")[:4])
           for l in served] == [(3, "0103"), (3, "0183"), (3, "0103"), (4, "0104")], f"{served}")
    kinds = [(f.get("dir"), f.get("ok"), f.get("error"), f.get("function"), f.get("exception"))
             for f in frames]
    want = [
        ("request", True, None, 3, None), ("response", True, None, 3, None),
        ("request", True, None, 3, None), ("response", True, None, 3, 2),
        ("?", False, "crc_mismatch", None, None),
        ("?", False, "garbage", None, None),
        ("request", True, None, 3, None), ("response", False, "no_response", 3, None),
        ("request", True, None, 3, None), ("?", False, "crc_mismatch", None, None),
        ("response", False, "no_response", 3, None),
        ("request", True, None, 4, None), ("response", True, None, 4, None),
    ]
    check("modbus: every frame seen, in order, with its direction and state",
          kinds == want, f"{kinds}")
    responses = [f for f in frames if f.get("dir") == "response" and f.get("ok")]
    check("modbus: each response paired with its request (latency between 0 and 1 s)",
          len(responses) == 3 and all(0 < f["latency_us"] < 1000000 for f in responses))
    check("modbus: times rise", all(a["time_us"] <= b["time_us"] for a, b in zip(frames,
                                                                                 frames[1:])))
    check("modbus: the exception spelled out", any(
        f.get("exception_name") == "illegal_data_address" for f in frames),
        "the SM unit answers a read outside its map (holding 200) with exception 02")
    bad = [f for f in frames if f.get("error") == "crc_mismatch"]
    check("modbus: CRC errors with the expected and received CRC",
          len(bad) == 2 and all("expected" in f and "received" in f for f in bad))
    check("modbus: the garbage's bytes reported",
          any(f.get("error") == "garbage" and f.get("bytes") == "ff0055" for f in frames))
    s = summary[0] if summary else {}
    check("modbus: the summary", summary and s.get("frames") == 11 and s.get("requests") == 5
          and s.get("responses") == 3 and s.get("missing_responses") == 2
          and s.get("exceptions") == 1 and s.get("crc_errors") == 2
          and s.get("garbage_bytes") == 3 and s.get("slave_1") == [4, 3, 4]
          and s.get("slave_5") == [1, 0, 1], f"{summary}")


def modbus_text(cli):
    """The monitor's text output: one line a frame, hex where engineers read hex, a summary."""
    tap = Tap()
    tap.start()
    server = start([cli, "serve", "sm-unit", "--device", tap.path("device")])
    monitor = start([cli, "monitor", "modbus", "--device", tap.path("monitor")])
    wait_open((server, tap.path("device")), (monitor, tap.path("monitor")))
    run([cli, "read", "modbus", "--device", tap.path("client"), "--slave", "1", "--function",
         "3", "--address", "36", "--quantity", "1"])
    time.sleep(0.3)
    monitor.send_signal(signal.SIGINT)
    out, _ = monitor.communicate(timeout=10)
    served = stop_server(server)
    tap.running = False
    check("modbus text: the emulator's line for what it served", len(served) == 1 and
          served[0].startswith("time_us=") and served[0].endswith(
              "ok  slave=1 function=0x03 address=0x0024 quantity=1 crc=0x01C4 "
              "answer=[01 03 02 03 20 B9 6C]"), f"{served}")
    lines = out.splitlines()
    print("\n".join("  " + l for l in lines))
    check("modbus text: the request line", len(lines) == 3 and lines[0].startswith("time_us=")
          and lines[0].endswith("dir=request  ok  slave=1 function=0x03 address=0x0024 "
                                "quantity=1 crc=0x01C4"), f"{lines}")
    check("modbus text: the response line, paired", len(lines) == 3 and
          " dir=response latency_us=" in lines[1] and
          lines[1].endswith("ok  slave=1 function=0x03 byte_count=2 values=800 crc=0x6CB9"),
          f"{lines}")
    check("modbus text: the summary", len(lines) == 3 and lines[2].startswith(
        "# summary=yes frames=2 requests=1 responses=1 missing_responses=0"), f"{lines}")


def tformat(cli):
    tap = Tap()
    tap.start()
    encoder = start([cli, "serve", "tformat-encoder", "--device", tap.path("device"), "--json"])
    monitor = start([cli, "monitor", "tformat", "--device", tap.path("monitor"), "--json",
                     "--response-ms", "300"])
    wait_open((encoder, tap.path("device")), (monitor, tap.path("monitor")))

    def ask(*args):
        out = run([cli, "read", "tformat", "--device", tap.path("client"), "--json"] +
                  list(args))
        time.sleep(0.1)
        return out

    ask("--id", "3")                                          # a pair (ID3)
    ask("--id", "6", "--address", "5", "--data", "0x5A")      # a pair (EEPROM write)
    time.sleep(0.1)                                           # the EEPROM's busy time
    ask("--id", "D", "--address", "5")                        # a pair (EEPROM read)
    tap.corrupt_next_response = True
    ask("--id", "0")                                          # the monitor's copy corrupted
    tap.drop_next_response = True
    ask("--id", "1")                                          # the monitor misses the response
    time.sleep(0.4)                                           # (flagged after --response-ms)
    tap.noise([0x00, 0x01])                                   # line noise (no CF)
    time.sleep(0.2)
    ask("--id", "3")                                          # a pair
    frames, summary = stop_monitor(monitor)
    served = [json.loads(l) for l in stop_server(encoder)]
    tap.running = False
    check("tformat: the emulator printed each request it answered (--json)",
          [(l.get("data_id"), l.get("answer", "")[:2]) for l in served] ==
          [(3, "1a"), (6, "32"), (13, "ea"), (0, "02"), (1, "8a"), (3, "1a")], f"{served}")
    for f in frames:
        print("  " + json.dumps(f))
    kinds = [(f.get("dir"), f.get("ok"), f.get("error"), f.get("data_id")) for f in frames]
    want = [
        ("request", True, None, 3), ("response", True, None, 3),
        ("request", True, None, 6), ("response", True, None, 6),
        ("request", True, None, 13), ("response", True, None, 13),
        ("request", True, None, 0), ("response", False, "crc_mismatch", None),
        ("request", True, None, 1), ("response", False, "no_response", 1),
        ("?", False, "garbage", None),
        ("request", True, None, 3), ("response", True, None, 3),
    ]
    check("tformat: every frame seen, in order, with its direction and state",
          kinds == want, f"{kinds}")
    eeprom = [f for f in frames if f.get("dir") == "response" and f.get("data_id") in (6, 13)]
    check("tformat: the EEPROM write echoed (address 5, 0x5A), the read answered for address 5",
          len(eeprom) == 2 and eeprom[0].get("edf") == 0x5A and eeprom[0].get("address") == 5
          and eeprom[1].get("address") == 5, f"{eeprom}")
    check("tformat: times rise", all(a["time_us"] <= b["time_us"] for a, b in zip(frames,
                                                                                  frames[1:])))
    s = summary[0] if summary else {}
    check("tformat: the summary", summary and s.get("frames") == 12 and s.get("requests") == 6
          and s.get("responses") == 5 and s.get("missing_responses") == 1
          and s.get("crc_errors") == 1 and s.get("garbage_bytes") == 2
          and s.get("data_id_3") == [2, 2, 0] and s.get("data_id_1") == [1, 0, 1],
          f"{summary}")


def crc16(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return bytes(data) + bytes([crc & 0xFF, crc >> 8])


def monitor_written(cli, protocol, writes, *options):
    """The monitor on a pty, `writes` (bytes, then the seconds to wait) written straight onto
    it: the frames it printed and its summary."""
    tap = Tap()  # (its thread is not started: only the monitor's pty is used)
    monitor = start([cli, "monitor", protocol, "--device", tap.path("monitor"), "--json",
                     *options])
    wait_open((monitor, tap.path("monitor")))
    for data, wait in writes:
        tap.noise(data)
        time.sleep(wait)
    return stop_monitor(monitor)


def modbus_lost(cli):
    """issue 23: a corrupted request, then 5 x t3.5 (20 ms at 9600 8E1) later a request, its
    exception reply and a request: every one; frames 5 ms apart are not merged."""
    bad = bytearray(crc16(bytes.fromhex("110300000002")))
    bad[3] ^= 0x40
    request = crc16(bytes.fromhex("110300000002"))
    exception = crc16(bytes.fromhex("118302"))
    third = crc16(bytes.fromhex("110400010001"))
    # The silence the monitor reports (--gap-us) far from the gaps written, either way, so that
    # a busy machine cannot move a gap across it: every gap a silence (2 ms against 200 ms),
    # then none (1 s against 5 ms).
    for gap, gap_us, name in ((0.2, "2000", "200 ms (silences)"),
                              (0.005, "1000000", "5 ms (no silence)")):
        frames, summary = monitor_written(
            cli, "modbus", [(bytes(bad), gap), (request, gap), (exception, gap), (third, 0.1)],
            "--response-ms", "5000", "--gap-us", gap_us)
        kinds = [(f.get("dir"), f.get("ok"), f.get("error")) for f in frames
                 if f.get("error") != "no_response"]  # (the third request's, at the end)
        check(f"modbus: a corrupted request, then request, exception, request {name} apart: "
              "every one reported",
              kinds == [("?", False, "crc_mismatch"), ("request", True, None),
                        ("response", True, None), ("request", True, None)]
              and frames[2].get("exception") == 2, f"{kinds}")
    # issue 23 review §2: the response to a corrupted request (it carries its own length)
    response = crc16(bytes.fromhex("1103040000002A"))
    for gap, gap_us, name in ((0.2, "2000", "silences"), (0.005, "1000000", "no silence")):
        frames, summary = monitor_written(
            cli, "modbus", [(bytes(bad), gap), (response, gap), (request, 0.1)],
            "--response-ms", "5000", "--gap-us", gap_us)
        kinds = [(f.get("dir"), f.get("ok"), f.get("error")) for f in frames
                 if f.get("error") != "no_response"]  # (the request's, at the end)
        check(f"modbus: the response behind a corrupted request is reported ({name})",
              kinds == [("?", False, "crc_mismatch"), ("response", True, None),
                        ("request", True, None)], f"{kinds}")
    garbage = bytes([0x00, 0xFF, 0x11, 0x10, 0x55])
    write = crc16(bytes.fromhex("010600010003"))
    frames, summary = monitor_written(cli, "modbus", [(garbage + write, 0.005), (write, 0.1)],
                                      "--gap-us", "1000000")
    kinds = [(f.get("dir"), f.get("ok")) for f in frames]
    check("modbus: an FC06 exchange right after garbage is reported",
          kinds == [("?", False), ("request", True), ("response", True)], f"{kinds}")


def tformat_abnormal(cli):
    """issue 23: EA 06 EC (a read of a closed address) and the encoder's ID3 reply, paired."""
    frames, summary = monitor_written(
        cli, "tformat",
        [(bytes.fromhex("EA06EC" "1A0000000011000000000B"), 0.1)])
    kinds = [(f.get("dir"), f.get("ok"), f.get("data_id"), f.get("id3_reply")) for f in frames]
    s = summary[0] if summary else {}
    check("tformat: EA 06 EC and its ID3 reply paired (no missing response, no phantom request, "
          "no garbage)",
          kinds == [("request", True, 13, None), ("response", True, 3, True)]
          and s.get("missing_responses") == 0 and s.get("garbage_bytes") == 0,
          f"{kinds} {summary}")


def tformat_truncated_request(cli):
    """issue 23 review §8: an ID3 request left unanswered, then an IDD request cut short by the
    silence: a request error (dir request), not a response to the ID3 request."""
    frames, summary = monitor_written(cli, "tformat", [(bytes.fromhex("1AEA06"), 0.5)],
                                      "--gap-us", "100000", "--response-ms", "5000")
    cut = [f for f in frames if f.get("error") == "truncated"]
    s = summary[0] if summary else {}
    check("tformat: a request cut short is a request's failure, not a response's",
          len(cut) == 1 and cut[0].get("dir") == "request" and s.get("responses") == 0,
          f"{frames} {summary}")


def tformat_echo_missing(cli):
    """issue 23: read tformat --echo on a line that does not echo: the response, not a timeout."""
    tap = Tap()
    tap.start()
    encoder = start([cli, "serve", "tformat-encoder", "--device", tap.path("device"), "--json"])
    wait_open((encoder, tap.path("device")))
    out = run([cli, "read", "tformat", "--device", tap.path("client"), "--json", "--id", "3",
               "--echo"])
    stop_server(encoder)
    tap.running = False
    lines = [json.loads(l) for l in out.splitlines() if l.strip()]
    check("tformat: read --echo on a line without echo: the response, flagged echo_missed",
          len(lines) == 1 and lines[0].get("ok") and lines[0].get("data_id") == 3
          and lines[0].get("echo_missed") is True, f"{lines}")


def main():
    cli, protocol = sys.argv[1], sys.argv[2]
    if protocol == "modbus":
        modbus(cli)
        modbus_text(cli)
        modbus_lost(cli)
    else:
        tformat(cli)
        tformat_abnormal(cli)
        tformat_truncated_request(cli)
        tformat_echo_missing(cli)
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
