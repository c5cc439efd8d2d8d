"""Frames per second of the motionbus package's decoders against pymodbus's decode of the same
frames (issue 26): T-format ID3 response decode, Modbus FC03 response decode (PDU, and RTU ADU
with its CRC), BiSS-C frame decode; pymodbus 3.0's ClientDecoder on the FC03 PDU and its RTU
framer on the FC03 ADU. Each figure is the best of `--repeat` runs of `--seconds` each
(the machine may be shared: the best run is the least disturbed one).

    PYTHONPATH=build/python /usr/bin/python3 bench/python/bench.py [--seconds 0.5] [--repeat 5]
"""

import argparse
import time
from typing import Any, Callable, List

from pymodbus.factory import ClientDecoder
from pymodbus.framer.rtu_framer import ModbusRtuFramer

from motionbus import DataId, biss, modbus, tformat


def rate(f: Callable[[], Any], seconds: float, repeat: int) -> float:
    best = 0.0
    for _ in range(repeat):
        n = 0
        batch = 200
        start = time.perf_counter()
        end = start + seconds
        while True:
            for _ in range(batch):
                f()
            n += batch
            now = time.perf_counter()
            if now >= end:
                break
        best = max(best, n / (now - start))
    return best


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=0.5)
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()

    id3 = tformat.encode_response(tformat.Response(DataId.read_all, abs=12345, abm=7, enid=0x11))
    id3_request = tformat.encode_request(DataId.read_all)
    values = list(range(10))
    fc03_request = modbus.encode_read(3, 0, len(values))
    fc03 = modbus.encode_read_registers_response(3, values)
    fc03_adu = modbus.encode_rtu(1, fc03)
    bits = biss.encode_frame(biss.ABSYS_LAYOUT, biss.SlaveValues(single_turn=123456), line_delay=2)
    packed, count = biss.encode_frame_bytes(biss.ABSYS_LAYOUT, biss.SlaveValues(single_turn=123456), line_delay=2)

    big = list(range(125))
    fc03_125_request = modbus.encode_read(3, 0, 125)
    fc03_125_adu = modbus.encode_rtu(1, modbus.encode_read_registers_response(3, big))
    framer125 = ModbusRtuFramer(ClientDecoder())

    def pymodbus_rtu_125() -> None:
        framer125.processIncomingPacket(fc03_125_adu, sink.append, unit=1)
        assert sink[0].registers
        sink.clear()

    def motionbus_rtu_125() -> None:
        modbus.decode_response_for(fc03_125_request, modbus.decode_rtu(fc03_125_adu).pdu).registers

    decoder = ClientDecoder()
    assert decoder.decode(fc03).registers == values
    framer = ModbusRtuFramer(ClientDecoder())
    sink: List[Any] = []

    def pymodbus_rtu() -> None:
        framer.processIncomingPacket(fc03_adu, sink.append, unit=1)
        sink.clear()

    def motionbus_rtu() -> None:
        modbus.decode_response_for(fc03_request, modbus.decode_rtu(fc03_adu).pdu).registers

    cases = [
        ("tformat ID3 decode_response", lambda: tformat.decode_response(id3)),
        ("tformat ID3 decode_response_for", lambda: tformat.decode_response_for(id3_request, id3)),
        ("modbus FC03 decode_response_for (PDU)", lambda: modbus.decode_response_for(fc03_request, fc03)),
        ("modbus FC03 PDU + .registers", lambda: modbus.decode_response_for(fc03_request, fc03).registers),
        ("pymodbus FC03 ClientDecoder.decode (PDU)", lambda: decoder.decode(fc03).registers),
        ("modbus FC03 RTU ADU (CRC) + .registers", motionbus_rtu),
        ("pymodbus FC03 RTU framer (CRC)", pymodbus_rtu),
        ("modbus FC03 125 registers, RTU ADU + .registers", motionbus_rtu_125),
        ("pymodbus FC03 125 registers, RTU framer", pymodbus_rtu_125),
        ("biss ABSYS decode_frame_bytes", lambda: biss.decode_frame_bytes(packed, biss.ABSYS_LAYOUT, bit_count=count)),
        ("biss ABSYS decode_frame (list of bits)", lambda: biss.decode_frame(bits, biss.ABSYS_LAYOUT)),
    ]
    width = max(len(n) for n, _ in cases)
    for name, f in cases:
        r = rate(f, a.seconds, a.repeat)
        print(f"{name:<{width}}  {r / 1e3:9.1f} k frames/s  {1e6 / r:7.2f} us/frame")


if __name__ == "__main__":
    main()
