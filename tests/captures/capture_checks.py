"""`motionbus decode ... capture` on recordings made by the real tools, and `encode ... --vcd`.

- Icarus Verilog runs tests/captures/tb.v, which drives BiSS-C MA/SLO, a Modbus RTU line and a
  T-format line, and dumps VCD: every frame decoded with its values and its start time.
- sigrok-cli turns raw logic samples (made here: a Modbus line at 9600 8E1 and BiSS-C MA/SLO
  at 100 kHz, sampled at 1 MHz) into a sigrok session file (.sr): every frame decoded.
- A CSV as analyzer software exports it (a time column, one column per channel) of a T-format
  line: both directions decoded and labelled.
- encode ... --vcd, then decode ... capture: the same frame back, for the three protocols.

The frames' bytes and CRCs are built here, independently of the library (the Modbus CRC-16 bit
by bit in tests/support/reference.py, the T-format CRC as the XOR of the bytes, the BiSS-C
CRC6 bit by bit).

Usage: capture_checks.py MOTIONBUS_CLI TESTS_CAPTURES_DIR WORK_DIR. Exit 0 when every check
holds.
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import reference  # noqa: E402  (the independent CRC-16, tests/support/reference.py)

failures = []


def check(name, condition, detail=""):
    print(("ok   " if condition else "FAIL ") + name + ("" if condition else f": {detail}"))
    if not condition:
        failures.append(name)


def decode(cli, *args):
    p = subprocess.run([cli, "decode", *args, "--json"], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=60)
    lines = [json.loads(line) for line in p.stdout.splitlines() if line.strip()]
    frames = [l for l in lines if not l.get("summary")]
    summary = [l for l in lines if l.get("summary")]
    return frames, (summary[0] if summary else {}), p.returncode, p.stderr


def crc16_modbus(data):
    """The CRC's two bytes as sent, low byte first."""
    crc = reference.crc16_modbus(data)
    return bytes([crc & 0xFF, crc >> 8])


def crc6_biss(bits):
    c = 0
    for b in bits:
        fb = ((c >> 5) & 1) ^ b
        c = (c << 1) & 0x3F
        if fb:
            c ^= 0x03
    return [((~c) >> k) & 1 for k in range(5, -1, -1)]


def biss_samples(position, ack=3, cds=0):
    data = [(position >> k) & 1 for k in range(31, -1, -1)] + [1, 1]
    return [0] * ack + [1, cds] + data + crc6_biss(data)


def uart_bits(data, parity):
    bits = []
    for b in data:
        d = [(b >> k) & 1 for k in range(8)]
        bits += [0] + d + ([sum(d) % 2] if parity == "E" else []) + [1]
    return bits


