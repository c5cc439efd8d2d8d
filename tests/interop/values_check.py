"""motionbus's typed values (tests/interop/values_dump.cpp) against pymodbus 3.0's
BinaryPayloadBuilder and BinaryPayloadDecoder in every byte order x word order, both directions,
and against libmodbus's helpers (tests/interop/libmodbus_values.c): the integer macros (ABCD) both
ways, and which register order each modbus_set_float_* writes and modbus_get_float_* reads, which
must be the one docs/modbus.md states ("Typed values: libmodbus's names").

usage: values_check.py VALUES_DUMP LIBMODBUS_VALUES
"""
import struct
import subprocess
import sys

from pymodbus.constants import Endian
from pymodbus.payload import BinaryPayloadBuilder, BinaryPayloadDecoder

# motionbus word order -> pymodbus (byteorder, wordorder), as docs/modbus.md has it
PYMODBUS = {
    "abcd": (Endian.Big, Endian.Big),
    "cdab": (Endian.Big, Endian.Little),
    "badc": (Endian.Little, Endian.Big),
    "dcba": (Endian.Little, Endian.Little),
}
# libmodbus 3.1.6 name -> the motionbus order its registers are in on this host (docs/modbus.md)
LIBMODBUS_SET = {"abcd": "badc", "badc": "abcd", "cdab": "dcba", "dcba": "cdab", "float": "cdab"}
LIBMODBUS_GET = {"abcd": "abcd", "badc": "badc", "cdab": "cdab", "dcba": "dcba", "float": "cdab"}

WIDTH = {"u32": 32, "i32": 32, "f32": 32, "u64": 64, "i64": 64, "f64": 64}
failures = []


class Peer:
    def __init__(self, path):
        self.p = subprocess.Popen([path], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)

    def ask(self, line):
        self.p.stdin.write(line + "\n")
        self.p.stdin.flush()
        return self.p.stdout.readline().split()

    def close(self):
        self.p.stdin.close()
        if self.p.wait(timeout=10) != 0:
            failures.append(f"{self.p.args[0]} exited with {self.p.returncode}")


def python_value(t, bits):
    """The Python number pymodbus is given for the value with these bits."""
    w = WIDTH[t]
    if t == "f32":
        return struct.unpack(">f", struct.pack(">I", bits))[0]
    if t == "f64":
        return struct.unpack(">d", struct.pack(">Q", bits))[0]
    if t[0] == "i" and bits >= 1 << (w - 1):
        return bits - (1 << w)
    return bits


def python_bits(t, value):
    w = WIDTH[t]
    if t == "f32":
        return struct.unpack(">I", struct.pack(">f", value))[0]
    if t == "f64":
        return struct.unpack(">Q", struct.pack(">d", value))[0]
    return value & ((1 << w) - 1)


def method(t):
    kind = {"u": "uint", "i": "int", "f": "float"}[t[0]]
    return f"{WIDTH[t]}bit_{kind}"


def regs_of(words):
    return [int(x, 16) for x in words]


def encoded(dump, t, bits):
    out = dump.ask(f"enc {t} {bits:x}")
    n = WIDTH[t] // 16
    return {out[i]: regs_of(out[i + 1:i + 1 + n]) for i in range(0, len(out), n + 1)}


def check_pymodbus(dump, t, bits):
    # A float32 reaches Python as a double: a signalling NaN comes back quiet (Python's
    # conversion, not pymodbus's ordering). The comparison then uses the bits Python holds.
    value = python_value(t, bits)
    held = python_bits(t, value)
    ours = encoded(dump, t, held)
    for order, (byteorder, wordorder) in PYMODBUS.items():
        where = f"{t} {bits:x} {order}"
        builder = BinaryPayloadBuilder(byteorder=byteorder, wordorder=wordorder)
        getattr(builder, "add_" + method(t))(value)
        theirs = builder.to_registers()
        if theirs != ours[order]:
            failures.append(f"pymodbus builder {where}: {theirs} != motionbus {ours[order]}")
        got = dump.ask(f"dec {t} {order} " + " ".join(f"{r:x}" for r in theirs))
        if int(got[0], 16) != held:
            failures.append(f"motionbus decoding pymodbus {where}: {got[0]} != {held:x}")
        decoder = BinaryPayloadDecoder.fromRegisters(ours[order], byteorder=byteorder,
                                                     wordorder=wordorder)
        back = python_bits(t, getattr(decoder, "decode_" + method(t))())
        if back != held:
            failures.append(f"pymodbus decoder {where}: {back:x} != {held:x}")
    return held != bits


def check_libmodbus(dump, lm, t, bits):
    ours = encoded(dump, t, bits)
    where = f"libmodbus {t} {bits:x}"
    if t in ("u32", "i32"):
        if regs_of(lm.ask(f"set32 {bits:x}")) != ours["abcd"]:
            failures.append(f"{where}: MODBUS_SET_INT32_TO_INT16 is not ABCD")
        if int(lm.ask("get32 %x %x" % tuple(ours["abcd"]))[0], 16) != bits:
            failures.append(f"{where}: MODBUS_GET_INT32_FROM_INT16 is not ABCD")
    elif t in ("u64", "i64"):
        if regs_of(lm.ask(f"set64 {bits:x}")) != ours["abcd"]:
            failures.append(f"{where}: MODBUS_SET_INT64_TO_INT16 is not ABCD")
        if int(lm.ask("get64 %x %x %x %x" % tuple(ours["abcd"]))[0], 16) != bits:
            failures.append(f"{where}: MODBUS_GET_INT64_FROM_INT16 is not ABCD")
    elif t == "f32":
        out = lm.ask(f"set {bits:x}")
        written = {out[i]: regs_of(out[i + 1:i + 3]) for i in range(0, len(out), 3)}
        for name, order in LIBMODBUS_SET.items():
            if written[name] != ours[order]:
                failures.append(f"{where}: modbus_set_float_{name} wrote {written[name]}, "
                                f"not {order.upper()} {ours[order]}")
        for name, order in LIBMODBUS_GET.items():
            out = lm.ask("get %x %x" % tuple(ours[order]))
            read = {out[i]: int(out[i + 1], 16) for i in range(0, len(out), 2)}
            if read[name] != bits:
                failures.append(f"{where}: modbus_get_float_{name} of {order.upper()} "
                                f"{ours[order]} gave {read[name]:x}")


def main():
    dump = Peer(sys.argv[1])
    lm = Peer(sys.argv[2])
    dump.p.stdin.write("samples\n")
    dump.p.stdin.flush()
    samples = []
    for line in dump.p.stdout:
        if line.strip() == "end":
            break
        t, hexbits = line.split()
        samples.append((t, int(hexbits, 16)))
    quieted = 0
    for t, bits in samples:
        quieted += check_pymodbus(dump, t, bits)
        check_libmodbus(dump, lm, t, bits)
    dump.close()
    lm.close()
    kinds = sorted({t for t, _ in samples})
    if len(samples) < 50 or kinds != sorted(WIDTH):
        failures.append(f"only {len(samples)} samples of {kinds}")
    for f in failures:
        print("FAIL", f)
    print(f"{len(samples)} values x 4 orders, pymodbus and libmodbus; "
          f"{quieted} float32 signalling NaN(s) compared as Python holds them (quiet)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
