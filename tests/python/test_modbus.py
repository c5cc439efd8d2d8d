"""motionbus.modbus: random PDUs of both roles round-tripped (Hypothesis), pymodbus 3.0's own
RTU framer agreeing with the package on random PDUs, the framer in its three roles, TCP, the
server over a Python object, the SM unit profile and emulator."""

from typing import Any, List

import pytest
from hypothesis import given, strategies as st
from pymodbus.bit_read_message import ReadCoilsRequest, ReadCoilsResponse, ReadDiscreteInputsRequest
from pymodbus.bit_write_message import WriteMultipleCoilsRequest, WriteSingleCoilRequest
from pymodbus.factory import ClientDecoder, ServerDecoder
from pymodbus.framer.rtu_framer import ModbusRtuFramer
from pymodbus.register_read_message import (ReadHoldingRegistersRequest, ReadHoldingRegistersResponse,
                                            ReadInputRegistersRequest)
from pymodbus.register_write_message import WriteMultipleRegistersRequest, WriteSingleRegisterRequest

import motionbus
import reference
from motionbus import DecodeError, EncodeError, modbus as mb
from motionbus import tformat
from motionbus.devices import sm_unit as sm

slaves = st.integers(1, 247)
addresses = st.integers(0, 0xFFFF)
regs = st.lists(st.integers(0, 0xFFFF), min_size=1, max_size=123)
coils = st.lists(st.booleans(), min_size=1, max_size=1968)


@st.composite
def requests(draw: st.DrawFn) -> tuple:
    """(pdu, pymodbus request) of one of the functions both implement."""
    kind = draw(st.sampled_from(["rc", "rdi", "rhr", "rir", "wsc", "wsr", "wmc", "wmr"]))
    if kind in ("rc", "rdi"):
        q = draw(st.integers(1, 2000))
        a = draw(st.integers(0, 0x10000 - q))
        return (mb.encode_read(1 if kind == "rc" else 2, a, q),
                (ReadCoilsRequest if kind == "rc" else ReadDiscreteInputsRequest)(a, q))
    if kind in ("rhr", "rir"):
        q = draw(st.integers(1, 125))
        a = draw(st.integers(0, 0x10000 - q))
        return (mb.encode_read(3 if kind == "rhr" else 4, a, q),
                (ReadHoldingRegistersRequest if kind == "rhr" else ReadInputRegistersRequest)(a, q))
    if kind == "wsc":
        a, on = draw(addresses), draw(st.booleans())
        return mb.encode_write_single_coil(a, on), WriteSingleCoilRequest(a, on)
    if kind == "wsr":
        a, v = draw(addresses), draw(st.integers(0, 0xFFFF))
        return mb.encode_write_single_register(a, v), WriteSingleRegisterRequest(a, v)
    if kind == "wmc":
        c = draw(coils)
        a = draw(st.integers(0, 0x10000 - len(c)))
        return mb.encode_write_multiple_coils(a, c), WriteMultipleCoilsRequest(a, c)
    v = draw(regs)
    a = draw(st.integers(0, 0x10000 - len(v)))
    return mb.encode_write_multiple_registers(a, v), WriteMultipleRegistersRequest(a, v)


def pymodbus_frames(framer: ModbusRtuFramer, data: bytes, unit: int) -> List[Any]:
    out: List[Any] = []
    framer.processIncomingPacket(data, out.append, unit=unit)
    return out


@given(requests(), slaves)
def test_pymodbus_rtu_framer_agrees_on_requests(qp: tuple, slave: int) -> None:
    pdu, req = qp
    req.unit_id = slave
    theirs = ModbusRtuFramer(ServerDecoder()).buildPacket(req)
    ours = mb.encode_rtu(slave, pdu)
    assert ours == theirs
    assert ours[-2:] == reference.crc16_modbus(ours[:-2]).to_bytes(2, "little")
    got = pymodbus_frames(ModbusRtuFramer(ServerDecoder()), ours, slave)
    assert len(got) == 1 and got[0].function_code == pdu[0] and got[0].unit_id == slave
    frames = mb.RtuFramer(mb.FramerRole.server, address=slave).feed(theirs)
    assert len(frames) == 1 and frames[0].pdu == pdu and frames[0].slave == slave
    q = mb.decode_request(frames[0].pdu)
    assert q.function == pdu[0]
    if hasattr(req, "address"):
        assert q.address == req.address