def tb_vcd(cli, source, work):
    subprocess.run(["iverilog", "-g2005", "-o", "tb.vvp", os.path.join(source, "tb.v")],
                   cwd=work, check=True)
    subprocess.run(["vvp", "-n", "tb.vvp"], cwd=work, check=True, stdout=subprocess.DEVNULL)
    vcd = os.path.join(work, "capture.vcd")
    frames, summary, status, err = decode(cli, "biss", "capture", vcd, "--clock", "ma",
                                          "--data", "slo")
    check("VCD (Icarus): two BiSS-C frames, positions and start times",
          [(f.get("time_us"), f.get("position"), f.get("ok")) for f in frames] ==
          [(2, 123456, True), (107, 7, True)] and status == 0, f"{frames} {err}")
    check("VCD (Icarus): the BiSS-C clock measured", summary.get("clock_hz") == 1000000,
          f"{summary}")
    frames, summary, status, err = decode(cli, "modbus", "capture", vcd, "--line", "tb.mb_line")
    check("VCD (Icarus): the Modbus request and its response, with their times",
          [(f.get("time_us"), f.get("dir"), f.get("function"), f.get("values")) for f in frames]
          == [(1000, "request", 3, None), (20167, "response", 3, [555, 0, 100])]
          and frames[1].get("latency_us") == 19167 and status == 0, f"{frames} {err}")
    text = subprocess.run([cli, "decode", "modbus", "capture", vcd, "--line", "mb_line"],
                          stdout=subprocess.PIPE, text=True, timeout=60).stdout.splitlines()
    check("VCD (Icarus): the Modbus frames in text", text[:2] == [
        "time_us=1000 dir=request  ok  slave=17 function=0x03 address=0x006B quantity=3 "
        "crc=0x8776",
        "time_us=20167 dir=response latency_us=19167  ok  slave=17 function=0x03 byte_count=6 "
        "values=555,0,100 crc=0xBAC8"], f"{text}")
    text = subprocess.run([cli, "decode", "biss", "capture", vcd, "--clock", "ma", "--data",
                           "slo"], stdout=subprocess.PIPE, text=True, timeout=60).stdout
    check("VCD (Icarus): the BiSS-C frames in text", text.splitlines()[:1] == [
        "time_us=2 clocks=45  ok  position=123456 ne=1 nw=1 cds=0 crc=0x3E line_delay=0 start=3 ack_bits=3"],
        text)
    text = subprocess.run([cli, "decode", "tformat", "capture", vcd, "--line", "tf_line"],
                          stdout=subprocess.PIPE, text=True, timeout=60).stdout
    check("VCD (Icarus): the T-format frames in text", text.splitlines()[:2] == [
        "time_us=200 dir=request  ok  data_id=3 cf=0x1A",
        "time_us=206 dir=response latency_us=6  ok  data_id=3 cf=0x1A sf=0x20 ea0=0 ea1=1 ca0=0 "
        "ca1=0 abs=74565 abm=4660 enid=0x11 almc=0xC0 alarms=\"BE battery error, BA battery alarm\" "
        "crc=0xAA"], text)
    frames, summary, status, err = decode(cli, "tformat", "capture", vcd, "--line", "tf_line")
    check("VCD (Icarus): the T-format request and response, both directions labelled",
          [(f.get("time_us"), f.get("dir"), f.get("data_id")) for f in frames] ==
          [(200, "request", 3), (206, "response", 3)] and frames[1].get("abs") == 0x012345
          and frames[1].get("abm") == 0x1234 and frames[1].get("alarms") == ["BE", "BA"],
          f"{frames} {err}")


