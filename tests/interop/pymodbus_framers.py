"""pymodbus 3.0's ModbusAsciiFramer and ModbusRtuFramer (the framer of its RTU-over-TCP client)
against motionbus's ascii_framer and rtu_framer with frame_end::length, offline: frames built
by pymodbus are encoded byte for byte alike by encode_ascii / encode_rtu, and framed by ours in
every role, split at every byte, back to back and with garbage between them; frames built by
ours are parsed by pymodbus into the same messages; bad ASCII input (a bad LRC, a non-hex
character) is refused by both, and ours reads the next frame.

Usage: pymodbus_framers.py FRAMERS_TOOL   (tests/interop/framers_tool.cpp). Exit 0: all agree.
Its helpers (Ours, check, pdu_of, frame_line) serve pymodbus_framer_differential.py too.
"""
import random
import subprocess
import sys

from pymodbus.bit_read_message import ReadCoilsRequest, ReadCoilsResponse, ReadDiscreteInputsRequest
from pymodbus.bit_write_message import WriteMultipleCoilsRequest, WriteSingleCoilRequest
from pymodbus.bit_write_message import WriteMultipleCoilsResponse, WriteSingleCoilResponse
from pymodbus.diag_message import ReturnQueryDataRequest
from pymodbus.factory import ClientDecoder, ServerDecoder
from pymodbus.file_message import ReadFifoQueueRequest
from pymodbus.framer.ascii_framer import ModbusAsciiFramer
from pymodbus.framer.rtu_framer import ModbusRtuFramer
from pymodbus.mei_message import ReadDeviceInformationRequest
from pymodbus.other_message import ReadExceptionStatusRequest, ReportSlaveIdRequest
from pymodbus.pdu import ExceptionResponse
from pymodbus.register_read_message import ReadHoldingRegistersRequest, ReadInputRegistersRequest
from pymodbus.register_read_message import ReadHoldingRegistersResponse
from pymodbus.register_read_message import ReadWriteMultipleRegistersRequest
from pymodbus.register_write_message import MaskWriteRegisterRequest, WriteMultipleRegistersRequest
from pymodbus.register_write_message import WriteMultipleRegistersResponse
from pymodbus.register_write_message import WriteSingleRegisterRequest
from pymodbus.register_write_message import WriteSingleRegisterResponse

TOOL = None  # the framers_tool binary: the command line's, or set by the importing script
FAILURES = []


def check(cond, what):
    if not cond:
        FAILURES.append(what)
        print("FAIL:", what)


def requests(unit):
    return [
        ReadCoilsRequest(1, 10, unit=unit),
        ReadDiscreteInputsRequest(0xC4, 22, unit=unit),
        ReadHoldingRegistersRequest(0x6B, 3, unit=unit),
        ReadInputRegistersRequest(8, 1, unit=unit),
        WriteSingleCoilRequest(0xAC, True, unit=unit),
        WriteSingleRegisterRequest(1, 3, unit=unit),
        WriteMultipleCoilsRequest(0x13, [True, False, True, True, False, False, True, True, True,
                                         False], unit=unit),
        WriteMultipleRegistersRequest(1, [0x000A, 0x0102], unit=unit),
        ReadWriteMultipleRegistersRequest(read_address=3, read_count=6, write_address=14,
                                          write_registers=[0xFF, 0xFF, 0xFF], unit=unit),
        MaskWriteRegisterRequest(4, 0xF2, 0x25, unit=unit),
        ReturnQueryDataRequest([0x1234, 0x5678], unit=unit),
        ReadFifoQueueRequest(0x4DE, unit=unit),
        ReadDeviceInformationRequest(1, 0, unit=unit),
        ReadExceptionStatusRequest(unit=unit),
        ReportSlaveIdRequest(unit=unit),
    ]


