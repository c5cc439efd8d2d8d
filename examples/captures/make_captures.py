"""Writes the sample recordings of examples/captures/: each protocol's frames as a VCD, a CSV (as
analyzer software exports it) and a sigrok session file (.sr), to try `motionbus decode ...
capture` without hardware (what each holds: docs/cli.md, "Sample recordings").

The frames come from the CLI itself: requests from `motionbus encode`, the responses' CRCs
from `motionbus crc`, the BiSS-C bits from `motionbus encode biss csd`. The levels are drawn
here (UART: idle high, start bit, 8 data bits LSB first, parity, stop bit; BiSS-C: MA clocks,
SLO changed at each falling edge) and the .sr is made by sigrok-cli from raw samples.

Usage: make_captures.py MOTIONBUS_CLI [OUT_DIR]   (needs sigrok-cli for the .sr files)
Run again after changing it; tests/cli/sample_captures_check.py checks the shipped files.
"""
import json
import os
import subprocess
import sys
import tempfile


def cli_json(cli, *args):
    p = subprocess.run([cli, *args, "--json"], stdout=subprocess.PIPE, text=True, check=True)
    return json.loads(p.stdout)


def with_crc(cli, protocol, hex_bytes):
    """The bytes with their CRC appended as sent (Modbus: the wire bytes; T-format: one byte)."""
    r = cli_json(cli, "crc", protocol, hex_bytes)
    tail = r["wire"] if protocol == "modbus" else f"{r['crc']:02x}"
    return bytes.fromhex(hex_bytes + tail)


def uart_bits(data, parity):
    bits = []
    for b in data:
        d = [(b >> k) & 1 for k in range(8)]
        bits += [0] + d + ([sum(d) % 2] if parity == "E" else []) + [1]
    return bits


def uart_changes(frames, baud, parity):
    """[(time_s, level)] of a UART line sending each (start_s, bytes)."""
    changes = [(0.0, 1)]
    for start, data in frames:
        for i, bit in enumerate(uart_bits(data, parity)):
            t = start + i / baud
            if bit != changes[-1][1]:
                changes.append((t, bit))
        end = start + len(uart_bits(data, parity)) / baud
        if changes[-1][1] != 1:
            changes.append((end, 1))
    return changes


def biss_changes(frames, clock_hz):
    """[(time_s, MA, SLO)] of BiSS-C frames, each (start_s, SL samples): one clock per sample,
    falling edge first; SLO set at the falling edge, so stable at the rising edge."""
    rows = [(0.0, 1, 1)]
    period = 1.0 / clock_hz
    for start, bits in frames:
        for i, bit in enumerate(bits):
            t = start + i * period
            rows.append((t, 0, bit))
            rows.append((t + period / 2, 1, bit))
        end = start + len(bits) * period
        rows.append((end + period, 1, 1))  # MA high; SLO back to idle high (timeout over)
    return rows


def write_vcd(path, names, rows, end):
    ids = "!\"#$%&"
    lines = ["$version motionbus examples/captures/make_captures.py $end", "$timescale 1 ns $end",
             "$scope module motionbus $end"]
    lines += [f"$var wire 1 {ids[i]} {n} $end" for i, n in enumerate(names)]
    lines += ["$upscope $end", "$enddefinitions $end"]
    last = None
    for r in rows:
        t = round(r[0] * 1e9)
        levels = r[1:]
        changed = [i for i in range(len(names)) if last is None or last[i] != levels[i]]
        if not changed:
            continue
        lines.append(f"#{t}")
        if last is None:
            lines.append("$dumpvars")
        lines += [f"{levels[i]}{ids[i]}" for i in changed]
        if last is None:
            lines.append("$end")
        last = levels
    lines.append(f"#{round(end * 1e9)}")  # the end of the recording
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def write_csv(path, names, rows, end):
    lines = ["Time [s]," + ",".join(names)]
    last = None
    for r in rows:
        if last is not None and tuple(last) == tuple(r[1:]):
            continue
        lines.append(f"{r[0]:.9f}," + ",".join(str(v) for v in r[1:]))
        last = r[1:]
    lines.append(f"{end:.9f}," + ",".join(str(v) for v in last))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def write_sr(path, names, rows, end, rate):
    """Raw samples at `rate`, one byte a sample, turned into a session file by sigrok-cli."""
    count = int(round(end * rate)) + 1
    samples = bytearray(count)
    for k, r in enumerate(rows):
        first = int(round(r[0] * rate))
        last = int(round(rows[k + 1][0] * rate)) if k + 1 < len(rows) else count
        value = sum(v << i for i, v in enumerate(r[1:]))
        samples[first:last] = bytes([value]) * (last - first)
    with tempfile.TemporaryDirectory() as work:
        raw = os.path.join(work, "raw.bin")
        with open(raw, "wb") as f:
            f.write(samples)
        mapping = ",".join(f"{i}={n}" for i, n in enumerate(names))
        if os.path.exists(path):
            os.remove(path)
        subprocess.run(["sigrok-cli", "-I", f"binary:numchannels={len(names)}:samplerate={rate}",
                        "-i", raw, "-C", mapping, "-o", path], check=True)