def sigrok_sr(cli, work):
    rate = 1000000
    total = 60000
    samples = [0b111] * total  # line, MA, SLO idle high
    # Modbus at 9600 8E1: a request at 1 ms, its response 15 ms later
    request = bytes.fromhex("0103000000") + b"\x02"
    request += crc16_modbus(request)
    response = bytes.fromhex("01030400070008")
    response += crc16_modbus(response)
    for start, frame in ((1000, request), (25000, response)):
        for i, bit in enumerate(uart_bits(frame, "E")):
            for s in range(start + round(i * rate / 9600), start + round((i + 1) * rate / 9600)):
                samples[s] = (samples[s] & ~1) | bit
    # BiSS-C at 100 kHz (10 samples a clock): frames at 45 ms and 52 ms
    for start, position in ((45000, 0xCAFE), (52000, 99)):
        for i, bit in enumerate(biss_samples(position)):
            t = start + 10 * i
            for s in range(t, t + 10):
                ma = 0 if s < t + 5 else 1
                samples[s] = (samples[s] & 1) | (ma << 1) | (bit << 2)
    raw = os.path.join(work, "raw.bin")
    with open(raw, "wb") as f:
        f.write(bytes(samples))
    sr = os.path.join(work, "capture.sr")
    subprocess.run(["sigrok-cli", "-I", f"binary:numchannels=3:samplerate={rate}", "-i", raw,
                    "-C", "0=line,1=MA,2=SLO", "-o", sr], check=True)
    frames, summary, status, err = decode(cli, "modbus", "capture", sr, "--line", "line")
    check("sigrok .sr: the Modbus request and its response, with their times",
          [(f.get("time_us"), f.get("dir"), f.get("ok")) for f in frames] ==
          [(1000, "request", True), (25000, "response", True)]
          and frames[1].get("values") == [7, 8] and summary.get("slave_1") == [1, 1, 0],
          f"{frames} {summary} {err}")
    frames, summary, status, err = decode(cli, "biss", "capture", sr, "--clock", "MA",
                                          "--data", "SLO")
    check("sigrok .sr: two BiSS-C frames at 100 kHz",
          [(f.get("time_us"), f.get("position")) for f in frames] == [(45000, 0xCAFE),
                                                                      (52000, 99)]
          and summary.get("clock_hz") == 100000, f"{frames} {summary} {err}")
    frames, _, status, _ = decode(cli, "biss", "capture", sr, "--clock", "MA", "--data", "nope")
    check("sigrok .sr: an unknown channel is a usage error", status == 2)
    bad = os.path.join(work, "bad.vcd")
    with open(bad, "w") as f:
        f.write("$timescale 1ns $end\n$var wire 1 ! a $end\n$enddefinitions $end\n#zz\n1!\n")
    _, _, status, err = decode(cli, "tformat", "capture", bad, "--line", "a")
    check("a malformed VCD is a usage error, with its reason", status == 2 and
          "the time 'zz' is not a number" in err, err)
    with open(bad, "w") as f:
        f.write("$timescale 1ns $end\n$var wire 1 ! a $end\n$enddefinitions $end\n#20\n1!\n"
                "#10\n0!\n")
    _, _, status, err = decode(cli, "tformat", "capture", bad, "--line", "a")
    check("a VCD whose time goes back is a usage error", status == 2 and
          "the time '#10' goes back" in err, err)
    bad_csv = os.path.join(work, "bad.csv")
    with open(bad_csv, "w") as f:
        f.write("Time [s],a\n0,1\n1e-6,x\n")
    _, _, status, err = decode(cli, "tformat", "capture", bad_csv, "--line", "a")
    check("a CSV level other than 0 or 1 is a usage error", status == 2 and
          "row 3: the level 'x' of 'a' is not 0 or 1" in err, err)
    with open(raw, "rb") as f:
        with open(os.path.join(work, "not_a_zip.sr"), "wb") as g:
            g.write(f.read(64))
    _, _, status, err = decode(cli, "modbus", "capture", os.path.join(work, "not_a_zip.sr"),
                               "--line", "line")
    check("a .sr that is not a session file is a usage error", status == 2 and
          "not a sigrok session file" in err, err)


def analyzer_csv(cli, work):
    baud = 2500000
    request = [0x02]  # ID0
    response = [0x02, 0x00, 0x40, 0xE2, 0x01]  # CF, SF, ABS 123456
    x = 0
    for b in response:
        x ^= b
    response.append(x)
    bad = list(response)
    bad[3] ^= 0x01  # one flipped bit: the CRC no longer matches
    rows = ["Time [s],tf,unused"]
    level = 1
    rows.append(f"0.000000000,{level},0")
    for start, frame in ((100e-6, request), (110e-6, response), (300e-6, request),
                         (310e-6, bad)):
        for i, bit in enumerate(uart_bits(frame, "N")):
            if bit != level:
                level = bit
                rows.append(f"{start + i / baud:.9f},{level},0")
    if level != 1:
        rows.append(f"{400e-6:.9f},1,0")
    rows.append(f"{500e-6:.9f},1,0")
    path = os.path.join(work, "tformat.csv")
    with open(path, "w") as f:
        f.write("\n".join(rows) + "\n")
    frames, summary, status, err = decode(cli, "tformat", "capture", path, "--line", "tf")
    check("CSV: T-format requests and responses, both directions labelled, a CRC error flagged",
          [(f.get("time_us"), f.get("dir"), f.get("ok"), f.get("error")) for f in frames] ==
          [(100, "request", True, None), (110, "response", True, None),
           (300, "request", True, None), (310, "response", False, "crc_mismatch")]
          and frames[1].get("abs") == 123456 and status == 1, f"{frames} {err}")
    check("CSV: the CRC error's evidence", frames[3].get("expected") == x ^ 0x01 and
          frames[3].get("received") == x if len(frames) == 4 else False, f"{frames}")


