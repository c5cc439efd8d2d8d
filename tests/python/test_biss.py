"""motionbus.biss: random frames of random layouts and chains round-tripped through the
encoder and the decoder (bits, bytes and words), compared with a frame built sample by sample
in plain Python; register access between the control master and slave; EDS; ABSYS."""

from typing import Dict, List

import pytest
from hypothesis import given, strategies as st

import motionbus
import reference
from motionbus import DecodeError, EncodeError, IncompleteError, biss
from motionbus.devices import absys


@st.composite
def layouts(draw: st.DrawFn) -> biss.SlaveLayout:
    mt = draw(st.integers(0, 24))
    st_bits = draw(st.integers(1, 40 - mt if mt < 40 else 1))
    width = draw(st.sampled_from([0, 4, 6, 8, 16]))
    poly = draw(st.integers(1, (1 << width) - 1)) if width else 0
    return biss.SlaveLayout(multi_turn_bits=mt, single_turn_bits=st_bits,
                            alignment_bits=draw(st.integers(0, 4)), has_error=draw(st.booleans()),
                            has_warning=draw(st.booleans()),
                            crc=biss.CrcFormat(width, poly, 0, draw(st.booleans())))


def values_for(draw: st.DrawFn, l: biss.SlaveLayout) -> biss.SlaveValues:
    return biss.SlaveValues(multi_turn=draw(st.integers(0, (1 << l.multi_turn_bits) - 1)),
                            single_turn=draw(st.integers(0, (1 << l.single_turn_bits) - 1)),
                            ne=draw(st.booleans()), nw=draw(st.booleans()))


@given(st.lists(layouts(), min_size=1, max_size=biss.MAX_CHAIN), st.data(), st.integers(0, 30),
       st.integers(1, 20), st.booleans(), st.integers(0, 16))
def test_chain_round_trip_in_every_capture_form(chain: List[biss.SlaveLayout], d: st.DataObject, delay: int,
                                                ack: int, cds: bool, timeout: int) -> None:
    vals = [values_for(d.draw, l) for l in chain]
    bits = biss.encode_frame(chain, vals, line_delay=delay, ack_bits=ack, cds=cds, timeout_bits=timeout)
    assert len(bits) == biss.encoded_bits(chain, line_delay=delay, ack_bits=ack, timeout_bits=timeout)
    f = biss.decode_frame(bits, chain)
    assert (f.line_delay, f.ack_bits, f.cds) == (delay, ack, cds)
    assert f.end == len(bits) - timeout
    for got, want, l in zip(f.slaves, vals, chain):
        assert got.crc_ok
        assert (got.multi_turn if l.multi_turn_bits else 0, got.single_turn) == (want.multi_turn, want.single_turn)
        assert got.error == (l.has_error and not want.ne)
        assert got.warning == (l.has_warning and not want.nw)
    for order in (biss.BitOrder.msb_first, biss.BitOrder.lsb_first):
        packed, n = biss.encode_frame_bytes(chain, vals, line_delay=delay, ack_bits=ack, cds=cds,
                                            timeout_bits=timeout, order=order)
        assert n == len(bits)
        assert biss.decode_frame_bytes(packed, chain, bit_count=n, order=order) == f
    words = [int.from_bytes(packed[i:i + 2].ljust(2, b"\0"), "big") for i in range(0, len(packed), 2)]
    msb, _ = biss.encode_frame_bytes(chain, vals, line_delay=delay, ack_bits=ack, cds=cds, timeout_bits=timeout)
    words = [int.from_bytes(msb[i:i + 2].ljust(2, b"\0"), "big") for i in range(0, len(msb), 2)]
    assert biss.decode_frame_words(words, chain, word_bits=16, bit_count=len(bits)) == f


@given(st.integers(0, (1 << 32) - 1), st.booleans(), st.booleans(), st.integers(0, 20), st.integers(1, 8),
       st.booleans())
def test_absys_frame_matches_a_plain_python_frame(pos: int, ne: bool, nw: bool, delay: int, ack: int,
                                                  cds: bool) -> None:
    ref = reference.biss_frame(pos, 32, ne, nw, delay, ack, cds)
    bits = biss.encode_frame(biss.ABSYS_LAYOUT, biss.SlaveValues(single_turn=pos, ne=ne, nw=nw),
                             line_delay=delay, ack_bits=ack, cds=cds)
    assert bits == ref
    f = biss.decode_frame(ref, absys.LAYOUT)
    s = f.slaves[0]
    assert (s.single_turn, s.data, s.ne, s.nw, s.crc) == (pos, pos, ne, nw, reference.crc6_biss(ref[delay + ack + 2:-6]))


