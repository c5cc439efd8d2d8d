#!/usr/bin/env python3
"""The timing diagrams of docs/timing/: WaveJSON made from the library's own encoders, through
the Python package (docs/python.md), for WaveDrom to render (tools/scripts/timing_diagrams.sh).

    timing_diagrams.py --write DIR    write DIR/<name>.json for every diagram
    timing_diagrams.py --check DIR    exit 1 when a file in DIR differs from what the encoders give

Every wave on a line comes from an encoder (tformat.encode_line, modbus.encode_rtu,
biss.encode_frame) and is decoded back here before it is drawn: a diagram that does not
decode to the values it names is not written. The pytest suite (tests/python/
test_timing_diagrams.py) runs the check, so a change to an encoder that leaves a diagram stale
fails the test command; the SVGs carry the SHA-256 of the WaveJSON they were rendered from.
"""

import argparse
import json
import os
import sys
from typing import Dict, List, Sequence, Tuple

import motionbus
from motionbus import biss, modbus, tformat

Diagram = Dict[str, object]


# ---------------------------------------------------------------------------------------------
# WaveJSON helpers


def wave_of_levels(levels: Sequence[int]) -> str:
    """'0'/'1' per tick, '.' where the level repeats."""
    out = []
    prev = None
    for v in levels:
        c = '1' if v else '0'
        out.append('.' if c == prev else c)
        prev = c
    return ''.join(out)


def lane_of_spans(spans: Sequence[Tuple[int, str, str]]) -> Tuple[str, List[str]]:
    """A data lane from (ticks, kind, label) spans; kind is a WaveDrom data character ('=',
    '2'..'9') or 'z' (nothing on the lane), label is drawn inside data spans."""
    wave = []
    data = []
    for ticks, kind, label in spans:
        if ticks <= 0:
            continue
        wave.append(kind + '.' * (ticks - 1))
        if kind not in ('z', 'x', '0', '1'):
            data.append(label)
    return ''.join(wave), data


def merge_dots(wave: str) -> str:
    """Join adjacent spans of the same plain state ('zz' -> 'z.')."""
    out: List[str] = []
    for c in wave:
        if out and c in 'zx01' and _last_state(out) == c:
            out.append('.')
        else:
            out.append(c)
    return ''.join(out)


def _last_state(out: List[str]) -> str:
    for c in reversed(out):
        if c != '.':
            return c
    return ''


def data_lane(name: str, spans: Sequence[Tuple[int, str, str]]) -> Dict[str, object]:
    wave, data = lane_of_spans(spans)
    lane: Dict[str, object] = {'name': name, 'wave': merge_dots(wave)}
    if data:
        lane['data'] = data
    return lane


def node_string(length: int, marks: Dict[int, str]) -> str:
    """A WaveDrom node string: '.' everywhere, a letter at the given ticks."""
    s = ['.'] * length
    for tick, letter in marks.items():
        s[tick] = letter
    return ''.join(s)


# ---------------------------------------------------------------------------------------------
# T-format (docs/tformat.md §1-3): fields of 10 bits on one half-duplex line at 2.5 Mbps.

TF_BIT_NS = 400            # 2.5 Mbps
TF_TURNAROUND_BITS = 8     # 3.2 us: the order of the TS5700N8500's turnaround (about 3 us)
TF_LEAD_BITS = 2           # idle before the request and after the response


def _tf_field_labels(frame: bytes, names: Sequence[str]) -> List[str]:
    return ['%s %02X' % (n, b) for n, b in zip(names, frame)]


def tformat_exchange(title: str, request: bytes, req_names: Sequence[str], response: bytes,
                     resp_names: Sequence[str]) -> Diagram:
    """A request and its response on the line, one tick a field (10 bits, 4 us)."""
    line = (tformat.encode_line(request, TF_LEAD_BITS)
            + tformat.encode_line(response, TF_TURNAROUND_BITS) + [1] * TF_LEAD_BITS)
    # The line decodes back to the frames drawn, the response where the diagram puts it.
    q = tformat.decode_request_line(line, 0)
    r = tformat.decode_response_line(line, q.end)
    assert tformat.encode_request(int(q.frame.id), q.frame.address, q.frame.edf)[:len(request)] \
        == request, title
    assert isinstance(r.frame, tformat.Response), title
    assert tformat.encode_response(r.frame) == response, title
    assert r.start_bit == TF_LEAD_BITS + 10 * len(request) + TF_TURNAROUND_BITS, title
    spans = ([(1, 'z', '')]
             + [(1, '5' if 0 < i == len(request) - 1 else '3', l)
                for i, l in enumerate(_tf_field_labels(request, req_names))]
             + [(1, 'z', '')]
             + [(1, '4' if i + 1 < len(response) else '5', l)
                for i, l in enumerate(_tf_field_labels(response, resp_names))]
             + [(1, 'z', '')])
    ticks = sum(s[0] for s in spans)
    lanes: List[object] = [
        dict(data_lane('line', spans),
             node=node_string(ticks, {1 + len(request): 'A', 2 + len(request): 'B'})),
        data_lane('sender', [(1, 'z', ''), (len(request), '3', 'master'), (1, 'z', ''),
                             (len(response), '4', 'encoder'), (1, 'z', '')]),
    ]
    foot = 'one tick a field (10 bits, 4 us); turnaround about 3 us'
    return {'signal': lanes, 'edge': ['A<->B turnaround'], 'head': {'text': title},
            'foot': {'text': foot}, 'config': {'hscale': 2}}