def uart_csv(path, column, baud, frames, parity="E", end=None):
    """A CSV (time column, one channel) of a UART line: `frames` is a list of (start seconds,
    bytes) or (start, bytes, bad_stop): bad_stop holds the stop bit of byte 0 low (a framing
    error, a T-format delimiter error)."""
    rows = [f"Time [s],{column}", "0.000000000,1"]
    level = 1
    last = 0.0
    for item in frames:
        start, data = item[0], item[1]
        bits = uart_bits(data, parity)
        if len(item) > 2 and item[2]:
            bits[(9 if parity == "N" else 10)] = 0
        for i, bit in enumerate(bits):
            if bit != level:
                level = bit
                rows.append(f"{start + i / baud:.9f},{level}")
        last = start + len(bits) / baud
        if level != 1:  # a low stop bit: the line back to idle after it
            level = 1
            rows.append(f"{last:.9f},1")
    if level != 1:
        rows.append(f"{last:.9f},1")
        level = 1
    rows.append(f"{(end if end is not None else last + 0.05):.9f},1")
    with open(path, "w") as f:
        f.write("\n".join(rows) + "\n")


def modbus_frame(hex_text):
    data = bytes.fromhex(hex_text)
    return data + crc16_modbus(data)


def modbus_lost_frames(cli, work):
    """issue 23: a corrupted request, then 5 x t3.5 later a request, its exception reply and a
    request, at 9600 8E1; garbage, then an FC06 exchange; --parity N on the 8E1 recording."""
    baud = 9600
    char = 11 / baud
    t35 = 3.5 * char
    bad = bytearray(modbus_frame("110300000002"))
    bad[3] ^= 0x40
    request = modbus_frame("110300000002")
    exception = modbus_frame("118302")
    third = modbus_frame("110400010001")
    frames = []
    t = 0.001
    for data in (bytes(bad), request, exception, third):
        frames.append((t, data))
        t += len(data) * char + 5 * t35
    path = os.path.join(work, "modbus_lost.csv")
    uart_csv(path, "line", baud, frames)
    got, summary, status, err = decode(cli, "modbus", "capture", path, "--line", "line")
    got = [f for f in got if f.get("error") != "no_response"]  # the last request's, at the end
    check("Modbus capture: a corrupted request, then request, exception, request: every one",
          [(f.get("dir"), f.get("ok"), f.get("error")) for f in got] ==
          [("?", False, "crc_mismatch"), ("request", True, None), ("response", True, None),
           ("request", True, None)]
          and got[0].get("bytes") == bytes(bad).hex()
          and got[2].get("exception") is not None
          and summary.get("missing_responses") == 1, f"{got} {summary} {err}")
    # the same frames 1.5 ms apart: closer than t3.5 (4 ms) and the old monitor's 20 ms, which
    # merged them; length rule and CRC frame them apart, whatever the gap
    frames = []
    t = 0.001
    for data in (bytes(bad), request, exception, third):
        frames.append((t, data))
        t += len(data) * char + 0.0015
    path = os.path.join(work, "modbus_close.csv")
    uart_csv(path, "line", baud, frames)
    for gap in ([], ["--gap-us", "20000"]):
        got, summary, status, err = decode(cli, "modbus", "capture", path, "--line", "line",
                                           *gap)
        got = [f for f in got if f.get("error") != "no_response"]
        check(f"Modbus capture: frames closer than the gap are framed apart {gap}",
              [(f.get("dir"), f.get("ok"), f.get("error")) for f in got] ==
              [("?", False, "crc_mismatch"), ("request", True, None), ("response", True, None),
               ("request", True, None)], f"{got} {err}")
    # garbage right before an FC06 request, then its echo
    write = modbus_frame("010600010003")
    garbage = bytes([0x00, 0xFF, 0x11, 0x10, 0x55])
    frames = [(0.001, garbage + write), (0.001 + 13 * char + 5 * t35, write)]
    path = os.path.join(work, "modbus_garbage.csv")
    uart_csv(path, "line", baud, frames)
    got, summary, status, err = decode(cli, "modbus", "capture", path, "--line", "line")
    check("Modbus capture: an FC06 exchange after garbage is reported",
          [(f.get("dir"), f.get("ok")) for f in got] ==
          [("?", False), ("request", True), ("response", True)]
          and got[0].get("bytes") == garbage.hex() and summary.get("missing_responses") == 0,
          f"{got} {summary} {err}")
    # an 8E1 recording read as 8N1: the parity bit is read as the stop bit
    path = os.path.join(work, "modbus_lost.csv")
    got, summary, status, err = decode(cli, "modbus", "capture", path, "--line", "line",
                                       "--parity", "N")
    check("Modbus capture --parity N of an 8E1 line: frames fail with the framing error",
          got and not any(f.get("ok") for f in got) and status == 1
          and any(f.get("error") == "framing_error" and "byte_index" in f for f in got),
          f"{got} {err}")
    # a parity error in a byte of a valid frame: the frame fails, with the evidence
    bits_path = os.path.join(work, "modbus_parity.csv")
    rows = ["Time [s],line", "0.000000000,1"]
    level = 1
    bits = uart_bits(request, "E")
    bits[2 * 11 + 9] ^= 1  # byte 2's parity bit
    for i, bit in enumerate(bits):
        if bit != level:
            level = bit
            rows.append(f"{0.001 + i / baud:.9f},{level}")
    rows.append(f"{0.001 + len(bits) / baud:.9f},1")
    rows.append("0.050000000,1")
    with open(bits_path, "w") as f:
        f.write("\n".join(rows) + "\n")
    got, summary, status, err = decode(cli, "modbus", "capture", bits_path, "--line", "line")
    got = [f for f in got if f.get("error") != "no_response"]
    check("Modbus capture: a parity error fails its frame, with the byte and the frame",
          [(f.get("ok"), f.get("error"), f.get("byte_index")) for f in got] ==
          [(False, "parity_error", 2)] and got[0].get("bytes") == request.hex()
          and status == 1, f"{got} {err}")