@given(st.data())
def test_corrupted_frame_gives_crc_evidence(d: st.DataObject) -> None:
    bits = biss.encode_frame(biss.ABSYS_LAYOUT, biss.SlaveValues(single_turn=d.draw(st.integers(0, 2**32 - 1))),
                             line_delay=2)
    i = d.draw(st.integers(5, len(bits) - 1))  # data, nE, nW or CRC
    bits[i] ^= 1
    with pytest.raises(DecodeError) as e:
        biss.decode_frame(bits, biss.ABSYS_LAYOUT)
    assert e.value.name == "crc_mismatch" and e.value.unit == "bits"
    payload = bits[5:39]  # after 2 idle samples, Ack, Start and CDS: 32 data bits, nE, nW
    assert e.value.expected == reference.crc6_biss(payload)
    assert e.value.received == int("".join(map(str, bits[39:45])), 2)


def test_decode_failures() -> None:
    with pytest.raises(DecodeError) as e:
        biss.decode_frame([1] * 100, biss.ABSYS_LAYOUT, max_line_delay=10)
    assert e.value.name == "no_ack"
    with pytest.raises(DecodeError) as e:
        biss.decode_frame([1, 0] + [0] * 100, biss.ABSYS_LAYOUT, max_ack_bits=10)
    assert e.value.name == "no_start"
    bits = biss.encode_frame(biss.ABSYS_LAYOUT, biss.SlaveValues(single_turn=1))
    with pytest.raises(IncompleteError) as ie:
        biss.decode_frame(bits[:20], biss.ABSYS_LAYOUT)
    assert ie.value.needed > 0 and ie.value.unit == "bits"
    with pytest.raises(EncodeError) as ee:
        biss.SlaveLayout(single_turn_bits=0).validate()
    assert ee.value.code == motionbus.Errc.biss_layout
    with pytest.raises(EncodeError):
        biss.encode_frame(biss.ABSYS_LAYOUT, biss.SlaveValues(single_turn=1 << 32))
    with pytest.raises(EncodeError):
        biss.encode_frame([biss.ABSYS_LAYOUT] * 2, [biss.SlaveValues()])


def test_crc_formats_and_layouts() -> None:
    c = biss.crc_from_biss_notation(0x43)
    assert (c.width, c.poly, c.start, c.inverted) == (6, 3, 0, True)
    assert biss.crc_from_eds(0x21) == c
    assert biss.crc_from_biss_notation(0x13, 0, biss.CrcOutput.plain).inverted is False
    lay = biss.SlaveLayout(multi_turn_bits=12, single_turn_bits=20, crc=c)
    assert lay.data_bits == 32 and lay.frame_bits == 40 and "SlaveLayout(" in repr(lay)
    lay.alignment_bits = 2
    assert lay.data_bits == 34
    assert biss.ABSYS_LAYOUT.frame_bits == 40


class RegisterFile:
    def __init__(self) -> None:
        self.mem: Dict[int, int] = {a: a ^ 0x5A for a in range(128)}
        self.busy_frames = 0

    def readable(self, a: int) -> bool:
        return True

    def writable(self, a: int) -> bool:
        return a >= 0x40

    def ready(self) -> bool:
        self.busy_frames = max(0, self.busy_frames - 1)
        return self.busy_frames == 0

    def read(self, a: int) -> int:
        return self.mem[a]

    def write(self, a: int, v: int) -> None:
        self.mem[a] = v
        self.busy_frames = 3


def run(master: biss.ControlMaster, slave_step: object, limit: int = 20000) -> None:
    cds = False
    for _ in range(limit):
        if not master.busy:
            return
        cdm = master.step(cds)
        cds = slave_step(cdm)  # type: ignore[operator]
    raise AssertionError("access did not finish")