def exchanges(unit):
    """(request, response) pairs of the client role."""
    return [
        (ReadHoldingRegistersRequest(0x6B, 3, unit=unit),
         ReadHoldingRegistersResponse([0x022B, 0, 0x64], unit=unit)),
        (ReadCoilsRequest(0x13, 19, unit=unit),
         ReadCoilsResponse([True, False] * 9 + [True], unit=unit)),
        (WriteSingleRegisterRequest(1, 3, unit=unit), WriteSingleRegisterResponse(1, 3, unit=unit)),
        (WriteSingleCoilRequest(0xAC, True, unit=unit), WriteSingleCoilResponse(0xAC, True, unit=unit)),
        (WriteMultipleRegistersRequest(1, [10, 258], unit=unit),
         WriteMultipleRegistersResponse(1, 2, unit=unit)),
        (WriteMultipleCoilsRequest(0x13, [True] * 10, unit=unit),
         WriteMultipleCoilsResponse(0x13, 10, unit=unit)),
        (ReadHoldingRegistersRequest(0, 1, unit=unit), ExceptionResponse(3, 2, unit=unit)),
    ]


def pdu_of(message):
    return bytes([message.function_code]) + message.encode()


class Ours:
    """framers_tool in one mode and role: lines in, lines out."""

    def __init__(self, mode, role, address):
        self.p = subprocess.Popen([TOOL, mode, role, str(address)], stdin=subprocess.PIPE,
                                  stdout=subprocess.PIPE, text=True)

    def ask(self, line, replies=None):
        """Sends `line`; with `replies` (a count), reads that many lines."""
        self.p.stdin.write(line + "\n")
        self.p.stdin.flush()
        return [self.p.stdout.readline().strip() for _ in range(replies or 0)]

    def results(self, lines):
        """The results of `lines`, all of them: an `encode` line after them marks their end."""
        for line in lines:
            self.p.stdin.write(line + "\n")
        self.p.stdin.write("encode 1 07\n")
        self.p.stdin.flush()
        out = []
        while True:
            got = self.p.stdout.readline().strip()
            check(got != "", "framers_tool ended early")
            if got.startswith("encoded") or got == "":
                return out
            out.append(got)

    def close(self):
        self.p.stdin.close()
        self.p.wait()


def framer_of(kind, decoder):
    return (ModbusAsciiFramer if kind == "ascii" else ModbusRtuFramer)(decoder)


def pymodbus_parse(kind, decoder, data, unit):
    got = []
    framer_of(kind, decoder).processIncomingPacket(data, got.append, unit=unit, single=True)
    return got


def frame_line(unit, pdu):
    return f"frame {unit} {pdu.hex()}"


def splits(data, rng):
    """`data` as a socket may deliver it: every split in two, and random chunkings."""
    for cut in range(len(data) + 1):
        yield [data[:cut], data[cut:]]
    for _ in range(20):
        parts, at = [], 0
        while at < len(data):
            n = rng.randint(1, 40)
            parts.append(data[at:at + n])
            at += n
        yield parts