def modbus_late_response(cli, work):
    """A recording has no response time: a response long after its request, with no request
    between, is paired (before session 18 a 32-bit response time ran out after 4295 s: the
    request was reported missing and its response left alone)."""
    request = modbus_frame("110300000002")
    response = modbus_frame("110304000A000B")
    path = os.path.join(work, "modbus_late.csv")
    uart_csv(path, "line", 9600, [(0.001, request), (5000.0, response)])
    got, summary, status, err = decode(cli, "modbus", "capture", path, "--line", "line")
    check("Modbus capture: a response 5000 s after its request is paired, nothing missing",
          [(f.get("dir"), f.get("ok")) for f in got] == [("request", True), ("response", True)]
          and summary.get("missing_responses") == 0 and status == 0, f"{got} {summary} {err}")


def tformat_abnormal(cli, work):
    """issue 23: requests the encoder answers with ID3 data (spec §6.3.2, Tables 5 and 6) are
    paired with the reply and flagged."""
    baud = 2500000

    def with_crc(data):
        x = 0
        for b in data:
            x ^= b
        return bytes(data) + bytes([x])

    def id3(sf):
        return with_crc([0x1A, sf, 0, 0, 0, 0x11, 0, 0, 0, 0])

    exchanges = [
        (bytes([0xEA, 0x06, 0xEC]), False, 0x00, None),  # IDD page 7 address 6: closed
        (bytes([0x82]), False, 0x40, "parity"),  # ID0 CF, parity wrong: ca0
        (bytes([0x02]), True, 0x80, "framing_error"),  # ID0, delimiter error: ca1
        (bytes([0xA2]), False, 0x00, "unknown_data_id"),  # ID4
        (bytes([0xEA, 0x06, 0x00]), False, 0x00, "crc_mismatch"),  # IDD, bad CRC
        # Table 6 No. 4: a parity error in an EEPROM request's CF: sized by its Data ID
        (bytes([0xB2, 0x00, 0x32, 0x12]), False, 0x40, "parity"),  # ID6
        (bytes([0x6A, 0x06, 0xEC]), False, 0x40, "parity"),  # IDD
    ]
    frames = []
    t = 100e-6
    for request, bad_stop, sf, _ in exchanges:
        frames.append((t, request, bad_stop))
        frames.append((t + len(request) * 4e-6 + 3e-6, id3(sf)))
        t += 200e-6
    path = os.path.join(work, "tformat_abnormal.csv")
    uart_csv(path, "tf", baud, frames, parity="N")
    got, summary, status, err = decode(cli, "tformat", "capture", path, "--line", "tf")
    pairs = [(f.get("dir"), f.get("error"), f.get("id3_reply"), f.get("ca0"), f.get("ca1"))
             for f in got]
    expected = []
    for request, _, sf, error in exchanges:
        expected.append(("request" if error != "framing_error" else "?", error, None, None,
                         None))
        expected.append(("response", None, True, 1 if sf & 0x40 else 0, 1 if sf & 0x80 else 0))
    check("T-format capture: abnormal requests paired with their ID3 replies, flagged",
          pairs == expected and summary.get("missing_responses") == 0
          and summary.get("garbage_bytes") == 0, f"{pairs} {summary} {err}")
    first = got[:2]
    check("T-format capture: EA 06 EC and its ID3 reply: no missing response, no phantom",
          len(first) == 2 and first[0].get("ok") and first[0].get("data_id") == 13
          and first[1].get("ok") and first[1].get("data_id") == 3, f"{first}")


