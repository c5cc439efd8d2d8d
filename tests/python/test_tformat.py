"""motionbus.tformat: round trips of random frames (Hypothesis), the checks against the
request, the receiver fed in chunks and byte by byte, the TS5700N8500 profile and emulator."""

from typing import List

import pytest
from hypothesis import given, strategies as st

import motionbus
import reference
from motionbus import DataId, DecodeError, IncompleteError, tformat
from motionbus.devices import ts5700n8500 as ts

IDS = list(DataId)


@st.composite
def responses(draw: st.DrawFn) -> tformat.Response:
    i = draw(st.sampled_from(IDS))
    return tformat.Response(i, sf=draw(st.integers(0, 15)) << 4, abs=draw(st.integers(0, (1 << 17) - 1)),
                            abm=draw(st.integers(0, 0xFFFF)), enid=draw(st.integers(0, 255)),
                            almc=draw(st.integers(0, 255)), address=draw(st.integers(0, 127)),
                            busy=draw(st.booleans()), edf=draw(st.integers(0, 255)))


def layout_view(r: tformat.Response) -> tuple:
    """The fields the response's layout carries (others decode as 0)."""
    return (r.id, r.cf, r.size)


@given(responses())
def test_response_round_trip(r: tformat.Response) -> None:
    frame = tformat.encode_response(r)
    assert len(frame) == tformat.response_size(r.id) == r.size
    assert frame[-1] == reference.crc8_tformat(frame[:-1])
    d = tformat.decode_response(frame)
    assert layout_view(d) == layout_view(r)
    assert tformat.encode_response(d) == frame  # every field the layout carries survived
    assert tformat.decode_response(frame + b"\x00\x01", exact=False) == d
    with pytest.raises(DecodeError) as e:
        tformat.decode_response(frame + b"\x00", exact=True)
    assert e.value.name == "wrong_length"
    assert "Response(id=DataId." in repr(d)


@given(responses(), st.data())
def test_corrupted_response_raises_with_evidence(r: tformat.Response, d: st.DataObject) -> None:
    frame = bytearray(tformat.encode_response(r))
    i = d.draw(st.integers(1, len(frame) - 1))
    frame[i] ^= 1 << d.draw(st.integers(0, 7))
    try:
        tformat.decode_response(frame)
    except DecodeError as e:
        assert e.code in (motionbus.Errc.crc_mismatch, motionbus.Errc.reserved_bits, motionbus.Errc.out_of_range)
        if e.code == motionbus.Errc.crc_mismatch:
            assert e.expected == reference.crc8_tformat(bytes(frame[:-1])) and e.received == frame[-1]
    else:  # a flip in a field the check cannot see is impossible: XOR CRC catches any 1-bit flip
        raise AssertionError("a one-bit flip passed")


def test_short_input_is_incomplete() -> None:
    frame = tformat.encode_response(tformat.Response(DataId.read_all, abs=5))
    with pytest.raises(IncompleteError) as e:
        tformat.decode_response(frame[:4])
    assert e.value.needed == 7 and e.value.name == "truncated"


@given(st.sampled_from(IDS), st.integers(0, 127), st.integers(0, 255))
def test_request_round_trip(i: DataId, address: int, data: int) -> None:
    q = tformat.encode_request(i, address, data)
    assert len(q) == tformat.request_size(i)
    assert q[0] == tformat.control_field(i)
    d = tformat.decode_request(q)
    assert d.id == i and d.cf == q[0] and d.size == len(q)
    if i in (DataId.eeprom_read, DataId.eeprom_write):
        assert d.address == address and d.crc == reference.crc8_tformat(q[:-1])
    if i == DataId.eeprom_write:
        assert d.edf == data
    assert "Request(" in repr(d)


def test_response_checked_against_request() -> None:
    q = tformat.encode_request(DataId.eeprom_read, 5)
    ok = tformat.encode_response(tformat.Response(DataId.eeprom_read, address=5, edf=0x42))
    assert tformat.decode_response_for(q, ok).edf == 0x42
    other = tformat.encode_response(tformat.Response(DataId.eeprom_read, address=6))
    with pytest.raises(DecodeError) as e:
        tformat.decode_response_for(q, other)
    assert (e.value.name, e.value.expected, e.value.received) == ("address_mismatch", 5, 6)
    alarm = tformat.encode_response(tformat.Response(DataId.read_all, sf=0x40))
    with pytest.raises(DecodeError) as e:
        tformat.decode_response_for(tformat.encode_request(DataId.read_all), alarm)
    assert e.value.code == motionbus.Errc.tformat_communication_alarm
    r = tformat.decode_response(alarm)
    assert r.ca0 and not r.ca1 and not r.ea0 and not r.ea1


