"""motionbus.crc against plain Python references (Hypothesis)."""

from hypothesis import given, strategies as st

import reference
from motionbus import EncodeError, crc

data = st.binary(max_size=300)


@given(data)
def test_crc16_modbus_matches_reference(d: bytes) -> None:
    assert crc.crc16_modbus(d) == reference.crc16_modbus(d)
    assert crc.crc16_modbus(bytearray(d)) == crc.crc16_modbus(memoryview(d))


def test_crc16_modbus_check_value() -> None:
    assert crc.crc16_modbus(b"123456789") == 0x4B37  # the CRC catalogue's check value


@given(data)
def test_crc8_tformat_matches_reference(d: bytes) -> None:
    assert crc.crc8_tformat(d) == reference.crc8_tformat(d)


@given(st.integers(0, 64).flatmap(lambda n: st.tuples(st.just(n), st.integers(0, (1 << n) - 1))))
def test_biss_crcs_match_reference(nv: tuple) -> None:
    n, v = nv
    bits = reference.to_bits(v, n)
    assert crc.crc6_biss(v, n) == reference.crc6_biss(bits)
    assert crc.crc4_biss(v, n) == reference.crc4_biss(bits)


@given(st.integers(1, 16), st.data())
def test_dynamic_crc_matches_reference(width: int, d: st.DataObject) -> None:
    poly = d.draw(st.integers(0, (1 << width) - 1))
    init = d.draw(st.integers(0, (1 << width) - 1))
    payload = d.draw(st.binary(max_size=40))
    c = crc.Crc(width, poly, init)
    bits = [b for byte in payload for b in reference.to_bits(byte, 8)]
    assert c.update(payload).value == reference.crc_bits(bits, width, poly, init)
    assert "width=" in repr(c)
    c2 = crc.Crc(width, poly, init).update_bits(int.from_bytes(payload[:8], "big"), 8 * len(payload[:8]))
    assert c2.value == reference.crc_bits(bits[:64], width, poly, init)
    assert c2.width == width


def test_crc_refusals() -> None:
    for bad in ((0, 1), (33, 1), (4, 0x10)):
        try:
            crc.Crc(*bad)
        except EncodeError as e:
            assert e.name == "invalid_argument"
        else:
            raise AssertionError(f"Crc{bad} accepted")
    for f in (crc.crc6_biss, crc.crc4_biss):
        try:
            f(0, 65)
        except ValueError:
            pass
        else:
            raise AssertionError("count 65 accepted")