def round_trips(cli, work):
    def encode(*args):
        p = subprocess.run([cli, "encode", *args, "--json"], stdout=subprocess.PIPE, text=True,
                           timeout=30)
        return json.loads(p.stdout)

    vcd = os.path.join(work, "biss.vcd")
    e = encode("biss", "csd", "--position", "4242", "--cds", "1", "--vcd", vcd, "--baud",
               "2000000")
    frames, summary, _, _ = decode(cli, "biss", "capture", vcd, "--clock", "MA", "--data", "SLO")
    check("encode biss csd --vcd, then decode biss capture",
          e.get("ok") and [(f.get("position"), f.get("cds")) for f in frames] == [(4242, 1)]
          and summary.get("clock_hz") == 2000000, f"{frames}")
    vcd = os.path.join(work, "modbus.vcd")
    e = encode("modbus", "request", "--function", "16", "--slave", "9", "--address", "0x10",
               "--values", "1,2,3", "--vcd", vcd, "--baud", "19200", "--parity", "N",
               "--stop-bits", "2")
    frames, _, _, _ = decode(cli, "modbus", "capture", vcd, "--line", "line", "--baud", "19200",
                             "--parity", "N", "--stop-bits", "2")
    check("encode modbus request --vcd, then decode modbus capture",
          e.get("ok") and frames and frames[0].get("values") == [1, 2, 3]
          and frames[0].get("slave") == 9 and frames[0].get("address") == 0x10, f"{frames}")
    vcd = os.path.join(work, "tformat.vcd")
    e = encode("tformat", "request", "--id", "D", "--address", "9", "--vcd", vcd)
    frames, _, _, _ = decode(cli, "tformat", "capture", vcd, "--line", "line")
    check("encode tformat request --vcd, then decode tformat capture",
          e.get("ok") and frames and frames[0].get("data_id") == 13
          and frames[0].get("address") == 9 and frames[0].get("dir") == "request", f"{frames}")


def main():
    cli, source, work = sys.argv[1], sys.argv[2], sys.argv[3]
    os.makedirs(work, exist_ok=True)
    tb_vcd(cli, source, work)
    sigrok_sr(cli, work)
    analyzer_csv(cli, work)
    modbus_lost_frames(cli, work)
    modbus_late_response(cli, work)
    tformat_abnormal(cli, work)
    round_trips(cli, work)
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