def tformat_field() -> Diagram:
    """One field, bit by bit: CF of ID3 (0x1A)."""
    cf = tformat.encode_request(3)
    bits = tformat.encode_line(cf, 1) + [1]
    assert tformat.decode_request_line(bits, 0).frame.id == motionbus.DataId.read_all
    labels = (['start'] + ['b%d' % i for i in range(8)] + ['delim'])
    lanes = [
        {'name': 'line', 'wave': wave_of_levels(bits)},
        data_lane('bit', [(1, 'z', '')] + [(1, '2' if i in (0, 9) else '=', l)
                                           for i, l in enumerate(labels)] + [(1, 'z', '')]),
        data_lane('CF bits', [(1, 'z', ''), (1, 'z', ''), (3, '3', 'sync 010'),
                              (4, '4', 'Data ID 3'), (1, '5', 'parity'), (1, 'z', ''),
                              (1, 'z', '')]),
    ]
    return {'signal': lanes, 'head': {'text': 'T-format field: CF of ID3 = 0x%02X' % cf[0]},
            'foot': {'text': '400 ns a bit at 2.5 Mbps, LSB first; the idle line is 1'},
            'config': {'hscale': 2}}


def tformat_diagrams() -> Dict[str, Diagram]:
    d: Dict[str, Diagram] = {}
    d['tformat_field'] = tformat_field()
    req = tformat.encode_request(0)
    resp = tformat.encode_response(tformat.Response(0, abs=123456))
    d['tformat_id0'] = tformat_exchange(
        'T-format ID0: read the absolute position (123456)', req, ['CF'], resp,
        ['CF', 'SF', 'ABS0', 'ABS1', 'ABS2', 'CRC'])
    req = tformat.encode_request(0xD, 5)
    resp = tformat.encode_response(tformat.Response(0xD, address=5, edf=0x12))
    d['tformat_eeprom_read'] = tformat_exchange(
        'T-format ID D: EEPROM read of address 5 (data 0x12)', req, ['CF', 'ADF', 'CRC'], resp,
        ['CF', 'ADF', 'EDF', 'CRC'])
    req = tformat.encode_request(6, 5, 0x34)
    resp = tformat.encode_response(tformat.Response(6, address=5, edf=0x34))
    d['tformat_eeprom_write'] = tformat_exchange(
        'T-format ID6: EEPROM write of 0x34 to address 5', req, ['CF', 'ADF', 'EDF', 'CRC'], resp,
        ['CF', 'ADF', 'EDF', 'CRC'])
    req = tformat.encode_request(3)
    resp = tformat.encode_response(tformat.Response(3, abs=123456, enid=0x11, abm=4660,
                                                    almc=0xC0,
                                                    sf=tformat.status_field(0xC0)))
    d['tformat_id3'] = tformat_exchange(
        'T-format ID3: read all (position 123456, multi-turn 4660, battery alarms)', req, ['CF'],
        resp, ['CF', 'SF', 'ABS0', 'ABS1', 'ABS2', 'ENID', 'ABM0', 'ABM1', 'ABM2', 'ALMC', 'CRC'])
    return d


# ---------------------------------------------------------------------------------------------
# Modbus RTU (docs/modbus.md §1): characters of 11 bits (8E1); frames apart by t3.5 or more,
# characters within a frame by t1.5 or less. One tick = half a character.

MB_BAUD = 19200
MB_CHAR_BITS = 11


