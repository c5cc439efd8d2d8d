"""Independent computations shared by the Python test tools (the meter, the firmware checks):
written from the specifications, never with the library under test."""


def crc16_modbus(data):
    """CRC-16/MODBUS: polynomial 0xA001 reflected, initial value 0xFFFF, bit by bit."""
    crc = 0xFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def rtu(slave, pdu):
    """The RTU ADU of `pdu` for `slave`: address, PDU, CRC low byte first."""
    body = [slave] + list(pdu)
    c = crc16_modbus(body)
    return body + [c & 0xFF, c >> 8]