def test_helpers() -> None:
    assert tformat.control_field(DataId.read_all) == 0x1A
    assert tformat.status_field(0x04) == 0x10 and tformat.status_field(0x80, ca1=True) == 0xA0
    assert tformat.absolute_position(5, 2) == (2 << 17) | 5
    assert tformat.resolution_for_enid(0x17) == (23, 16) and tformat.resolution_for_enid(0x99) is None
    r = tformat.decode_response(tformat.encode_response(tformat.Response(3, almc=0x41)))
    assert r.alarms == [motionbus.AlmcBit.os, motionbus.AlmcBit.be]
    assert tformat.MAX_REQUEST_SIZE == 4 and tformat.MAX_RESPONSE_SIZE == 11


@given(st.lists(responses(), min_size=1, max_size=5), st.integers(1, 11))
def test_receiver_chunks_and_bytes_agree(rs: List[tformat.Response], chunk: int) -> None:
    stream = b"".join(tformat.encode_response(r) for r in rs)
    rx = tformat.Receiver(check_against_request=False)
    got: list = []
    for i in range(0, len(stream), chunk):
        got += rx.feed(stream[i:i + chunk])
    rx2 = tformat.Receiver(check_against_request=False)
    by_byte = [e for b in stream for e in rx2.put(b)]
    assert got == by_byte
    assert [g.size for g in got] == [r.size for r in rs]
    assert rx.pending == 0 and rx.dropped == 0 and rx.idle() is None


def test_receiver_echo_and_rejects() -> None:
    q = tformat.encode_request(DataId.read_abs)
    good = tformat.encode_response(tformat.Response(DataId.read_abs, abs=77))
    bad = bytearray(good)
    bad[-1] ^= 0xFF
    rx = tformat.Receiver(tformat.Echo.expected)
    rx.sent(q)
    events = rx.feed(q + good)
    assert [e.abs for e in events] == [77] and rx.echoes_skipped == 1 and not rx.echo_missed
    rx.sent(q)
    events = rx.feed(q + bytes(bad))
    assert isinstance(events[0], DecodeError) and events[0].name == "crc_mismatch"
    rx.feed(good[:3])
    err = rx.idle()
    assert isinstance(err, DecodeError) and err.name == "truncated"
    assert rx.dropped >= 3


def test_ts5700n8500_emulator_and_profile() -> None:
    e = ts.Emulator()
    e.set_position(1000, 3)
    e.rotate(1 << 17)
    assert (e.abs, e.abm) == (1000, 4)
    r = tformat.decode_response(e.respond(tformat.encode_request(DataId.read_all), 0))
    assert (r.abs, r.abm, r.enid) == (1000, 4, ts.ENID)
    e.set_condition(motionbus.AlmcBit.be, True)
    e.set_speed_rpm(0)
    e.set_temperature(25)
    assert e.almc & 0x40
    assert e.respond(b"\x00", 0) == b""  # bad sync code: silence
    abnormal = tformat.decode_response(e.respond(tformat.encode_request(DataId.read_abs), 0, delimiter_error=True))
    assert abnormal.id == DataId.read_all and abnormal.ca1
    now = 0
    for step in ts.write_verify_plan(0, 3, 0x5A):
        reply = e.respond(step.request, now)
        now += step.wait_after_us + 1
        if step.verify:
            assert tformat.decode_response(reply).edf == step.expected_edf == 0x5A
    assert e.eeprom(0, 3) == 0x5A and not e.busy(10**9) and e.page == 0
    assert len(ts.reset_plan(DataId.reset_errors)) == 10 and len(ts.page_change_plan(7)) == 1
    assert ts.writable(7, 4) and not ts.writable(7, 5)
    assert ts.encode_overheat_threshold(90) == ts.OVERHEAT_FACTORY == e.overheat_threshold
    assert ts.decode_overheat_threshold(0xDA) == 90 and ts.decode_overheat_threshold(0x10) is None
    assert ts.decode_temperature(0xFF) == -1
    table = ts.alarm_table()
    assert [a.symbol for a in table] == ["OS", "FS", "CE", "OF", "OH", "ME", "BE", "BA"]
    ce = table[2]
    assert ce.latch == ts.LatchRule.by_speed and ce.latched_at(50) and not ce.latched_at(-150)
    assert ce.flag == motionbus.AlmcBit.ce and ce.name and ce.action and "AlarmInfo(" in repr(ce)
    assert (ts.SINGLE_TURN_BITS, ts.MULTI_TURN_BITS, ts.COUNTS_PER_TURN) == (17, 16, 1 << 17)
    assert ts.STANDARD_BIT_RATE == 2500000 and ts.TEMPERATURE_PAGE == 7
    assert (ts.OVERHEAT_ADDRESS, ts.TEMPERATURE_ADDRESS) == (4, 5)
    with pytest.raises(motionbus.EncodeError):
        ts.reset_plan(DataId.read_abs)
    with pytest.raises(motionbus.EncodeError):
        ts.encode_overheat_threshold(200)