def modbus_adu(title: str, request: bytes, response: bytes, req_names: Sequence[str],
               resp_names: Sequence[str], gap_after: int) -> Diagram:
    """Request, t3.5 silence, response; one inter-character gap (below t1.5) drawn in the
    response after character `gap_after`."""
    q = modbus.decode_rtu(request)
    r = modbus.decode_rtu(response)
    assert modbus.encode_rtu(q.slave, q.pdu) == request and modbus.encode_rtu(r.slave, r.pdu) \
        == response, title
    char_us = MB_CHAR_BITS * 1e6 / MB_BAUD
    t15 = modbus.t15_us(MB_BAUD)
    t35 = modbus.t35_us(MB_BAUD)
    half = char_us / 2
    t35_ticks = int(round(t35 / half))     # 7 at 19200 baud 8E1
    gap_ticks = int(t15 / half) - 1        # a gap shorter than t1.5: allowed within a frame
    assert t35_ticks == 7 and gap_ticks >= 1, (t35, t15, char_us)

    def chars(frame: bytes, names: Sequence[str], colour: str,
              gap_at: int) -> List[Tuple[int, str, str]]:
        out: List[Tuple[int, str, str]] = []
        for i, (b, n) in enumerate(zip(frame, names)):
            kind = '5' if i >= len(frame) - 2 else colour
            out.append((2, kind, '%s %02X' % (n, b)))
            if i == gap_at:
                out.append((gap_ticks, 'z', ''))
        return out

    req_spans = chars(request, req_names, '3', -1)
    resp_spans = chars(response, resp_names, '4', gap_after)
    spans = ([(t35_ticks, 'z', '')] + req_spans + [(t35_ticks, 'z', '')] + resp_spans
             + [(t35_ticks, 'z', '')])
    ticks = sum(s[0] for s in spans)
    req_end = t35_ticks + 2 * len(request)
    resp_start = req_end + t35_ticks
    gap_start = resp_start + 2 * (gap_after + 1)
    marks = {0: 'A', t35_ticks: 'B', req_end: 'C', resp_start: 'D', gap_start: 'E',
             gap_start + gap_ticks: 'F', ticks - t35_ticks: 'G', ticks - 1: 'H'}
    lanes: List[object] = [
        dict(data_lane('line', spans), node=node_string(ticks, marks)),
        data_lane('frame', [(t35_ticks, 'z', ''),
                            (2 * len(request), '3', 'request: slave, PDU, CRC'),
                            (t35_ticks, 'z', ''),
                            (2 * len(response) + gap_ticks, '4', 'response'),
                            (t35_ticks, 'z', '')]),
    ]
    edges = ['A<->B t3.5 or more', 'C<->D t3.5 or more', 'E<->F under t1.5',
             'G<->H t3.5 or more']
    foot = ('%d baud 8E1: a character of 11 bits lasts %.0f us; t1.5 = %d us, t3.5 = %d us '
            '(one tick = half a character)' % (MB_BAUD, char_us, t15, t35))
    return {'signal': lanes, 'edge': edges, 'head': {'text': title}, 'foot': {'text': foot},
            'config': {'hscale': 1}}


def modbus_diagrams() -> Dict[str, Diagram]:
    d: Dict[str, Diagram] = {}
    req = modbus.encode_rtu(1, modbus.encode_read(3, 0x006B, 1))
    resp = modbus.encode_rtu(1, modbus.encode_read_registers_response(3, [0x022B]))
    d['modbus_rtu_fc03'] = modbus_adu(
        'Modbus RTU: FC03 read of register 0x006B, slave 1', req, resp,
        ['slave', 'FC', 'addr hi', 'addr lo', 'qty hi', 'qty lo', 'CRC lo', 'CRC hi'],
        ['slave', 'FC', 'count', 'reg hi', 'reg lo', 'CRC lo', 'CRC hi'],
        gap_after=2)
    return d


# ---------------------------------------------------------------------------------------------
# BiSS-C (docs/biss.md §1): MA clocks, SLO answers; one tick = one MA period.

BISS_LEAD = 2       # MA idle before the frame
BISS_TIMEOUT = 6    # ticks of timeout drawn after the last clock
BISS_SHOWN = 3      # position bits drawn at each end; the ones between are cut ('|' on every lane)


