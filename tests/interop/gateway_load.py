"""The gateway's bounded load run and its added latency (docs/modbus.md, "The gateway under
load"). Not part of the test command: run it by hand, and record its figures.

1. Load: `motionbus serve modbus` on one end of a pseudo-terminal pair made by socat, at
   115200 baud 8E1; `motionbus gateway` on the other; REQUESTS requests (10 000 by default)
   over CLIENTS (8) TCP connections at once, each connection one request at a time. Every
   request is its own: connection c owns holding registers 100c..100c+99; its request k is,
   for even k, FC06 writing the value 2048c + k to register 100c + (k/2) % 100 and, for odd
   k, FC03 reading that register back, which must give the value request k-1 wrote. Each
   answer is checked against its request (transaction id, unit, function, address, value);
   no connection may receive a byte more after its last answer; the server must have served
   exactly REQUESTS requests (its log: none lost, none duplicated on the line). The gateway's
   resident memory (VmRSS) is sampled before the first request, at every tenth of the run
   and after the last.
2. Latency: the same line, one client, FC03 of 10 registers, one transaction at a time:
   directly on the pty (an RTU master: the line's own time), through `motionbus gateway`, and
   through pymodbus 3.0's forwarding server (a Modbus TCP server whose datastore is
   RemoteSlaveContext over pymodbus's serial client on the same pty), in rounds (a direct
   block, then rounds of gateway, pymodbus, direct). The added latency of a forwarder in a
   round is its median minus the mean of the direct medians just before and after the
   round; the figure is the median over the rounds.

Usage: /usr/bin/python3 gateway_load.py MOTIONBUS_CLI [--requests N] [--clients N]
       [--latency-samples N] [--json]
Exit 0 when every check holds.
"""
import argparse
import json
import os
import re
import socket
import statistics
import struct
import subprocess
import sys
import tempfile
import termios
import threading
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from reference import rtu  # noqa: E402  (tests/support/reference.py)

BAUD = 115200


def mbap(tid, unit, pdu):
    return struct.pack(">HHHB", tid, 0, len(pdu) + 1, unit) + pdu


def recv_exact(s, n):
    out = b""
    while len(out) < n:
        got = s.recv(n - len(out))
        if not got:
            raise ConnectionError("closed by the gateway")
        out += got
    return out


def recv_adu(s):
    head = recv_exact(s, 7)
    return head + recv_exact(s, struct.unpack(">H", head[4:6])[0] - 1)


def rss_kib(pid):
    with open(f"/proc/{pid}/status", encoding="ascii") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for(path_or_pattern, log=None, timeout=10.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if log is None:
            if os.path.exists(path_or_pattern):
                return True
        else:
            with open(log, encoding="utf-8", errors="replace") as f:
                m = re.search(path_or_pattern, f.read())
            if m:
                return m
        time.sleep(0.05)
    return None


class Line:
    """socat's pty pair, `serve modbus` on one end (its log in the scratch directory)."""

    def __init__(self, cli, scratch):
        self.cli = cli
        self.unit = os.path.join(scratch, "unit")
        self.master = os.path.join(scratch, "master")
        self.serve_log = os.path.join(scratch, "serve.log")
        self.procs = []
        self.procs.append(subprocess.Popen(
            ["socat", f"pty,raw,echo=0,link={self.unit}", f"pty,raw,echo=0,link={self.master}"],
            stderr=subprocess.DEVNULL))
        if not (wait_for(self.unit) and wait_for(self.master)):
            raise RuntimeError("socat made no pty pair")
        fd = os.open(self.master, os.O_RDWR | os.O_NOCTTY)
        self.fresh_termios = termios.tcgetattr(fd)
        os.close(fd)
        with open(self.serve_log, "w", encoding="ascii") as log:
            self.procs.append(subprocess.Popen(
                [cli, "serve", "modbus", "--device", self.unit, "--baud", str(BAUD), "--units",
                 "1", "--points", "1000", "--json"], stdout=log, stderr=subprocess.STDOUT))
        time.sleep(0.5)

    def restore_termios(self):
        """The pty's settings as socat made them: pyserial cannot open it again (tcsetattr:
        EINVAL) with the settings it left there."""
        fd = os.open(self.master, os.O_RDWR | os.O_NOCTTY)
        termios.tcsetattr(fd, termios.TCSANOW, self.fresh_termios)
        os.close(fd)

    def served(self):
        with open(self.serve_log, encoding="utf-8", errors="replace") as f:
            return sum(1 for line in f if '"request"' in line)

    def start(self, args, log_path):
        log = open(log_path, "w", encoding="ascii")  # pylint: disable=consider-using-with
        p = subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT)
        self.procs.append(p)
        return p

    def stop(self, p):
        p.terminate()
        p.wait(timeout=5)
        self.procs.remove(p)

    def close(self):
        for p in reversed(self.procs):
            p.terminate()
            try:
                p.wait(timeout=5)
            except subprocess.TimeoutExpired:
                p.kill()