def modbus(cli):
    """9600 8E1, slave 17: FC03 and its registers, FC06 and its echo, FC03 past the table and
    exception 02. Each response 25 ms after its request (a silence longer than t3.5)."""
    baud = 9600
    req1 = bytes.fromhex(cli_json(cli, "encode", "modbus", "request", "--function", "3",
                                  "--slave", "17", "--address", "107", "--quantity", "3")["hex"])
    rsp1 = with_crc(cli, "modbus", "110306022b00000064")
    req2 = bytes.fromhex(cli_json(cli, "encode", "modbus", "request", "--function", "6",
                                  "--slave", "17", "--address", "1", "--values", "3")["hex"])
    rsp2 = req2  # FC06 answers with the request itself
    req3 = bytes.fromhex(cli_json(cli, "encode", "modbus", "request", "--function", "3",
                                  "--slave", "17", "--address", "0x0FFF", "--quantity",
                                  "2")["hex"])
    rsp3 = with_crc(cli, "modbus", "118302")
    frames = []
    t = 0.001
    for frame in (req1, rsp1, req2, rsp2, req3, rsp3):
        frames.append((t, frame))
        t += len(uart_bits(frame, "E")) / baud + 0.025
    return ["line"], uart_changes(frames, baud, "E"), t, 200000


def tformat(cli):
    """2.5 Mbaud 8N1, one line for both directions: ID0 and its position, ID3 and its
    position, multi-turn, ENID and alarms, an EEPROM read (ID D) and its data. Each response
    3 us after its request."""
    baud = 2500000
    req1 = bytes.fromhex(cli_json(cli, "encode", "tformat", "request", "--id", "0")["hex"])
    rsp1 = with_crc(cli, "tformat", "020040e201")  # ABS 123456
    req2 = bytes.fromhex(cli_json(cli, "encode", "tformat", "request", "--id", "3")["hex"])
    rsp2 = with_crc(cli, "tformat", "1a2045230111341200c0")
    req3 = bytes.fromhex(cli_json(cli, "encode", "tformat", "request", "--id", "D",
                                  "--address", "5")["hex"])
    rsp3 = with_crc(cli, "tformat", "ea0512")  # address 5, data 0x12
    frames = []
    t = 10e-6
    for i, frame in enumerate((req1, rsp1, req2, rsp2, req3, rsp3)):
        frames.append((t, frame))
        t += len(uart_bits(frame, "N")) / baud + (3e-6 if i % 2 == 0 else 40e-6)
    return ["line"], uart_changes(frames, baud, "N"), t, 25000000


def biss(cli):
    """BiSS-C at 1 MHz, AMO ABSYS layout: three sensor data frames 100 us apart (the shaft
    turning), the last with nW low (a warning)."""
    frames = []
    t = 5e-6
    for position, nw in ((123456, 1), (123460, 1), (123470, 0)):
        bits = cli_json(cli, "encode", "biss", "csd", "--position", str(position), "--ack", "3",
                        "--nw", str(nw))["bits"]
        frames.append((t, [int(b) for b in bits]))
        t += 100e-6
    return ["MA", "SLO"], biss_changes(frames, 1e6), t, 10000000


def main():
    cli = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.dirname(os.path.abspath(__file__))
    for name, make in (("modbus", modbus), ("tformat", tformat), ("biss", biss)):
        names, rows, end, rate = make(cli)
        write_vcd(os.path.join(out, name + ".vcd"), names, rows, end)
        write_csv(os.path.join(out, name + ".csv"), names, rows, end)
        write_sr(os.path.join(out, name + ".sr"), names, rows, end, rate)
    return 0


if __name__ == "__main__":
    sys.exit(main())