def biss_frame(title: str, values: 'biss.SlaveValues', line_delay: int, ack_bits: int, cds: bool,
               cdm: bool) -> Diagram:
    layout = biss.ABSYS_LAYOUT
    sl = biss.encode_frame(layout, values, line_delay=line_delay, ack_bits=ack_bits, cds=cds,
                           timeout_bits=0)
    f = biss.decode_frame(sl, layout)
    s = f.slaves[0]
    assert (f.line_delay, f.start - f.line_delay, f.cds, s.single_turn, s.crc_ok) == \
        (line_delay, ack_bits, cds, values.single_turn, True), title
    clocks = len(sl)
    assert f.end == clocks, (f.end, clocks)
    # The timeout as the encoder gives it: SLO low (busy) after the CRC.
    with_timeout = biss.encode_frame(layout, values, line_delay=line_delay, ack_bits=ack_bits,
                                     cds=cds, timeout_bits=BISS_TIMEOUT - 2)
    assert with_timeout[:clocks] == sl, title
    data_bits = layout.data_bits
    crc_bits = layout.frame_bits - data_bits - 2
    # SLO one level a tick: idle, the encoder's samples (one per MA period), the timeout (SLO
    # low: busy), idle. The middle of the position is cut: BISS_SHOWN bits at each end, one
    # gap tick between them.
    first_data = BISS_LEAD + f.start + 2            # after Start and CDS
    cut_from = first_data + BISS_SHOWN
    cut_to = first_data + data_bits - BISS_SHOWN
    full = [1] * BISS_LEAD + with_timeout + [1, 1] + ([1] if cdm else [])
    slo = full[:cut_from] + [full[cut_from - 1]] + full[cut_to:]
    slo_wave = list(wave_of_levels(slo))
    slo_wave[cut_from] = '|'
    shown_clocks = clocks - (cut_to - cut_from) + 1
    # MA: high, then one clock per SL sample (falls at the period's start, rises in its middle),
    # then the timeout: MA high (CDM = 0) or held low (CDM = 1).
    ma = ['1'] + ['.'] * (BISS_LEAD - 1) + ['n'] + ['.'] * (shown_clocks - 1) \
        + [('0' if cdm else '1')] + ['.'] * (BISS_TIMEOUT - 1) + (['1'] if cdm else [])
    ma[cut_from] = '|'
    ticks = len(slo)
    assert len(ma) == ticks, (len(ma), ticks)
    spans = [(BISS_LEAD, 'z', ''), (line_delay, '2', 'delay'),
             (ack_bits, '3', 'Ack'), (1, '3', 'Start'), (1, '6', 'CDS'),
             (2 * BISS_SHOWN + 1, '4', 'position %d' % s.single_turn),
             (1, '6', 'nE'), (1, '6', 'nW'), (crc_bits, '5', 'CRC6 %02X' % s.crc),
             (BISS_TIMEOUT - 2, '7', 'timeout'), (2 + int(cdm), 'z', '')]
    field_wave, field_data = lane_of_spans(spans)
    field = list(merge_dots(field_wave))
    field[cut_from] = '|'
    end_of_clocks = BISS_LEAD + shown_clocks
    marks = {end_of_clocks: 'A', end_of_clocks + BISS_TIMEOUT - 2: 'B'}
    lanes: List[object] = [
        {'name': 'MA', 'wave': ''.join(ma)},
        {'name': 'SLO', 'wave': ''.join(slo_wave), 'node': node_string(ticks, marks)},
        {'name': 'field', 'wave': ''.join(field), 'data': field_data},
    ]
    cdm_text = ('CDM 1: MA held low through the timeout' if cdm
                else 'CDM 0: MA high through the timeout')
    foot = ('AMO ABSYS layout (32-bit position, bits %d..%d cut), one tick = one MA period; %s'
            % (31 - BISS_SHOWN, BISS_SHOWN, cdm_text))
    return {'signal': lanes, 'edge': ['A<->B timeout'], 'head': {'text': title},
            'foot': {'text': foot}, 'config': {'hscale': 1}}


def biss_diagrams() -> Dict[str, Diagram]:
    d: Dict[str, Diagram] = {}
    d['biss_frame'] = biss_frame(
        'BiSS-C sensor data frame: line delay 2, Ack 1, CDS 0, position 123456, CDM 0',
        biss.SlaveValues(single_turn=123456), line_delay=2, ack_bits=1, cds=False, cdm=False)
    d['biss_frame_processing'] = biss_frame(
        'BiSS-C frame with processing time: Ack 4 clocks, CDS 1, CDM 1',
        biss.SlaveValues(single_turn=123460), line_delay=1, ack_bits=4, cds=True, cdm=True)
    return d


# ---------------------------------------------------------------------------------------------


def all_diagrams() -> Dict[str, Diagram]:
    d: Dict[str, Diagram] = {}
    d.update(tformat_diagrams())
    d.update(modbus_diagrams())
    d.update(biss_diagrams())
    return d


def to_text(diagram: Diagram) -> str:
    return json.dumps(diagram, indent=1, sort_keys=True) + '\n'


def main(argv: Sequence[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument('--write', metavar='DIR')
    g.add_argument('--check', metavar='DIR')
    a = p.parse_args(argv)
    diagrams = all_diagrams()
    if a.write:
        os.makedirs(a.write, exist_ok=True)
        for name, diagram in diagrams.items():
            with open(os.path.join(a.write, name + '.json'), 'w', encoding='utf-8') as f:
                f.write(to_text(diagram))
        print('\n'.join(sorted(diagrams)))
        return 0
    stale = []
    for name, diagram in diagrams.items():
        path = os.path.join(a.check, name + '.json')
        try:
            with open(path, encoding='utf-8') as f:
                ok = f.read() == to_text(diagram)
        except OSError:
            ok = False
        if not ok:
            stale.append(path)
    for path in stale:
        print('stale or missing: %s (tools/scripts/timing_diagrams.sh)' % path, file=sys.stderr)
    return 1 if stale else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
