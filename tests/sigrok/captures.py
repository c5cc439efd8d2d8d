"""Test captures for the sigrok decoders, built from the library's own encoders through the
motionbus package: a T-format line (one half-duplex UART line) and a BiSS-C MA/SLO pair, as
raw samples (one byte a sample, bit 0 = channel 0) that sigrok-cli's binary input reads, with
the values each frame was built from."""

from motionbus import AlmcBit, biss, tformat, DataId
from motionbus.devices import ts5700n8500

TF_BAUD = 2500000
TF_OVERSAMPLE = 8                   # samples per bit
TF_RATE = TF_BAUD * TF_OVERSAMPLE   # 20 MHz


def _span(first_bit, size):
    """The samples uart's DATA covers for a frame of `size` bytes whose first start bit is bit
    `first_bit` (8N1: 10 bits a byte): from the first data bit to the end of the last."""
    return ((first_bit + 1) * TF_OVERSAMPLE, (first_bit + 10 * (size - 1) + 9) * TF_OVERSAMPLE)


def _tf_bits(frame, idle_bits):
    return tformat.encode_line(frame, idle_bits)


def tformat_capture(corrupt=False, tail=None):
    """(raw samples, expected): a request/response exchange per Data ID, an EEPROM read and
    write, an abnormal (unknown Data ID) request and a request left unanswered. `corrupt` flips
    a bit in the ID3 response's ABS (its CRC goes bad). `tail` ends the capture with one more
    request, unanswered: 'unanswered' records 60 us of idle line after it, 'cut' only 1.6 us
    (4 bits: the capture may have cut its response off)."""
    enc = ts5700n8500.Emulator()
    enc.set_position(123456, 77)
    bits = [1] * 40
    expected = []
    now = 0

    def exchange(request, answer=True, flip=None, delimiter_error=False):
        nonlocal now
        reply = enc.respond(request, now_us=now, delimiter_error=delimiter_error) if answer else b''
        now += 100
        entry = {'request_bytes': bytes(request), 'reply': None, 'delimiter_error': delimiter_error,
                 'request_span': _span(len(bits), len(request))}
        line = _tf_bits(request, 0)
        if delimiter_error:
            line[9] = 0                                 # the first byte's stop bit
        bits.extend(line)
        if reply:
            data = bytearray(reply)
            if flip is not None:
                data[flip] ^= 0x01
            entry['reply_span'] = _span(len(bits) + 8, len(data))
            bits.extend(_tf_bits(bytes(data), 8))      # the encoder answers about 3 us later
            entry['reply_bytes'] = bytes(data)
            entry['reply'] = None if flip is not None else tformat.decode_response(reply)
        bits.extend([1] * 150)                          # 60 us to the next request
        expected.append(entry)

    for did in (DataId.read_abs, DataId.read_abm, DataId.read_enid,
                DataId.read_all):
        exchange(tformat.encode_request(did), flip=3 if corrupt and did == DataId.read_all
                 else None)
    exchange(tformat.encode_request(DataId.eeprom_write, 0x05, 0x5A))
    exchange(tformat.encode_request(DataId.eeprom_read, 0x05))
    exchange(bytes([0x2A]))                             # Data ID 5: unknown, answered with ID3
    exchange(tformat.encode_request(DataId.read_abm), delimiter_error=True)   # ID3 data, SF CA1
    exchange(tformat.encode_request(DataId.read_abs), answer=False)
    enc.set_condition(AlmcBit.be, True)                 # the battery error in the last reply
    exchange(tformat.encode_request(DataId.read_all))
    if tail is not None:
        exchange(tformat.encode_request(DataId.read_abs), answer=False)
        if tail == 'cut':
            del bits[len(bits) - 150 + 4:]
    samples = bytes(b for b in bits for _ in range(TF_OVERSAMPLE))
    return samples, expected


BISS_HALF = 4                       # samples per half clock period (1 MHz MA at 8 MHz)
BISS_RATE = 8000000
BISS_TIMEOUT = 20                   # the slave's timeout, in clock periods


def biss_capture(layout, positions, register_read=None, corrupt_frame=None, extra_clocks=4):
    """(raw samples, per frame [(values, cds, cdm, (first sample, end of the clocks))], the
    control master): sensor data frames of `layout` (one
    SlaveLayout or a chain) with `positions` (per frame, a list of SlaveValues), MA on channel
    0 and SLO on channel 1. `register_read` (slave_id, address, registers: bytes of the
    emulated register file) runs a control master and slave over the frames' CDM/CDS bits.
    `corrupt_frame` flips a data bit of that frame's first slave."""
    chain = layout if isinstance(layout, (list, tuple)) else [layout]
    master = slave = None
    if register_read is not None:
        slave_id, address, regs = register_read

        class Regs:
            def readable(self, a): return a < len(regs)
            def writable(self, a): return False
            def ready(self): return True
            def read(self, a): return regs[a]
            def write(self, a, v): pass
        master = biss.ControlMaster()
        slave = biss.ControlSlave(Regs(), slave_id=slave_id)
        master.start_read(slave_id, address, 1)
    out = bytearray([3] * 40)           # MA high, SLO high
    frames = []
    cds = False
    line_delay = 2
    for k, values in enumerate(positions):
        bits = biss.encode_frame(chain, values, line_delay=line_delay, ack_bits=1, cds=cds)
        if corrupt_frame == k:
            start = bits.index(1, line_delay + 1)       # the Start bit after the Ack
            bits[start + 2 + 3] ^= 1                    # a data bit of the first slave
        cdm = master.step(cds) if master is not None else False
        first = len(out)                # MA's first falling edge
        # SLO changes with MA's falling edge, the master samples at the rising edge.
        for b in bits + [0] * extra_clocks:
            out.extend([0 | (b << 1)] * BISS_HALF)
            out.extend([1 | (b << 1)] * BISS_HALF)
        # The timeout: SLO low, then high; MA low for the timeout when CDM = 1 (else high).
        ma = 0 if cdm else 1
        out.extend([ma | 0] * (BISS_TIMEOUT * 2 * BISS_HALF))
        out.extend([1 | 2] * (10 * 2 * BISS_HALF))
        frames.append((values, cds, cdm, (first, first + len(bits + [0] * extra_clocks) * 2 *
                                          BISS_HALF)))
        if slave is not None:
            cds = slave.step(cdm)
    return bytes(out), frames, master