@given(st.integers(0, 7), st.integers(0x40, 0x7F), st.binary(min_size=1, max_size=4))
def test_control_master_and_slave(slave_id: int, address: int, data: bytes) -> None:
    data = data[: 0x80 - address]
    regs = RegisterFile()
    slave = biss.ControlSlave(regs, slave_id=slave_id)
    m = biss.ControlMaster()
    m.start_write(slave_id, address, data)
    run(m, slave.step)
    assert m.state == biss.ControlState.done and m.error is None and m.transferred == len(data)
    assert bytes(regs.mem[address + i] for i in range(len(data))) == data
    m.start_read(slave_id, address, len(data))
    run(m, slave.step)
    assert m.data == data and slave.accesses == 2 * len(data) and m.frames >= biss.ControlMaster.frames_for(len(data)) - biss.PREAMBLE_FRAMES
    m.start_write(slave_id, 0x00, b"\x01")  # not writable: refused
    run(m, slave.step)
    assert m.state == biss.ControlState.failed and m.error is not None
    assert slave.rejected_writes == 0 and slave.refused_busy == 0
    wrong = biss.ControlMaster(max_wait_frames=64)
    wrong.start_read((slave_id + 1) % 8, address)
    run(wrong, slave.step)
    assert wrong.error == motionbus.Errc.biss_not_acknowledged


@given(st.integers(0, 7), st.integers(0x40, 0x7E), st.binary(min_size=1, max_size=2))
def test_control_observer_sees_what_master_and_slave_do(slave_id: int, address: int,
                                                        data: bytes) -> None:
    regs = RegisterFile()
    slave = biss.ControlSlave(regs, slave_id=slave_id)
    m = biss.ControlMaster()
    m.start_write(slave_id, address, data)
    obs = biss.ControlObserver()
    seen: List[biss.ObservedAccess] = []
    cds = False
    for _ in range(2000):
        busy = m.busy
        cdm = m.step(cds)
        e = obs.step(cds, cdm)
        if e is not None:
            seen.append(e)
        if not busy:
            break
        cds = slave.step(cdm)
    head, *rest = seen
    assert (head.kind, head.slave_id, head.address, head.write, head.cts) == (
        "header", slave_id, address, True, True)
    assert head.crc == biss.header_crc(slave_id, address) and head.crc_ok and head.echo == 1
    assert [(b.kind, b.address, b.data, b.answer, b.crc_ok, b.stop) for b in rest] == [
        ("byte", address + i, v, v, True, False) for i, v in enumerate(data)]
    # wait states: none before the first byte, some while the previous write keeps it busy
    assert [b.waits > 0 for b in rest] == [i > 0 for i in range(len(data))]
    assert all(b.answer_crc == biss.data_crc(b.data) for b in rest)
    obs.reset()
    assert obs.step(True, True) is None


def test_control_master_refusals_and_crcs() -> None:
    m = biss.ControlMaster()
    with pytest.raises(EncodeError):
        m.start_read(8, 0)
    m.start_read(0, 0)
    with pytest.raises(EncodeError) as e:
        m.start_read(0, 0)
    assert e.value.name == "busy"
    m.abort()
    assert m.error == motionbus.Errc.biss_aborted
    assert biss.header_bits(0, 0x42, False) >> 16 == 3
    assert biss.header_crc(0, 0x42) == reference.crc4_biss(reference.to_bits((1 << 10) | 0x42, 11))
    assert biss.data_crc(0xA5) == reference.crc4_biss(reference.to_bits(0xA5, 8))


def test_slave_register_file_errors_surface() -> None:
    class Bad:
        def read(self, a: int) -> int:
            raise KeyError(a)

    slave = biss.ControlSlave(Bad())
    m = biss.ControlMaster()
    m.start_read(0, 1)
    with pytest.raises(KeyError):
        run(m, slave.step)