@given(st.lists(st.sampled_from(IDS), min_size=1, max_size=6), st.integers(1, 16))
def test_listener_pairs_requests_and_responses(ids: List[DataId], chunk: int) -> None:
    e = ts.Emulator()
    e.set_position(4321, 2)
    stream = b""
    for i in ids:
        q = tformat.encode_request(i, 1, 2)
        stream += q + e.respond(q, 0)
    ls = tformat.Listener()
    events = [x for k in range(0, len(stream), chunk) for x in ls.feed(stream[k:k + chunk])] + ls.idle()
    ls2 = tformat.Listener()
    assert [x for b in stream for x in ls2.put(b)] + ls2.idle() == events
    requests = [h for h in events if not h.is_response]
    responses = [h for h in events if h.is_response]
    assert [h.request.id for h in requests] == ids
    assert len(responses) == len(ids) and all(h.request is None and h.request_error is None for h in responses)
    for h, i in zip(responses, ids):
        assert h.response is not None and h.response.id == i and not h.id3_reply
        assert h.bytes == tformat.encode_response(h.response)
    assert ls.dropped == 0 and ls.pending == 0 and not ls.expecting_response


def test_listener_flags_abnormal_requests_and_bad_responses() -> None:
    e = ts.Emulator()
    bad_parity = bytes([tformat.control_field(DataId.read_abs) ^ 0x80])
    ls = tformat.Listener()
    events = ls.feed(bad_parity + e.respond(bad_parity, 0))
    assert events[0].request_error == motionbus.Errc.tformat_parity and events[0].request.cf == bad_parity[0]
    assert events[1].is_response and events[1].id3_reply and "Heard(" in repr(events[1])
    q = tformat.encode_request(DataId.read_abs)
    reply = bytearray(e.respond(q, 0))
    reply[-1] ^= 1
    ls.feed(q)
    assert ls.expecting_response
    rejected = ls.feed(bytes(reply)) + ls.idle()
    assert isinstance(rejected[0], DecodeError) and rejected[0].name == "crc_mismatch"


@given(responses(), st.integers(0, 40), st.data())
def test_line_samples_round_trip(r: tformat.Response, idle: int, d: st.DataObject) -> None:
    frame = tformat.encode_response(r)
    bits = tformat.encode_line(frame, idle)
    assert len(bits) == idle + 10 * len(frame)
    assert bits[idle:idle + 10] == [0] + [(frame[0] >> i) & 1 for i in range(8)] + [1]  # LSB first
    got = tformat.decode_response_line(bits + [1, 1])
    assert (got.start_bit, got.end) == (idle, len(bits))
    assert tformat.encode_response(got.frame) == frame and "LineFrame(" in repr(got)
    k = idle + 10 * d.draw(st.integers(0, len(frame) - 1)) + 9  # a delimiter
    broken = list(bits)
    broken[k] = 0
    with pytest.raises(DecodeError) as e:
        tformat.decode_response_line(broken)
    assert e.value.unit == "bits"
    q = tformat.encode_request(r.id, 3, 4)
    req = tformat.decode_request_line(tformat.encode_line(q, 5))
    assert req.frame.id == r.id and req.start_bit == 5