@given(slaves, st.sampled_from([1, 3]), st.data())
def test_pymodbus_rtu_framer_agrees_on_read_responses(slave: int, fc: int, d: st.DataObject) -> None:
    if fc == 3:
        values = d.draw(st.lists(st.integers(0, 0xFFFF), min_size=1, max_size=125))
        ours = mb.encode_rtu(slave, mb.encode_read_registers_response(3, values))
        theirs_msg: Any = ReadHoldingRegistersResponse(values)
        request = mb.encode_read(3, 0, len(values))
    else:
        values = d.draw(st.lists(st.booleans(), min_size=8, max_size=2000).map(lambda v: v[: len(v) // 8 * 8]))
        ours = mb.encode_rtu(slave, mb.encode_read_bits_response(1, values))
        theirs_msg = ReadCoilsResponse(values)
        request = mb.encode_read(1, 0, len(values))
    theirs_msg.unit_id = slave
    assert ModbusRtuFramer(ClientDecoder()).buildPacket(theirs_msg) == ours
    got = pymodbus_frames(ModbusRtuFramer(ClientDecoder()), ours, slave)
    assert len(got) == 1
    assert (got[0].registers if fc == 3 else got[0].bits[: len(values)]) == values
    r = mb.decode_response_for(request, mb.decode_rtu(ours).pdu)
    assert (r.registers if fc == 3 else r.bits) == values


@given(requests())
def test_request_decode_and_write_response(qp: tuple) -> None:
    pdu, _ = qp
    q = mb.decode_request(pdu)
    assert "Request(function=" in repr(q)
    if pdu[0] in (5, 6, 15, 16):
        echo = mb.encode_write_response(q)
        r = mb.decode_response_for(pdu, echo)
        assert r.address == q.address and not r.exception
        if pdu[0] == 16:
            assert q.registers == [int.from_bytes(q.data[i:i + 2], "big") for i in range(0, len(q.data), 2)]
            assert r.quantity == q.quantity == len(q.registers)
        if pdu[0] == 15:
            assert len(q.coils) == q.quantity


def test_client_encoders_and_exception() -> None:
    assert mb.encode_mask_write_register(4, 0xF2, 0x25) == bytes.fromhex("16 0004 00f2 0025")
    assert mb.encode_read_write_multiple_registers(3, 6, 14, [0xFF, 0xFF, 0xFF]) == bytes.fromhex(
        "17 0003 0006 000e 0003 06 00ff00ff00ff")
    assert mb.encode_raw(0x07) == b"\x07"
    assert mb.encode_diagnostics(0, b"\xa5\x37") == bytes.fromhex("08 0000 a537")
    assert mb.encode_read_fifo_queue(0x4DE) == bytes.fromhex("18 04de")
    assert mb.encode_read_device_identification(1, 0) == bytes.fromhex("2b 0e 01 00")
    q = mb.encode_read(3, 0, 2)
    r = mb.decode_response_for(q, mb.encode_exception(3, 2))
    assert r.exception and r.exception_code == mb.ExceptionCode.illegal_data_address
    assert mb.exception_for(motionbus.Errc.modbus_quantity) == mb.ExceptionCode.illegal_data_value
    with pytest.raises(DecodeError) as e:
        mb.decode_response_for(q, mb.encode_read_registers_response(4, [1, 2]))
    assert e.value.name == "response_mismatch"
    with pytest.raises(EncodeError) as ee:
        mb.encode_read(3, 0, 126)
    assert ee.value.name == "illegal_quantity"


def test_server_response_encoders_and_unpaired_decode() -> None:
    assert mb.decode_response(mb.encode_exception_status_response(0x6D)).status == 0x6D
    r = mb.decode_response(mb.encode_comm_event_counter_response(0xFFFF, 0x108))
    assert (r.status, r.event_count) == (0xFFFF, 0x108)
    r = mb.decode_response(mb.encode_comm_event_log_response(0, 0x108, 0x121, b"\x20\x00"))
    assert (r.event_count, r.message_count, r.data[-2:]) == (0x108, 0x121, b"\x20\x00")
    r = mb.decode_response(mb.encode_fifo_response([0x1B8, 0x1284]))
    assert r.fifo_count == 2 and r.registers == [0x1B8, 0x1284]
    pdu = mb.encode_device_identification_response(1, 0x81, False, 0, [(0, b"Vendor"), (1, b"P1")])
    r = mb.decode_response(pdu)
    assert r.objects == [(0, b"Vendor"), (1, b"P1")] and r.object_count == 2 and r.conformity == 0x81
    assert not r.more_follows and r.next_object == 0
    r = mb.decode_response(mb.encode_write_single_register(7, 9))
    assert (r.address, r.value, r.byte_count) == (7, 9, 0)
    for attr in ("and_mask", "or_mask", "sub_function", "quantity"):
        assert getattr(r, attr) == 0
    r = mb.decode_response(mb.encode_mask_write_register(1, 2, 3))
    assert (r.and_mask, r.or_mask) == (2, 3)
    r = mb.decode_response(mb.encode_diagnostics(0, b"\x12\x34"))
    assert r.sub_function == 0 and r.data.endswith(b"\x12\x34")
    q = mb.decode_request(mb.encode_read_write_multiple_registers(1, 2, 3, [4]))
    assert (q.write_address, q.write_quantity, q.registers) == (3, 1, [4])
    q = mb.decode_request(mb.encode_mask_write_register(1, 2, 3))
    assert (q.and_mask, q.or_mask) == (2, 3)
    q = mb.decode_request(mb.encode_diagnostics(1, b"\xff\x00"))
    assert q.sub_function == 1 and q.value == 0
    q = mb.decode_request(mb.encode_read_device_identification(4, 5))
    assert (q.mei_type, q.read_code, q.object_id) == (0x0E, 4, 5)


@given(st.integers(0, 0xFFFF), st.integers(0, 255), st.binary(min_size=1, max_size=253))
def test_tcp_round_trip(t: int, unit: int, pdu: bytes) -> None:
    adu = mb.encode_tcp(t, unit, pdu)
    f = mb.decode_tcp(adu + b"\x00\x00")
    assert (f.transaction, f.protocol, f.unit, f.pdu, f.size) == (t, 0, unit, pdu, len(adu))
    assert "TcpFrame(" in repr(f)


@given(st.lists(requests(), min_size=1, max_size=4), st.integers(1, 300))
def test_framer_chunks_bytes_and_listener(qs: list, chunk: int) -> None:
    stream = b"".join(mb.encode_rtu(9, pdu) for pdu, _ in qs)
    server = mb.RtuFramer(mb.FramerRole.server, address=9, ends=mb.FrameEnd.length)
    got = [e for i in range(0, len(stream), chunk) for e in server.feed(stream[i:i + chunk])]
    assert [f.pdu for f in got] == [pdu for pdu, _ in qs]
    server2 = mb.RtuFramer(mb.FramerRole.server, address=9, ends=mb.FrameEnd.length)
    assert [e for b in stream for e in server2.put(b)] == got
    other = mb.RtuFramer(mb.FramerRole.server, address=8, ends=mb.FrameEnd.length)
    assert other.feed(stream) == [] and other.skipped == len(qs)
    listener = mb.RtuFramer(mb.FramerRole.listener)
    heard = listener.feed(stream) + listener.idle()
    assert [f.pdu for f in heard] == [pdu for pdu, _ in qs]
    assert all(isinstance(f.heard_response, bool) for f in heard)
    assert listener.role == mb.FramerRole.listener and listener.pending == 0


def test_framer_client_silence_and_errors() -> None:
    req = mb.encode_rtu(3, mb.encode_read(3, 0, 1))
    resp = mb.encode_rtu(3, mb.encode_read_registers_response(3, [0x1234]))
    client = mb.RtuFramer(mb.FramerRole.client)
    client.sent(req)
    [f] = client.feed(resp)
    assert f.slave == 3 and not f.broadcast and f.crc == int.from_bytes(resp[-2:], "little")
    bad = bytearray(resp)
    bad[3] ^= 1
    client.sent(req)
    events = client.feed(bytes(bad)) + client.idle()
    errors = [e for e in events if isinstance(e, DecodeError)]
    assert errors and errors[0].name == "crc_mismatch"
    assert errors[0].expected == reference.crc16_modbus(bytes(bad[:-2]))
    server = mb.RtuFramer(address=3)
    assert server.feed(req[:4]) == [] and server.pending == 4
    [cut] = server.idle()
    assert isinstance(cut, DecodeError) and cut.name == "truncated" and server.dropped >= 0
    assert mb.decode_rtu(req) == mb.RtuFrame(3, req[1:-2], int.from_bytes(req[-2:], "little"))
    assert mb.t35_us(9600) > mb.t15_us(9600) > 0 and mb.t35_us(115200, mb.Parity.none) == 1750


class Recorder(mb.RegisterBank):
    def report_server_id(self) -> bytes:
        return b"\x02\x42\xff"  # the data part: byte count, then the device bytes


@given(st.integers(0, 90), st.lists(st.integers(0, 0xFFFF), min_size=1, max_size=10),
       st.lists(st.booleans(), min_size=1, max_size=20))
def test_server_over_python_object(a: int, values: List[int], bits: List[bool]) -> None:
    bank = Recorder(coils=120, discrete_inputs=10, holding_registers=100, input_registers=10)
    srv = mb.Server(bank, 5)
    write = mb.encode_rtu(5, mb.encode_write_multiple_registers(a, values))
    reply = srv.serve(write)
    expected = a + len(values) <= 100
    r = mb.decode_response_for(mb.decode_rtu(write).pdu, mb.decode_rtu(reply).pdu)
    assert r.exception != expected
    if expected:
        assert bank.holding_registers[a:a + len(values)] == values
        read = mb.encode_rtu(5, mb.encode_read(3, a, len(values)))
        assert srv.feed(read) == srv.feed(b"") + [mb.serve_rtu(bank, 5, read)]
    else:
        assert r.exception_code == mb.ExceptionCode.illegal_data_address
    srv.serve(mb.encode_rtu(5, mb.encode_write_multiple_coils(a, bits)))
    read = mb.decode_rtu(srv.serve(mb.encode_rtu(5, mb.encode_read(1, a, len(bits))))).pdu
    assert mb.decode_response_for(mb.encode_read(1, a, len(bits)), read).bits == bits
    ident = mb.decode_rtu(srv.serve(mb.encode_rtu(5, mb.encode_raw(0x11)))).pdu
    assert ident == bytes.fromhex("11 02 42 ff")
    assert srv.serve(mb.encode_rtu(0, mb.encode_write_single_coil(0, True))) == b""  # broadcast
    assert bank.coils[0] and srv.idle() == []


def test_server_device_failures_are_clear() -> None:
    class Broken:
        def read_holding_registers(self, address: int, count: int) -> List[int]:
            raise RuntimeError("sensor unplugged")

        def read_input_registers(self, address: int, count: int) -> List[int]:
            raise mb.ModbusException(mb.ExceptionCode.server_device_busy)

        def read_coils(self, address: int, count: int) -> List[bool]:
            return [True]  # wrong count

    with pytest.raises(RuntimeError, match="unplugged"):
        mb.serve_rtu(Broken(), 1, mb.encode_rtu(1, mb.encode_read(3, 0, 1)))
    busy = mb.serve_rtu(Broken(), 1, mb.encode_rtu(1, mb.encode_read(4, 0, 1)))
    assert mb.decode_rtu(busy).pdu == b"\x84\x06"
    with pytest.raises(ValueError):
        mb.serve_rtu(Broken(), 1, mb.encode_rtu(1, mb.encode_read(1, 0, 3)))
    none = mb.serve_rtu(object(), 1, mb.encode_rtu(1, mb.encode_read(3, 0, 1)))
    assert mb.decode_rtu(none).pdu == b"\x83\x01"  # no accessor: illegal function


def test_sm_unit_profile_and_emulator() -> None:
    e = sm.Emulator()
    q = sm.read_instantaneous(1)
    values = sm.decode_instantaneous(q, e.serve(q, 1))
    assert set(values) == set(sm.Channel)
    assert values[sm.Channel.voltage] == e.instantaneous_register(sm.Channel.voltage)
    q = sm.read_version(2)
    assert sm.decode_version(q, e.serve(q, 2)) == (1, 0)
    assert e.logged_in
    e.serve(sm.login(1, b"password"), 1)
    assert not e.logged_in
    denied = e.serve(sm.write_setting(1, 0, 10), 1)
    assert mb.decode_rtu(denied).pdu[0] & 0x80
    e.serve(sm.login(1, b"password"), 1)
    e.serve(sm.write_settings(1, 0, [10, 20]), 1)
    assert (e.setting(0), e.setting(1)) == (10, 20)
    e.set_time_ms(1000)
    e.inject_warning(0x0020)
    assert e.warning_status == 0x0020 and e.warning_count == 1
    for adu in (sm.read_state(1), sm.read_login_status(1), sm.read_log(1, 1, sm.Channel.torque),
                sm.read_inputs(1, 100, 3), sm.read_holding_block(1, 300, 2), sm.set_coil(1, 100),
                sm.change_password(1, b"newpassword")):
        assert mb.decode_rtu(e.serve(adu, 1)).slave == 1
    assert sm.unit_of(sm.Channel.current) == ("A", 1, 100, False)
    assert sm.raw_value(sm.Channel.temperature, 0xFFFF) == -1
    assert sm.log_address(2, sm.Channel.power, 3) == 2203
    lo, hi = sm.setting_limits(0)
    assert lo <= hi
    sm.check_password(b"abcdefgh")
    with pytest.raises(EncodeError):
        sm.check_password(b"short")
    assert sm.warning_name(0x0020) and sm.warning_name(0x8000) is None
    assert (sm.BAUD, sm.MIN_SLAVE, sm.MAX_SLAVE, sm.SETTING_COUNT) == (9600, 1, 16, 40)
    assert mb.MAX_PDU_SIZE == 253 and mb.MAX_RTU_SIZE == 256
    assert (mb.MAX_READ_BITS, mb.MAX_READ_REGISTERS, mb.MAX_WRITE_COILS, mb.MAX_WRITE_REGISTERS) == (2000, 125, 1968, 123)


def test_register_bank_and_fc11_layouts() -> None:
    bank = mb.RegisterBank(coils=4, discrete_inputs=4, holding_registers=4, input_registers=4)
    bank.write_coils(1, [True, True])
    bank.write_registers(2, [7, 8])
    bank.discrete_inputs[0] = True
    bank.input_registers[3] = 5
    assert bank.read_coils(0, 4) == [False, True, True, False]
    assert bank.read_discrete_inputs(0, 1) == [True]
    assert bank.read_holding_registers(2, 2) == [7, 8] and bank.read_input_registers(3, 1) == [5]
    with pytest.raises(mb.ModbusException):
        bank.read_input_registers(3, 2)
    two = bytes.fromhex("11 01 00")  # the SM unit's FC11: two bytes, no byte count
    r = mb.decode_response_for(mb.encode_raw(0x11), two, mb.ReportIdFormat.two_bytes_no_count)
    assert r.data == b"\x01\x00"
    with pytest.raises(DecodeError):
        mb.decode_response(bytes.fromhex("11 05 00"), mb.ReportIdFormat.standard)
    assert mb.decode_response(bytes.fromhex("11 02 01 ff")).data[-2:] == b"\x01\xff"


def test_response_status_field() -> None:
    r = tformat.decode_response(tformat.encode_response(tformat.Response(tformat.DataId.read_abs, sf=0x30)))
    assert r.sf == 0x30 and r.ea0 and r.ea1