def test_eds_round_trip_and_absys() -> None:
    bp3 = absys.default_bp3(biss.EncoderType.rotary, 512, 10)
    bank = biss.encode_bp3(bp3)
    assert len(bank) == 64 and bank[63] == biss.bank_checksum(bank)
    back = biss.decode_bp3(bank, verify_checksum=True)
    assert back == bp3 and back.pulses_per_revolution == 512 << 10 and back.type == biss.EncoderType.rotary
    assert back.layout().frame_bits == absys.LAYOUT.frame_bits and back.lsb_nm > 0
    common = biss.EdsCommon()
    assert biss.decode_eds_common(biss.encode_eds_common(common), verify_checksum=True) == common
    broken = bytearray(bank)
    broken[5] ^= 1
    with pytest.raises(DecodeError) as e:
        biss.decode_bp3(broken, verify_checksum=True)
    assert e.value.name == "invalid_eds" and e.value.expected != e.value.received
    with pytest.raises(IncompleteError):
        biss.decode_eds_common(bank[:10])

    emu = absys.Emulator()
    emu.set_position(123456)  # below the 512 << 10 pulses of a turn
    f = biss.decode_frame(emu.frame(3, 2), absys.LAYOUT)
    assert f.slaves[0].single_turn == emu.reported_position == emu.absolute_position == 123456
    assert emu.values().single_turn == 123456
    m = biss.ControlMaster()
    m.start_read(0, absys.REGISTERS["manufacturer_id"], 2)
    while m.busy:
        emu.control(m.step(emu.cds))
    assert m.data == b"Am" and emu.register_accesses == 2  # bytes
    m.start_read(0, absys.REGISTERS["serial_number"], 8)
    while m.busy:
        emu.control(m.step(emu.cds))
    assert absys.decode_serial_number(m.data) == ("ATJ", 0x00BC614E, "C")
    m.start_read(0, absys.REGISTERS["device_id"], 8)
    while m.busy:
        emu.control(m.step(emu.cds))
    assert absys.decode_device_id(m.data)[1] == 0x0011F58E
    emu.set_error(absys.SensorError.in_operation)
    assert biss.decode_frame(emu.frame(), absys.LAYOUT).slaves[0].error
    assert absys.decode_error_status(emu.error_status)["error"]
    assert absys.decode_error_status(absys.STATUS_HEALTHY) == {"error": False, "warning": False, "undefined": 0}
    assert absys.status_of(True, True) == absys.STATUS_HEALTHY
    emu.set_functional_reserve(100, 1)
    assert emu.offset == 0 and emu.selected_bank == 0x80 and not emu.busy and emu.refused_while_busy == 0
    assert emu.pulses_per_revolution == 512 << 10
    assert absys.write_time_us(absys.REGISTERS["command"], absys.Command.set_offset_to_position) == 17000
    assert absys.linear_position(5, 10) == -5 and absys.rotary_position(5, 10, 100) == 95
    assert absys.PresetMode.actual == 1


def test_eds_every_field_round_trips() -> None:
    c = biss.EdsCommon()
    for i, f in enumerate(["version", "length", "user_bank_start", "user_bank_end", "channels", "validity",
                           "location", "profile_bank", "data_format"]):
        setattr(c, f, 0x10 + i)
    c.data_length, c.crc_poly = 0x18, 0x21
    back = biss.decode_eds_common(biss.encode_eds_common(c))
    assert (back.version, back.length, back.user_bank_start, back.user_bank_end, back.channels, back.validity,
            back.location, back.profile_bank, back.data_length, back.data_format, back.crc_poly) == (
        0x10, 0x11, 0x12, 0x13, 0x14, 0x15, 0x16, 0x17, 0x18, 0x18, 0x21)
    p = biss.Bp3Profile()
    p.version, p.length, p.profile_id, p.feedback1, p.feedback2 = 2, 1, 0x6320, 1, 2
    p.power_on_delay_ms, p.type, p.positions = 9, biss.EncoderType.linear, 1
    p.mt_length, p.mt_format, p.coarse_length, p.coarse_format, p.fine_length, p.fine_format = 8, 0, 4, 0, 20, 0
    p.mt_count, p.sip_count, p.sip_resolution, p.crc_poly, p.crc_start = 256, 40, 3, 0x21, 0
    q = biss.decode_bp3(biss.encode_bp3(p))
    assert q == p and q.type == biss.EncoderType.linear and q.lsb_nm == 40 / 8
    assert (q.version, q.profile_id, q.feedback1, q.feedback2, q.power_on_delay_ms, q.positions) == (2, 0x6320, 1, 2, 9, 1)
    assert (q.mt_length, q.mt_format, q.coarse_length, q.coarse_format, q.fine_length, q.fine_format) == (8, 0, 4, 0, 20, 0)
    assert (q.mt_count, q.sip_count, q.sip_resolution, q.crc_poly, q.crc_start) == (256, 40, 3, 0x21, 0)
    assert q.layout().data_bits == 32


def test_slave_data_fields() -> None:
    bits = biss.encode_frame(biss.ABSYS_LAYOUT, biss.SlaveValues(single_turn=9))
    s = biss.decode_frame(bits, biss.ABSYS_LAYOUT).slaves[0]
    assert s.crc == s.crc_computed == reference.crc6_biss(bits[3:37])  # Ack, Start, CDS, then 32 data bits, nE, nW
