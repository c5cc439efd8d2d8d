"""Plain Python references the package is compared with: bit-by-bit CRCs written from their
definitions (not from the library), and a BiSS frame built sample by sample."""

from typing import List


def crc_bits(bits: List[int], width: int, poly: int, init: int = 0) -> int:
    """Non-reflected CRC over a bit list, MSB first (the textbook shift register)."""
    reg = init
    top = 1 << (width - 1)
    mask = (1 << width) - 1
    for b in bits:
        fb = ((reg & top) != 0) ^ bool(b)
        reg = (reg << 1) & mask
        if fb:
            reg ^= poly
    return reg


def to_bits(value: int, n: int) -> List[int]:
    return [(value >> (n - 1 - i)) & 1 for i in range(n)]


def crc16_modbus(data: bytes) -> int:
    reg = 0xFFFF
    for byte in data:
        reg ^= byte
        for _ in range(8):
            reg = (reg >> 1) ^ 0xA001 if reg & 1 else reg >> 1
    return reg


def crc8_tformat(data: bytes) -> int:
    x = 0
    for byte in data:
        x ^= byte
    return x


def crc6_biss(bits: List[int]) -> int:
    return crc_bits(bits, 6, 0x03) ^ 0x3F


def crc4_biss(bits: List[int]) -> int:
    return crc_bits(bits, 4, 0x03) ^ 0x0F


def biss_frame(data: int, data_bits: int, ne: bool, nw: bool, line_delay: int, ack: int,
               cds: bool) -> List[int]:
    """One ABSYS-like slave frame: idle 1s, Ack 0s, Start, CDS, data, nE, nW, CRC6."""
    payload = to_bits(data, data_bits) + [int(ne), int(nw)]
    return [1] * line_delay + [0] * ack + [1, int(cds)] + payload + to_bits(crc6_biss(payload), 6)