def start_gateway(line, scratch):
    log = os.path.join(scratch, "gateway.log")
    p = line.start([line.cli, "gateway", "--listen", "127.0.0.1:0", "--device", line.master,
                    "--baud", str(BAUD), "--timeout-ms", "1000"], log)
    m = wait_for(r"127\.0\.0\.1:(\d+)", log)
    if not m:
        raise RuntimeError("the gateway did not start: " + open(log, encoding="utf-8").read())
    return p, int(m.group(1))


def load_run(line, scratch, requests, clients):
    gateway, port = start_gateway(line, scratch)
    per_client = [requests // clients + (1 if c < requests % clients else 0)
                  for c in range(clients)]
    failures = []
    latencies = []
    done = [0]
    lock = threading.Lock()
    rss = [("start", 0, rss_kib(gateway.pid))]
    served_before = line.served()

    def client(c, count):
        try:
            s = socket.create_connection(("127.0.0.1", port), timeout=10)
            s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            mine = []
            for k in range(count):
                address = 100 * c + (k // 2) % 100
                value = (2048 * c + k - (k % 2)) & 0xFFFF  # odd k: what k-1 wrote
                pdu = (struct.pack(">BHH", 0x06, address, value) if k % 2 == 0
                       else struct.pack(">BHH", 0x03, address, 1))
                expect = (pdu if k % 2 == 0 else struct.pack(">BBH", 0x03, 2, value))
                t0 = time.perf_counter()
                s.sendall(mbap(k, 1, pdu))
                answer = recv_adu(s)
                mine.append(time.perf_counter() - t0)
                tid, proto, _, unit = struct.unpack(">HHHB", answer[:7])
                if (tid, proto, unit, answer[7:]) != (k, 0, 1, expect):
                    with lock:
                        failures.append(f"client {c} request {k}: {answer.hex()}, expected "
                                        f"{mbap(k, 1, expect).hex()}")
                    break
                with lock:
                    done[0] += 1
            s.setblocking(False)
            time.sleep(0.3)
            try:
                extra = s.recv(4096)
            except BlockingIOError:
                extra = None
            if extra:
                with lock:
                    failures.append(f"client {c}: {len(extra)} bytes after its last answer")
            s.close()
            with lock:
                latencies.extend(mine)
        except (OSError, ConnectionError) as e:
            with lock:
                failures.append(f"client {c}: {e}")

    threads = [threading.Thread(target=client, args=(c, n)) for c, n in enumerate(per_client)]
    t0 = time.perf_counter()
    for t in threads:
        t.start()
    next_sample = requests // 10
    while any(t.is_alive() for t in threads):
        time.sleep(0.05)
        with lock:
            n = done[0]
        if n >= next_sample and next_sample < requests:
            rss.append(("during", n, rss_kib(gateway.pid)))
            next_sample += requests // 10
    elapsed = time.perf_counter() - t0
    for t in threads:
        t.join()
    time.sleep(0.3)
    rss.append(("end", done[0], rss_kib(gateway.pid)))
    served = line.served() - served_before
    line.stop(gateway)
    latencies.sort()
    return {
        "requests": requests, "clients": clients, "answered": done[0], "served": served,
        "failures": failures, "seconds": round(elapsed, 2),
        "per_second": round(done[0] / elapsed, 1),
        "latency_ms_median": round(1e3 * statistics.median(latencies), 2) if latencies else None,
        "latency_ms_p99": round(1e3 * latencies[int(0.99 * (len(latencies) - 1))], 2)
        if latencies else None,
        "rss_kib": rss,
    }


def fc03_10():
    return struct.pack(">BHH", 0x03, 0, 10)


def latency_direct(line, samples):
    fd = os.open(line.master, os.O_RDWR | os.O_NOCTTY)  # raw already (socat); no baud on a pty
    request = bytes(rtu(1, fc03_10()))
    times = []
    for _ in range(samples):
        t0 = time.perf_counter()
        os.write(fd, request)
        got = b""
        while len(got) < 25:  # 1 + 1 + 1 + 20 + 2
            got += os.read(fd, 25 - len(got))
        times.append(time.perf_counter() - t0)
        if got[:3] != b"\x01\x03\x14":
            raise RuntimeError("direct: " + got.hex())
        time.sleep(0.004)  # the line's silence before the next request (t3.5 is 1.75 ms)
    os.close(fd)
    return times


def latency_tcp(port, samples):
    s = socket.create_connection(("127.0.0.1", port), timeout=5)
    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    times = []
    for k in range(samples):
        tid = k & 0xFFFF
        t0 = time.perf_counter()
        s.sendall(mbap(tid, 1, fc03_10()))
        answer = recv_adu(s)
        times.append(time.perf_counter() - t0)
        if answer[:2] != struct.pack(">H", tid) or answer[7:9] != b"\x03\x14":
            raise RuntimeError("tcp: " + answer.hex())
        time.sleep(0.004)
    s.close()
    return times


PYMODBUS_FORWARDER = """
import logging, sys
logging.getLogger("pymodbus").setLevel(logging.CRITICAL)  # its 'unit=' warning, each request
from pymodbus.client import ModbusSerialClient
from pymodbus.datastore import ModbusServerContext
from pymodbus.datastore.remote import RemoteSlaveContext
from pymodbus.server import StartTcpServer
client = ModbusSerialClient(port=sys.argv[1], baudrate=115200, parity="E", stopbits=1,
                            bytesize=8, timeout=1, strict=False)
assert client.connect()
context = ModbusServerContext(slaves=RemoteSlaveContext(client, unit=1), single=True)
print("listening", flush=True)
StartTcpServer(context=context, address=("127.0.0.1", int(sys.argv[2])))
"""


def forwarder_port(line, scratch):
    """Starts pymodbus's forwarding server on the pty; returns (process, port)."""
    line.restore_termios()
    port = free_port()
    log = os.path.join(scratch, "pymodbus.log")
    forwarder = line.start([sys.executable, "-c", PYMODBUS_FORWARDER, line.master, str(port)],
                           log)
    if not wait_for("listening", log):
        raise RuntimeError("the pymodbus forwarder did not start: " +
                           open(log, encoding="utf-8", errors="replace").read())
    for _ in range(100):
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            break
        except OSError:
            time.sleep(0.1)
    return forwarder, port


def latency_run(line, scratch, samples, rounds=4):
    """Rounds of: gateway, pymodbus, direct, after one direct block (samples // rounds each),
    so that each round's two forwarders have a direct block measured just before and just
    after them: a forwarder's added latency in a round is its median minus the mean of those
    two direct medians."""
    n = max(1, samples // rounds)
    blocks = {"direct_rtu": [], "motionbus_gateway": [], "pymodbus_forwarder": []}
    added = {"motionbus_gateway": [], "pymodbus_forwarder": []}
    before = latency_direct(line, n)
    blocks["direct_rtu"].extend(before)
    for _ in range(rounds):
        medians = {}
        for name in ("motionbus_gateway", "pymodbus_forwarder"):
            proc, port = (start_gateway(line, scratch) if name == "motionbus_gateway"
                          else forwarder_port(line, scratch))
            latency_tcp(port, 20)  # warm-up
            times = latency_tcp(port, n)
            line.stop(proc)
            medians[name] = statistics.median(times)
            blocks[name].extend(times)
        after = latency_direct(line, n)
        blocks["direct_rtu"].extend(after)
        base = (statistics.median(before) + statistics.median(after)) / 2
        for name, med in medians.items():
            added[name].append(med - base)
        before = after
    out = {}
    for name, times in blocks.items():
        times.sort()
        out[name] = {"median_ms": round(1e3 * statistics.median(times), 3),
                     "p90_ms": round(1e3 * times[int(0.9 * (len(times) - 1))], 3)}
        if name in added:
            out[name]["added_ms_per_round"] = [round(1e3 * v, 3) for v in added[name]]
            out[name]["added_ms"] = round(1e3 * statistics.median(added[name]), 3)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("cli")
    ap.add_argument("--requests", type=int, default=10000)
    ap.add_argument("--clients", type=int, default=8)
    ap.add_argument("--latency-samples", type=int, default=2000)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        line = Line(a.cli, scratch)
        try:
            load = load_run(line, scratch, a.requests, a.clients)
            latency = latency_run(line, scratch, a.latency_samples) if a.latency_samples else {}
        finally:
            line.close()
    rss = [r[2] for r in load["rss_kib"]]
    checks = {
        "every request answered": load["answered"] == a.requests,
        "every answer matches its request": not load["failures"],
        "the server served each request once": load["served"] == a.requests,
        "the gateway's memory flat (end RSS = RSS after the first tenth)":
            len(rss) < 3 or rss[-1] == rss[1],
    }
    result = {"load": load, "latency": latency, "checks": checks,
              "host": os.uname().machine, "load_average": os.getloadavg()}
    if a.json:
        print(json.dumps(result, indent=1))
    else:
        for k, v in load.items():
            if k != "failures":
                print(f"{k}: {v}")
        for f in load["failures"][:10]:
            print("  " + f)
        for k, v in latency.items():
            print(f"{k}: {v}")
        for k, v in checks.items():
            print(("ok   " if v else "FAIL ") + k)
    return 0 if all(checks.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