def main():
    rng = random.Random(25)
    for kind, mode in (("ascii", "ascii"), ("rtu", "rtu-tcp")):
        # 1. encoding: pymodbus's frames and ours, byte for byte
        enc = Ours(mode, "server", 1)
        for unit in (0, 1, 0x11, 247):
            for m in requests(unit) + [r for _, r in exchanges(unit)]:
                theirs = framer_of(kind, ServerDecoder()).buildPacket(m)
                ours = enc.ask(f"encode {unit} {pdu_of(m).hex()}", 1)[0]
                check(ours == "encoded " + theirs.hex(),
                      f"{kind} encode {type(m).__name__} unit {unit}: {ours} != {theirs.hex()}")
                # 2. pymodbus's server parses our request into the same message (but Return
                # Query Data: pymodbus 3.0 decodes diagnostics requests of 2 data bytes only)
                if type(m).__name__.endswith("Request") and m.function_code != 0x08:
                    raw = bytes.fromhex(ours.split()[1])
                    parsed = pymodbus_parse(kind, ServerDecoder(), raw, unit)
                    check(len(parsed) == 1 and pdu_of(parsed[0]) == pdu_of(m)
                          and parsed[0].unit_id == unit,
                          f"{kind}: pymodbus parses our {type(m).__name__} unit {unit}")
        enc.close()

        # 3. the server framer: pymodbus's requests back to back (this unit, broadcasts, others)
        stream, want = b"", []
        for unit in (0x11, 0x12, 0):
            for m in requests(unit):
                stream += framer_of(kind, ServerDecoder()).buildPacket(m)
                if unit in (0x11, 0):
                    want.append(frame_line(unit, pdu_of(m)))
        for parts in splits(stream, rng):
            server = Ours(mode, "server", 0x11)
            got = server.results([f"feed 7 {p.hex()}" for p in parts if p])
            server.close()
            check(got == want, f"{kind} server, split {[len(p) for p in parts]}: {got}")
            if got != want:
                break
        server = Ours(mode, "server", 0x11)
        check(server.results([f"put {stream.hex()}"]) == want, f"{kind} server by put()")
        server.close()

        # 4. the client framer: each response to the request sent, split anywhere
        client = Ours(mode, "client", 0)
        for request, response in exchanges(0x11):
            req = framer_of(kind, ClientDecoder()).buildPacket(request)
            rsp = framer_of(kind, ClientDecoder()).buildPacket(response)
            for cut in range(len(rsp) + 1):
                got = client.results([f"sent {req.hex()}", f"feed 64 {rsp[:cut].hex()}",
                                      f"feed 64 {rsp[cut:].hex()}"])
                check(got == [frame_line(0x11, pdu_of(response))],
                      f"{kind} client {type(response).__name__} cut {cut}: {got}")
            # pymodbus's client framer parses our response the same
            parsed = pymodbus_parse(kind, ClientDecoder(), rsp, 0x11)
            check(len(parsed) == 1 and pdu_of(parsed[0]) == pdu_of(response),
                  f"{kind}: pymodbus's client parses {type(response).__name__}")
        client.close()

    # 5. ASCII: garbage between frames, lowercase digits, and bad input refused by both
    good = ModbusAsciiFramer(ServerDecoder()).buildPacket(ReadHoldingRegistersRequest(0x6B, 3,
                                                                                      unit=0x11))
    bad_lrc = good[:-4] + (b"00" if good[-4:-2] != b"00" else b"01") + b"\r\n"
    non_hex = good[:5] + b"G" + good[6:]
    lower = good.lower()
    check(pymodbus_parse("ascii", ServerDecoder(), bad_lrc, 0x11) == [], "pymodbus: bad LRC refused")
    try:
        refused = pymodbus_parse("ascii", ServerDecoder(), non_hex, 0x11) == []
    except Exception:  # pymodbus 3.0: binascii.Error from a2b_hex
        refused = True
    check(refused, "pymodbus: a non-hex character refused")
    check(len(pymodbus_parse("ascii", ServerDecoder(), lower, 0x11)) == 1, "pymodbus: lowercase")
    line = good + b"garbage\x00\xff" + bad_lrc + non_hex + lower + b":1103" + good
    server = Ours("ascii", "server", 0x11)
    got = server.results([f"feed 5 {line.hex()}"])
    server.close()
    pdu = pdu_of(ReadHoldingRegistersRequest(0x6B, 3, unit=0x11))
    check(got == [frame_line(0x11, pdu), "error crc_mismatch", "error non_hex_character",
                  frame_line(0x11, pdu), "error missing_crlf", frame_line(0x11, pdu)],
          f"ascii server, garbage and bad frames: {got}")

    # 6. RTU over TCP: garbage (an unknown function) and a bad CRC between pymodbus's frames:
    # no silence ends them, the length rules resynchronise, every good frame is read
    reqs = requests(0x11)
    frames = [ModbusRtuFramer(ServerDecoder()).buildPacket(m) for m in reqs[:3]]
    corrupted = frames[0][:-1] + bytes([frames[0][-1] ^ 0xFF])
    line = frames[0] + b"\x11\x42\x00\x00" + frames[1] + corrupted + frames[2]
    for chunk in (1, 3, 8, 64):
        server = Ours("rtu-tcp", "server", 0x11)
        got = server.results([f"feed {chunk} {line.hex()}"])
        server.close()
        check([g for g in got if g.startswith("frame")] ==
              [frame_line(0x11, pdu_of(m)) for m in reqs[:3]] and "error crc_mismatch" in got,
              f"rtu over tcp, garbage and a bad CRC, chunks of {chunk}: {got}")

    if FAILURES:
        print(f"{len(FAILURES)} failures")
        return 1
    print("pymodbus framers: all agree")
    return 0


if __name__ == "__main__":
    TOOL = sys.argv[1]
    sys.exit(main())
