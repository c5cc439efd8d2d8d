#!/usr/bin/python3
"""The motionbus meter: instructions executed and stack used per operation, on the cores the
library ships to.

  meter.py run --core cortex-m4 --opt Os --out DIR --include DIR --tools TOOLS.json
      builds tests/meter/ops.cpp for the core at the level, loads the image into Unicorn (an
      instruction-set emulator), checks the meter on loops of known instruction count, then calls
      each operation on its inputs, checks every output against an independent computation made
      here, and writes DIR/meter-<core>-<opt>.json.
  meter.py report --out DIR --budgets budgets.json [--markdown FILE]
      merges the per-build files into DIR/meter.json (a list of {core, opt, operation,
      instructions, stack_bytes}), prints the table and fails when a budgeted figure exceeds its
      budget.

Counting: a code hook counts each instruction executed, from the operation's first instruction
to its return. Unicorn 2.0.1 does not call the hook for an instruction of a Cortex-M IT block
whose condition fails, though the core issues it: an IT instruction counts the whole block, and
the block's instructions that do run are not counted again. Stack: the stack is painted before
each call and a memory hook records the lowest address written below the caller's stack pointer;
the painted area scanned after the call must agree. On Cortex-M0+ every instruction executed is
checked to be ARMv6-M (Unicorn's Cortex-M0 model runs Thumb-2 code without complaint).

Must run with Debian's /usr/bin/python3 (python3-unicorn).
"""

import argparse
import json
import os
import struct
import subprocess
import sys

from unicorn import (UC_ARCH_ARM, UC_ARCH_RISCV, UC_HOOK_CODE, UC_HOOK_MEM_WRITE,
                     UC_MODE_MCLASS, UC_MODE_RISCV32, UC_MODE_THUMB, Uc)
from unicorn import arm_const, riscv_const

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "support"))
from reference import crc16_modbus, rtu  # noqa: E402,F401  (shared independent computations)
CORES = ("cortex-m0plus", "cortex-m4", "rv32imc")
OPTS = ("Os", "O2")


class MeterError(Exception):
    pass


# --- building ---------------------------------------------------------------------------------

# The images: the one where every operation is (ops.cpp), and the one where each stream object
# is alone in its translation unit (measure_alone()).
IMAGES = {"": ["ops.cpp"],
          "-alone": ["alone_main.cpp", "alone_receiver.cpp", "alone_framer.cpp",
                     "alone_gateway.cpp"],
          # the C API's calls (measure_capi()): its C++ source linked as a C firmware links it
          "-capi": ["capi_ops.cpp", os.path.join("..", "..", "c", "motionbus_c.cpp")]}


def build(core, opt, out, include, tools, image=""):
    os.makedirs(out, exist_ok=True)
    name = f"meter-{core}-{opt}{image}"
    sources = [os.path.join(HERE, src) for src in IMAGES[image]]
    elf = os.path.join(out, name + ".elf")
    common = ["-std=c++17", "-" + opt, "-fno-exceptions", "-fno-rtti", "-fno-threadsafe-statics",
              "-ffunction-sections", "-fdata-sections", "-Wall", "-Wextra", "-Werror",
              "-I" + include, "-I" + os.path.join(HERE, "..", "..", "c", "include")]
    if core in ("cortex-m0plus", "cortex-m4"):
        cpu = ["-mcpu=" + core, "-mthumb", "-mfloat-abi=soft"]
        cmd = [tools["arm_gxx"]] + common + cpu + [
            "-nostartfiles", "--specs=nosys.specs", "-T", os.path.join(HERE, "arm.ld")] + \
            sources + ["-o", elf]
        run(cmd)
    else:
        target = ["--target=riscv32-unknown-elf", "-march=rv32imc", "-mabi=ilp32", "-mno-relax",
                  "-nostdinc++"] + [f for d in tools["newlib_cxx"] for f in ("-isystem", d)]
        objs = []
        # the C runtime functions the compiler calls (the firmware examples' rv32 runtime)
        runtime = os.path.join(HERE, "..", "..", "examples", "firmware", "boards",
                               "rv32_runtime.cpp")
        for src, extra in [(src, []) for src in sources] + \
                [(runtime, ["-fno-builtin", "-fno-strict-aliasing"])]:
            obj = os.path.join(out, f"{name}.{os.path.basename(src)}.o")
            run([tools["clangxx"]] + common + target + extra + ["-c", src, "-o", obj])
            objs.append(obj)
        run([tools["riscv_ld"], "-m", "elf32lriscv", "-T", os.path.join(HERE, "rv32.ld")] +
            objs + ["-o", elf])
    return elf


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        raise MeterError("command failed: " + " ".join(cmd) + "\n" + p.stdout)


# --- ELF loading --------------------------------------------------------------------------------

class Image:
    """The loadable segments and the symbol table of a 32-bit little-endian ELF."""

    def __init__(self, path):
        with open(path, "rb") as f:
            self.raw = f.read()
        raw = self.raw
        if raw[:4] != b"\x7fELF" or raw[4] != 1 or raw[5] != 1:
            raise MeterError(path + ": not a 32-bit little-endian ELF")
        (self.machine,) = struct.unpack_from("<H", raw, 18)
        phoff, shoff = struct.unpack_from("<II", raw, 28)
        phentsize, phnum, shentsize, shnum, shstrndx = struct.unpack_from("<HHHHH", raw, 42)
        self.segments = []
        for i in range(phnum):
            p_type, p_offset, p_vaddr, _, p_filesz, p_memsz, _, _ = struct.unpack_from(
                "<IIIIIIII", raw, phoff + i * phentsize)
            if p_type == 1:  # PT_LOAD
                self.segments.append((p_vaddr, raw[p_offset:p_offset + p_filesz], p_memsz))
        sections = []
        for i in range(shnum):
            sections.append(struct.unpack_from("<IIIIIIIIII", raw, shoff + i * shentsize))
        shstr = sections[shstrndx]
        self.section_names = set()
        for s in sections:
            self.section_names.add(self._cstr(shstr[4] + s[0]))
        self.symbols = {}
        for s in sections:
            if s[1] == 2:  # SHT_SYMTAB
                strtab = sections[s[6]]
                for k in range(s[5] // 16):
                    name, value, size, info, _, _ = struct.unpack_from(
                        "<IIIBBH", raw, s[4] + k * 16)
                    if name:
                        self.symbols[self._cstr(strtab[4] + name)] = (value, size)

    def _cstr(self, at):
        end = self.raw.index(b"\0", at)
        return self.raw[at:end].decode()

    def symbol(self, name):
        if name not in self.symbols:
            raise MeterError("symbol not in image: " + name)
        return self.symbols[name][0]


# --- the machine ----------------------------------------------------------------------------------

STACK_REGION = 16 * 1024
PAINT = 0xA5


class Machine:
    def __init__(self, core, image):
        self.core = core
        self.image = image
        if core == "rv32imc":
            self.uc = Uc(UC_ARCH_RISCV, UC_MODE_RISCV32)
            self.flash, self.ram = 0x80000000, 0x80100000
        else:
            self.uc = Uc(UC_ARCH_ARM, UC_MODE_THUMB | UC_MODE_MCLASS)
            self.uc.ctl_set_cpu_model(arm_const.UC_CPU_ARM_CORTEX_M0 if core == "cortex-m0plus"
                                      else arm_const.UC_CPU_ARM_CORTEX_M4)
            self.flash, self.ram = 0x00000000, 0x20000000
        self.ram_size = 256 * 1024
        self.uc.mem_map(self.flash, 1024 * 1024)
        self.uc.mem_map(self.ram, self.ram_size)
        for vaddr, data, memsz in image.segments:
            self.uc.mem_write(vaddr, data + b"\0" * (memsz - len(data)))
        self.stack_top = self.ram + self.ram_size - 64
        self.stack_floor = self.stack_top - STACK_REGION
        self.stop = self.flash + 1024 * 1024 - 256  # the return address: never executed
        self.count = 0
        self.pending = set()
        self.lowest = self.stack_top
        self.violations = []
        self.profile = None  # address -> count, when set (a developer's aid)
        self.uc.hook_add(UC_HOOK_CODE, self._on_code)
        self.uc.hook_add(UC_HOOK_MEM_WRITE, self._on_write, begin=self.stack_floor,
                         end=self.stack_top - 1)

    # Counting, with the IT-block correction and the ARMv6-M check.
    def _on_code(self, uc, address, size, _):
        if address in self.pending:
            self.pending.discard(address)
            return
        self.pending.clear()
        self.count += 1
        if self.profile is not None:
            self.profile[address] = self.profile.get(address, 0) + 1
        if self.core == "rv32imc":
            return
        hw = struct.unpack("<H", uc.mem_read(address, 2))[0]
        if self.core == "cortex-m0plus":
            self._check_v6m(uc, address, size, hw)
        if (hw & 0xFF00) == 0xBF00 and (hw & 0x000F) != 0:  # IT: the block issues in full
            mask = hw & 0xF
            length = 4 - ((mask & -mask).bit_length() - 1)
            at = address + 2
            for _ in range(length):
                first = struct.unpack("<H", uc.mem_read(at, 2))[0]
                self.pending.add(at)
                at += 4 if (first >> 11) in (0x1D, 0x1E, 0x1F) else 2
            self.count += length

    def _check_v6m(self, uc, address, size, hw):
        bad = None
        if size == 4:
            hw2 = struct.unpack("<H", uc.mem_read(address + 2, 2))[0]
            is_bl = (hw & 0xF800) == 0xF000 and (hw2 & 0xD000) == 0xD000
            is_msr_mrs = (hw & 0xFFE0) in (0xF380, 0xF3E0) and (hw2 & 0xC000) == 0x8000
            is_barrier = hw == 0xF3BF and (hw2 & 0xFF00) == 0x8F00
            if not (is_bl or is_msr_mrs or is_barrier):
                bad = f"32-bit {hw:04x} {hw2:04x}"
        elif (hw & 0xFF00) == 0xBF00 and (hw & 0xF) != 0:
            bad = f"IT {hw:04x}"
        elif (hw & 0xF500) == 0xB100:
            bad = f"CBZ/CBNZ {hw:04x}"
        if bad:
            self.violations.append(f"{address:#x}: {bad}")

    def _on_write(self, uc, access, address, size, value, _):
        if address < self.lowest:
            self.lowest = address

    def call(self, name, *args):
        """Calls `name` with integer arguments; returns (result, instructions, stack bytes)."""
        entry = self.image.symbol(name)
        uc = self.uc
        uc.mem_write(self.stack_floor, bytes([PAINT]) * STACK_REGION)
        self.count = 0
        self.pending = set()
        self.lowest = self.stack_top
        if self.core == "rv32imc":
            regs = [riscv_const.UC_RISCV_REG_A0 + i for i in range(4)]
            for r, v in zip(regs, args):
                uc.reg_write(r, v & 0xFFFFFFFF)
            uc.reg_write(riscv_const.UC_RISCV_REG_SP, self.stack_top)
            uc.reg_write(riscv_const.UC_RISCV_REG_RA, self.stop)
            uc.emu_start(entry, self.stop, count=10_000_000)
            result = uc.reg_read(riscv_const.UC_RISCV_REG_A0)
        else:
            regs = [arm_const.UC_ARM_REG_R0, arm_const.UC_ARM_REG_R1, arm_const.UC_ARM_REG_R2,
                    arm_const.UC_ARM_REG_R3]
            for r, v in zip(regs, args):
                uc.reg_write(r, v & 0xFFFFFFFF)
            uc.reg_write(arm_const.UC_ARM_REG_SP, self.stack_top)
            uc.reg_write(arm_const.UC_ARM_REG_LR, self.stop | 1)
            uc.emu_start(entry | 1, self.stop, count=10_000_000)
            result = uc.reg_read(arm_const.UC_ARM_REG_R0)
        pc = uc.reg_read(riscv_const.UC_RISCV_REG_PC if self.core == "rv32imc"
                         else arm_const.UC_ARM_REG_PC)
        if (pc & ~1) != self.stop:
            raise MeterError(f"{name} did not return (pc {pc:#x})")
        if self.violations:
            raise MeterError(f"{name}: not ARMv6-M: " + "; ".join(self.violations[:5]))
        painted = bytes(uc.mem_read(self.stack_floor, STACK_REGION))
        deepest = next((i for i, b in enumerate(painted) if b != PAINT), STACK_REGION)
        hooked_depth = self.stack_top - self.lowest
        painted_depth = self.stack_top - (self.stack_floor + deepest) if deepest < STACK_REGION \
            else 0
        if painted_depth > hooked_depth or hooked_depth - painted_depth > 4:
            raise MeterError(f"{name}: stack paint ({painted_depth} B) and write hook "
                             f"({hooked_depth} B) disagree")
        return result, self.count, hooked_depth

    def write(self, symbol, data):
        self.uc.mem_write(self.image.symbol(symbol), bytes(data))

    def write_u32(self, symbol, value):
        self.write(symbol, struct.pack("<I", value))

    def read(self, symbol, size):
        return bytes(self.uc.mem_read(self.image.symbol(symbol), size))

    def out(self, n=16):
        return list(struct.unpack(f"<{n}I", self.read("meter_out", 4 * n)))

    def out_bytes(self):
        size, address = struct.unpack("<II", self.read("meter_out", 8))
        if size > 256:
            raise MeterError(f"output of {size} bytes")
        return bytes(self.uc.mem_read(address, size)) if size else b""

    def clear_out(self):
        self.write("meter_out", b"\0" * 256)


# --- independent computations -------------------------------------------------------------------

def crc_msb_first(bits, count, width, poly):
    """A non-reflected CRC of `count` bits (MSB first), initial value 0."""
    reg = 0
    top = 1 << (width - 1)
    for i in range(count - 1, -1, -1):
        bit = (bits >> i) & 1
        fb = ((reg & top) != 0) ^ bit
        reg = (reg << 1) & ((1 << width) - 1)
        if fb:
            reg ^= poly
    return reg


def tformat_crc(frame):
    value = int.from_bytes(bytes(frame), "big")
    return crc_msb_first(value, 8 * len(frame), 8, 0x01)  # x^8 + 1


def tformat_cf(code):
    return 0x02 | (code << 3) | ((bin(code).count("1") & 1) << 7)


def le24(v):
    return [v & 0xFF, (v >> 8) & 0xFF, (v >> 16) & 0xFF]


def tformat_id3(abs_, enid, abm, almc=0, sf=0):
    f = [tformat_cf(3), sf] + le24(abs_) + [enid] + le24(abm) + [almc]
    return f + [tformat_crc(f)]


def tformat_id0(abs_, sf=0):
    f = [tformat_cf(0), sf] + le24(abs_)
    return f + [tformat_crc(f)]


def words_msb_first(bits, nwords):
    """Packs a list of 0/1 samples into 32-bit words, the first sample in the MSB."""
    words = []
    for w in range(nwords):
        v = 0
        for k in range(32):
            i = 32 * w + k
            v = (v << 1) | (bits[i] if i < len(bits) else 0)
        words.append(v)
    return b"".join(struct.pack("<I", w) for w in words)


def rng(seed):
    x = seed
    while True:
        x = (x * 1103515245 + 12345) & 0x7FFFFFFF
        yield (x >> 16) & 0xFF


# --- the operations ------------------------------------------------------------------------------

STATUS_INCOMPLETE, STATUS_COMPLETE, STATUS_FAILED = 0, 1, 2


def expect(name, got, want):
    if got != want:
        raise MeterError(f"{name}: output {got!r}, expected {want!r}")


def stream_per_byte(m, op, prefix, report, first, first_out, frame, frame_out, start=()):
    """A stream object (`prefix`_start, `prefix`_byte) in its steady state: `first` fed byte by
    byte (its report must begin with `first_out`), then `frame`, measured: incomplete before
    its last byte, `frame_out` after it. Returns the instructions in all, the worst stack and
    the instructions of the costliest byte, and the instructions and stack of the cheapest (a
    byte inside the frame)."""
    m.call(prefix + "_start", *start)
    ready = 0
    for b in first:
        ready, _, _ = m.call(prefix + "_byte", b)
    m.call(report, ready & 0xFF)
    expect(op + " (the first frame)", m.out(len(first_out)), first_out)
    m.clear_out()
    total, worst, costliest, cheapest = 0, 0, 0, None
    for i, b in enumerate(frame):
        ready, n, s = m.call(prefix + "_byte", b)
        total, worst, costliest = total + n, max(worst, s), max(costliest, n)
        if cheapest is None or n < cheapest[0]:
            cheapest = (n, s)
        m.call(report, ready & 0xFF)
        if i < len(frame) - 1:
            expect(op + " (before the last byte)", m.out(1)[0], STATUS_INCOMPLETE)
    expect(op, m.out(len(frame_out)), frame_out)
    return total, worst, costliest, cheapest


def stream_hostile(m, op, prefix, report, start, seq, failed_at, last_out):
    """A stream object from its start on `seq`, bytes that hold a rejected frame: the report
    after byte `failed_at` must say failed, the one after the last byte begin with
    `last_out`.
    Returns the instructions in all, the worst stack and the instructions of the costliest
    byte."""
    m.call(prefix + "_start", *start)
    m.clear_out()
    total, worst, costliest = 0, 0, 0
    for i, b in enumerate(seq):
        ready, n, s = m.call(prefix + "_byte", b)
        total, worst, costliest = total + n, max(worst, s), max(costliest, n)
        m.call(report, ready & 0xFF)
        if i == failed_at:
            expect(op + f" (byte {i})", m.out(1)[0], STATUS_FAILED)
    expect(op, m.out(len(last_out)), last_out)
    return total, worst, costliest


def ascii_adu(slave, pdu):
    """The Modbus ASCII ADU (Serial Line §2.5.2.1): ':', the hex digits of the address, PDU and
    LRC (the two's complement of their 8-bit sum), CR LF."""
    data = [slave] + pdu
    data.append(-sum(data) & 0xFF)
    return list(b":" + "".join(f"{b:02X}" for b in data).encode() + b"\r\n")


def measure_ascii_framer(m, record):
    """The ASCII framer of a server (issue 25) in its steady state (an FC06 request, then the
    measured FC03 request): instructions per character over the frame
    (modbus.ascii_framer.per_byte.fc03) and at its costliest character (...worst_byte.fc03)."""
    first = [0x06, 0x00, 0x01, 0x00, 0x03]
    pdu = [0x03, 0x00, 0x05, 0x00, 0x0A]
    frame = ascii_adu(1, pdu)
    lrc = -sum([1] + pdu) & 0xFF
    op = "modbus.ascii_framer.per_byte.fc03"
    n, s, worst, _ = stream_per_byte(m, op, "op_modbus_ascii_framer", "op_report_ascii_framer",
                                     ascii_adu(1, first), [STATUS_COMPLETE, 0, 1, 5], frame,
                                     [STATUS_COMPLETE, 0, 1, 5, 3, lrc])
    record(op, round(n / len(frame), 1), s, per="byte", units=len(frame), total=n)
    record("modbus.ascii_framer.worst_byte.fc03", worst, s)


def measure_receiver(m, record, prefix, report, suffix):
    """The T-format receiver in its steady state (a first ID3 response, then the measured one):
    instructions a byte on average and at the costliest byte (the last: decode and check); an
    ID0 exchange; and two hostile lines from the start: an ID3 response with a bad CRC, then a
    good one (the rescan of the bytes held), and an ID0 response to an ID3 request (rejected
    at its last byte: the check against the request)."""
    id3 = tformat_id3(123456, 0x17, 3898, almc=0x00)
    n, s, worst, inside = stream_per_byte(m, "tformat.receiver.id3_per_byte" + suffix, prefix,
                                          report, tformat_id3(1, 0x17, 2),
                                          [STATUS_COMPLETE, 0, 1], id3,
                                          [STATUS_COMPLETE, 0, 123456, 3898, 0, 0x17], (3,))
    record("tformat.receiver.id3_per_byte" + suffix, round(n / len(id3), 1), s, per="byte",
           units=len(id3), total=n)
    record("tformat.receiver.id3_worst_byte" + suffix, worst, s)
    if not suffix:
        record("tformat.receiver.id3_inside_byte", *inside)
    id0 = tformat_id0(98765)
    n, s, worst, _ = stream_per_byte(m, "tformat.receiver.id0_per_byte" + suffix, prefix, report,
                                     tformat_id0(1), [STATUS_COMPLETE, 0, 1], id0,
                                     [STATUS_COMPLETE, 0, 98765], (0,))
    record("tformat.receiver.id0_per_byte" + suffix, round(n / len(id0), 1), s, per="byte",
           units=len(id0), total=n)
    record("tformat.receiver.id0_worst_byte" + suffix, worst, s)
    bad = id3[:-1] + [id3[-1] ^ 0xFF]
    seq = bad + id3
    op = "tformat.receiver.bad_crc_then_id3"
    n, s, worst = stream_hostile(m, op + suffix, prefix, report, (3,), seq, len(bad) - 1,
                                 [STATUS_COMPLETE, 0, 123456, 3898, 0, 0x17])
    record(op + ".per_byte" + suffix, round(n / len(seq), 1), s, per="byte", units=len(seq),
           total=n)
    record(op + ".worst_byte" + suffix, worst, s)
    op = "tformat.receiver.id0_to_id3_request"
    n, s, worst = stream_hostile(m, op + suffix, prefix, report, (3,), id0, len(id0) - 1,
                                 [STATUS_FAILED])
    record(op + ".per_byte" + suffix, round(n / len(id0), 1), s, per="byte", units=len(id0),
           total=n)
    record(op + ".worst_byte" + suffix, worst, s)


def fc10_request(address, values):
    data = []
    for v in values:
        data += [v >> 8, v & 0xFF]
    return rtu(1, [0x10, address >> 8, address & 0xFF, 0, len(values), 2 * len(values)] + data)


# The server framer's measured requests: (name, request ADU). FC03 is the fixed-size case (the
# function code gives the length); FC0F, 10 and 17 carry a byte count, so the framer's rule
# reads the bytes held at each byte until it has the count (the shortest request of each has
# the most such bytes for its length); FC08 Return Query Data has no length rule (any even
# number of data bytes): the CRC is tried at each byte past the fixed size.
SERVER_FRAMER_REQUESTS = (
    ("", rtu(1, [0x03, 0x00, 0x05, 0x00, 0x0A])),
    (".fc10_1", fc10_request(0x20, [0xA000])),
    (".fc10_10", fc10_request(0x20, [(0xA000 + 13 * i) & 0xFFFF for i in range(10)])),
    # the longest request but FC08's (a 255-byte ADU): its last byte's CRC is over 253 bytes
    (".fc10_123", fc10_request(0x00, [(0x5000 + 7 * i) & 0xFFFF for i in range(123)])),
    (".fc0f_1", rtu(1, [0x0F, 0x00, 0x13, 0x00, 0x01, 1, 0x01])),
    (".fc17_1_1", rtu(1, [0x17, 0x00, 0x05, 0x00, 0x01, 0x00, 0x20, 0x00, 0x01, 2, 0x12, 0x34])),
    (".fc08_q4", rtu(1, [0x08, 0x00, 0x00, 0xA5, 0x37])),
    # the longest ADU there is (256 bytes): every byte past the eighth tries the CRC
    (".fc08_q250", rtu(1, [0x08, 0x00, 0x00] + [(37 * i + 11) & 0xFF for i in range(250)])),
)


def measure_server_framer(m, record, prefix, report, suffix):
    """The server's framer (rtu_server_framer) in its steady state (an FC06 request, then the
    measured one) on each of SERVER_FRAMER_REQUESTS: instructions a byte on average
    (modbus.framer.per_byte<request>) and at its costliest byte (modbus.framer.worst_byte...).
    """
    first = rtu(1, [0x06, 0x00, 0x01, 0x00, 0x03])
    for name, request in SERVER_FRAMER_REQUESTS:
        op = "modbus.framer.per_byte" + name + suffix
        n, s, worst, inside = stream_per_byte(
            m, op, prefix, report, first, [STATUS_COMPLETE, 0, 1, 5], request,
            [STATUS_COMPLETE, 0, 1, len(request) - 3, request[1],
             request[-2] | (request[-1] << 8)])
        record(op, round(n / len(request), 1), s, per="byte", units=len(request), total=n)
        record("modbus.framer.worst_byte" + (name or ".fc03") + suffix, worst, s)
        if not name and not suffix:
            record("modbus.framer.inside_byte.fc03", *inside)


def measure_framer_noise(m, record):
    """The server's framer on 256 bytes of noise (rng(11): no frame in them, as the checks say)
    and the silence after them, through the C API (its image links idle(), as every server's
    firmware does; the main image's framer figures are measured without it): instructions a
    byte on average and at the costliest byte, and the idle() call that ends the noise (the
    bytes held rescanned, a frame looked for at each of them)."""
    r = rng(11)
    noise = [next(r) for _ in range(256)]
    m.call("op_capi_framer_start")
    total, worst, costliest = 0, 0, 0
    for b in noise:
        ready, n, s = m.call("op_capi_framer_byte", b)
        total, worst, costliest = total + n, max(worst, s), max(costliest, n)
        m.call("op_capi_report_framer", ready & 0xFF)
        if m.out(1)[0] == STATUS_COMPLETE:
            raise MeterError("capi.modbus.framer.per_byte.noise256: a frame in the noise")
    record("capi.modbus.framer.per_byte.noise256", round(total / len(noise), 1), worst,
           per="byte", units=len(noise), total=total)
    record("capi.modbus.framer.worst_byte.noise256", costliest, worst)
    m.clear_out()
    _, n, s = m.call("op_capi_framer_idle")
    expect("capi.modbus.framer.idle.noise256", m.out(1)[0], STATUS_FAILED)
    record("capi.modbus.framer.idle.noise256", n, s)


def measure_alone(m):
    """The stream objects, each alone in its translation unit (tests/meter/alone_*.cpp), as in
    a firmware whose receive interrupt's file holds nothing else: the compiler's inlining, and
    so the stack, differ from the image where everything is (the '.alone' operations)."""
    results = []

    def record(op, instructions, stack, **extra):
        results.append(dict(operation=op, instructions=instructions, stack_bytes=stack, **extra))

    measure_receiver(m, record, "op_alone_receiver", "op_alone_report_receiver", ".alone")
    measure_server_framer(m, record, "op_alone_framer", "op_alone_report_framer", ".alone")
    measure_gateway(m, record, ".alone")
    return results


def measure_gateway(m, record, suffix):
    """The gateway core (alone_gateway.cpp): one transaction, FC03 of 10 registers of unit 1,
    each step alone: the MBAP request taken, the RTU request written to the line, the RTU
    response taken into the MBAP response."""
    def once(fn, *args):
        m.clear_out()
        _, n, s = m.call(fn, *args)
        return n, s

    mbap = [0x12, 0x34, 0, 0, 0, 6, 1, 0x03, 0x00, 0x05, 0x00, 0x0A]
    m.write("meter_gateway_in", mbap)
    m.write_u32("meter_gateway_in_size", len(mbap))
    op = "modbus.gateway.from_client.fc03_10" + suffix
    n, s = once("op_alone_gateway_from_client")
    expect(op, m.out(4)[2:], [1, len(mbap)])  # queued, every byte taken
    record(op, n, s)
    op = "modbus.gateway.poll.fc03_10" + suffix
    n, s = once("op_alone_gateway_poll", 0)
    expect(op, list(m.out_bytes()), rtu(1, mbap[7:]))
    expect(op + " action", m.out(4)[2], 3)  # to_line
    record(op, n, s)
    data = []
    for i in range(10):
        data += [0x40 + i, i]
    response = rtu(1, [0x03, 20] + data)
    m.write("meter_gateway_in", response)
    m.write_u32("meter_gateway_in_size", len(response))
    op = "modbus.gateway.from_line.fc03_10" + suffix
    n, s = once("op_alone_gateway_from_line", 20000)
    expect(op, list(m.out_bytes()), [0x12, 0x34, 0, 0, 0, 23, 1, 0x03, 20] + data)
    expect(op + " action", m.out(4)[2:], [2, len(response)])  # to_client, every byte taken
    record(op, n, s)


def measure(m):
    results = []

    def record(op, instructions, stack, **extra):
        results.append(dict(operation=op, instructions=instructions, stack_bytes=stack, **extra))

    def once(op, fn, *args):
        m.clear_out()
        _, n, s = m.call(fn, *args)
        return n, s

    # T-format
    n, s = once("tformat.encode_request.id3", "op_tformat_encode_request_id3")
    expect("tformat.encode_request.id3", list(m.out_bytes()), [tformat_cf(3)])
    record("tformat.encode_request.id3", n, s)
    n, s = once("tformat.encode_request.id6", "op_tformat_encode_request_id6", 0x15, 0xA7)
    q = [tformat_cf(6), 0x15, 0xA7]
    expect("tformat.encode_request.id6", list(m.out_bytes()), q + [tformat_crc(q)])
    record("tformat.encode_request.id6", n, s)

    id3 = tformat_id3(123456, 0x17, 3898, almc=0x00)
    id0 = tformat_id0(98765)
    for op, frame, fields in (("tformat.decode_response.id0", id0, [98765, 0, 0, 0]),
                              ("tformat.decode_response.id3", id3, [123456, 3898, 0, 0x17])):
        m.write("meter_in", frame)
        m.write_u32("meter_in_size", len(frame))
        n, s = once(op, "op_tformat_decode_response")
        m.call("op_report_tformat")
        o = m.out(8)
        expect(op, o[:6], [STATUS_COMPLETE, 0] + fields)
        expect(op + " cf", o[7], frame[0])
        record(op, n, s)

    # The receiver in its steady state: a first response, then the measured one.
    measure_receiver(m, record, "op_tformat_receiver", "op_report_receiver", "")

    samples = [1] * 5
    for b in id3:
        samples += [0] + [(b >> k) & 1 for k in range(8)] + [1]
    nbits = len(samples)
    m.write("meter_in", words_msb_first(samples + [1] * 32, 4))
    m.write_u32("meter_in_size", nbits)
    n, s = once("tformat.line.decode_id3", "op_tformat_line_decode")
    m.call("op_report_line")
    o = m.out(9)
    expect("tformat.line.decode_id3", o[:6] + [o[8]], [STATUS_COMPLETE, 0, 123456, 3898, 0, 0x17,
                                                       5])
    record("tformat.line.decode_id3", n, s)

    m.call("op_tformat_encoder_setup", 0x1E240, 77)
    m.write("meter_in", [tformat_cf(3)])
    m.write_u32("meter_in_size", 1)
    n, s = once("tformat.encoder_model.respond_id3", "op_tformat_encoder_respond", 1000)
    expect("tformat.encoder_model.respond_id3", list(m.out_bytes()),
           tformat_id3(0x1E240, 0x11, 77))
    record("tformat.encoder_model.respond_id3", n, s)
    # An EEPROM write (ID6), the costliest request of the emulator's: answered with its echo
    # (T-format specification, the ID6 frame: CF ADF EDF CRC) once the line is idle.
    q = [tformat_cf(6), 0x05, 0x42]
    q.append(tformat_crc(q))
    m.write("meter_in", q)
    m.write_u32("meter_in_size", len(q))
    n, s = once("tformat.encoder_model.respond_id6", "op_tformat_encoder_respond", 31000)
    expect("tformat.encoder_model.respond_id6", list(m.out_bytes()), q)
    record("tformat.encoder_model.respond_id6", n, s)

    # Modbus
    r = rng(7)
    block = [next(r) for _ in range(256)]
    m.write("meter_in", block)
    m.write_u32("meter_in_size", len(block))
    for table in ("bitwise", "nibble", "byte"):
        op = "modbus.crc16.per_byte." + table
        n, s = once(op, "op_modbus_crc16_" + table)
        expect(op, m.out(1)[0], crc16_modbus(block))
        record(op, round(n / len(block), 1), s, per="byte", units=len(block), total=n)

    # The server's framer in its steady state (a first frame, then the measured one), and the
    # framer whose role is chosen at run time.
    measure_server_framer(m, record, "op_modbus_framer", "op_report_framer", "")
    request = rtu(1, [0x03, 0x00, 0x05, 0x00, 0x0A])
    n, s, _, _ = stream_per_byte(m, "modbus.framer.per_byte.either_role", "op_modbus_either_framer",
                              "op_report_either_framer", rtu(1, [0x06, 0x00, 0x01, 0x00, 0x03]),
                              [STATUS_COMPLETE, 0, 1, 5], request,
                              [STATUS_COMPLETE, 0, 1, 5, 3, request[-2] | (request[-1] << 8)])
    record("modbus.framer.per_byte.either_role", round(n / len(request), 1), s, per="byte",
           units=len(request), total=n)

    measure_ascii_framer(m, record)

    m.write("meter_in", request)
    m.write_u32("meter_in_size", len(request))
    n, s = once("modbus.decode_rtu.fc03_request", "op_modbus_decode_rtu")
    m.call("op_report_rtu")
    expect("modbus.decode_rtu.fc03_request", m.out(6),
           [STATUS_COMPLETE, 0, 1, 5, 3, request[-2] | (request[-1] << 8)])
    record("modbus.decode_rtu.fc03_request", n, s)

    values = [(0x1234 + 0x9E37 * i) & 0xFFFF for i in range(125)]
    payload = []
    for v in values:
        payload += [v >> 8, v & 0xFF]
    response = rtu(0x11, [0x03, 250] + payload)
    m.write("meter_in", response)
    m.write_u32("meter_in_size", len(response))
    n, s = once("modbus.client.fc03_125", "op_modbus_client_fc03", 125)
    m.call("op_report_client")
    mix = 0
    for v in values:
        mix = ((mix * 31) & 0xFFFFFFFF) ^ v
    expect("modbus.client.fc03_125", m.out(5), [STATUS_COMPLETE, 0, 125, sum(values), mix])
    record("modbus.client.fc03_125", n, s)

    registers = [(0x1000 + 7 * i) & 0xFFFF for i in range(128)]
    m.write("meter_registers", b"".join(struct.pack("<H", v) for v in registers))
    request = rtu(1, [0x03, 0x00, 0x05, 0x00, 0x0A])
    m.write("meter_in", request)
    m.write_u32("meter_in_size", len(request))
    data = []
    for v in registers[5:15]:
        data += [v >> 8, v & 0xFF]
    n, s = once("modbus.serve_rtu.fc03_10", "op_modbus_serve")
    expect("modbus.serve_rtu.fc03_10", list(m.out_bytes()), rtu(1, [0x03, 20] + data))
    record("modbus.serve_rtu.fc03_10", n, s)
    m.call("op_modbus_decode_rtu")
    n, s = once("modbus.serve.fc03_10", "op_modbus_serve_frame")
    expect("modbus.serve.fc03_10", list(m.out_bytes()), rtu(1, [0x03, 20] + data))
    record("modbus.serve.fc03_10", n, s)

    written = [(0xA000 + 13 * i) & 0xFFFF for i in range(10)]
    data = []
    for v in written:
        data += [v >> 8, v & 0xFF]
    request = rtu(1, [0x10, 0x00, 0x20, 0x00, 0x0A, 20] + data)
    m.write("meter_in", request)
    m.write_u32("meter_in_size", len(request))
    n, s = once("modbus.serve_rtu.fc10_10", "op_modbus_serve")
    expect("modbus.serve_rtu.fc10_10", list(m.out_bytes()),
           rtu(1, [0x10, 0x00, 0x20, 0x00, 0x0A]))
    now = struct.unpack("<128H", m.read("meter_registers", 256))
    expect("modbus.serve_rtu.fc10_10 registers", list(now[0x20:0x2A]), written)
    record("modbus.serve_rtu.fc10_10", n, s)
    m.write("meter_registers", b"\0" * 256)
    m.call("op_modbus_decode_rtu")
    n, s = once("modbus.serve.fc10_10", "op_modbus_serve_frame")
    expect("modbus.serve.fc10_10", list(m.out_bytes()), rtu(1, [0x10, 0x00, 0x20, 0x00, 0x0A]))
    now = struct.unpack("<128H", m.read("meter_registers", 256))
    expect("modbus.serve.fc10_10 registers", list(now[0x20:0x2A]), written)
    record("modbus.serve.fc10_10", n, s)

    n, s = once("modbus.encode_request.fc03", "op_modbus_encode_request_fc03", 0x006B, 3)
    expect("modbus.encode_request.fc03", list(m.out_bytes()),
           rtu(17, [0x03, 0x00, 0x6B, 0x00, 0x03]))
    record("modbus.encode_request.fc03", n, s)

    # BiSS-C
    position = 0x89ABCDEF
    data34 = (position << 2) | 0b11  # nE = 1, nW = 1: no error, no warning
    crc = crc_msb_first(data34, 34, 6, 0x03) ^ 0x3F  # x^6 + x + 1, sent inverted
    frame = [1, 1, 1, 0, 0, 1, 0] + [(data34 >> i) & 1 for i in range(33, -1, -1)] + \
            [(crc >> i) & 1 for i in range(5, -1, -1)]
    m.write("meter_in", words_msb_first(frame, 2))
    m.write_u32("meter_in_size", 64)
    n, s = once("biss.decode_frame.absys64", "op_biss_decode_frame")
    m.call("op_report_biss")
    expect("biss.decode_frame.absys64", m.out(6), [STATUS_COMPLETE, 0, position, 3, crc, 5])
    record("biss.decode_frame.absys64", n, s)

    n, s = once("biss.crc6.frame34", "op_biss_crc6", data34 >> 32, data34 & 0xFFFFFFFF)
    expect("biss.crc6.frame34", m.out(1)[0], crc)
    record("biss.crc6.frame34", n, s)

    regs = [(0x30 + 5 * i) & 0xFF for i in range(128)]
    m.write("meter_in", regs)
    m.clear_out()
    m.call("op_biss_control_start", 0x42)
    expect("biss.control_master start", m.out(2)[1], 0)
    total, worst, frames, cds = 0, 0, 0, 0
    slave_total, slave_worst = 0, 0
    while frames < 200:
        cdm, n, s = m.call("op_biss_master_step", cds)
        total, worst, frames = total + n, max(worst, s), frames + 1
        cds, n, s = m.call("op_biss_slave_step", cdm)
        slave_total, slave_worst = slave_total + n, max(slave_worst, s)
        m.call("op_report_control")
        if m.out(1)[0] != 1:  # control_state::busy
            break
    o = m.out(5)
    expect("biss.control_master.per_frame", [o[0], o[2], o[3], o[4]],
           [2, regs[0x42], regs[0x43], 0])  # control_state::done, the two registers, errc::ok
    record("biss.control_master.per_frame", round(total / frames, 1), worst, per="frame",
           units=frames, total=total)
    record("biss.control_slave.per_frame", round(slave_total / frames, 1), slave_worst,
           per="frame", units=frames, total=slave_total)

    # Device emulators. ABSYS: one frame (1 idle bit, 1 Ack bit, Start, CDS 0, the position,
    # nE = nW = 1, the inverted CRC6), then the master's CDM bit.
    position = 0x0001E240
    m.call("op_absys_setup", position)
    n, s = once("devices.absys.frame", "op_absys_frame")
    data34 = (position << 2) | 0b11
    crc = crc_msb_first(data34, 34, 6, 0x03) ^ 0x3F
    bits = [1, 0, 1, 0] + [(data34 >> i) & 1 for i in range(33, -1, -1)] + \
        [(crc >> i) & 1 for i in range(5, -1, -1)]
    o = m.out(3)
    got = [((o[1 + k // 32] >> (31 - k % 32)) & 1) for k in range(len(bits))]
    expect("devices.absys.frame", got, bits)
    expect("devices.absys.frame bits", o[0] >= len(bits), True)
    record("devices.absys.frame", n, s)
    # SM unit: FC03 of the settings 36..38 (over-heat 80.0 degC, shock 50.00 m/s2, log interval
    # 1.0 s: the emulator's factory settings), served from the request ADU.
    request = rtu(1, [0x03, 0x00, 36, 0x00, 3])
    m.write("meter_in", request)
    m.write_u32("meter_in_size", len(request))
    n, s = once("devices.sm_unit.serve_fc03_3", "op_sm_unit_serve")
    expect("devices.sm_unit.serve_fc03_3", list(m.out_bytes()),
           rtu(1, [0x03, 6, 800 >> 8, 800 & 0xFF, 5000 >> 8, 5000 & 0xFF, 0, 10]))
    record("devices.sm_unit.serve_fc03_3", n, s)
    measure_position(m, record)
    return results


def measure_position(m, record):
    """The position tracker (core/position.hpp) per read: an ID3 reading whose step crosses the
    TS5700N8500's multi-turn counter wrap (65535 -> 0), an ID0 reading crossing the single-turn
    rollover; the link health (core/link_health.hpp) per transaction."""
    turn = 1 << 17
    m.call("op_position_setup", turn - 300, 65535)
    m.clear_out()
    _, n, s = m.call("op_position_update_id3", 250, 0)
    o = m.out(4)
    counts = ((65535 << 17) + turn - 300) + 550  # +550 across the wrap: past 2^33
    expect("position.update.id3_wrap", o, [0, counts & 0xFFFFFFFF, counts >> 32, 550])
    record("position.update.id3_wrap", n, s)
    m.clear_out()
    _, n, s = m.call("op_position_update_id0", 250)
    o = m.out(4)
    expect("position.update.id0_rollover", o, [0, turn + 250, 0, 550])
    record("position.update.id0_rollover", n, s)
    # an impossible step (half a turn) is reported, the position kept
    m.clear_out()
    _, n, s = m.call("op_position_update_id0", 250 + turn // 2)
    expect("position.update.id0_implausible", m.out(4), [2, turn + 250, 0, 550])
    record("position.update.id0_implausible", n, s)
    # link health: three failures (crc_error = 2), the third losing a link that was up
    for outcome in (0, 0, 0):
        m.call("op_link_health_record", outcome)
    worst_n, worst_s = 0, 0
    for k, outcome in enumerate((2, 3, 2)):
        m.clear_out()
        _, n, s = m.call("op_link_health_record", outcome)
        worst_n, worst_s = max(worst_n, n), max(worst_s, s)
        expect("link_health.record", m.out(3), [1 if k == 2 else 0, k + 1, 4 + k])
    record("link_health.record", worst_n, worst_s)


def per_request(rows, prefix, suffix):
    """A whole FC03 request of 10 registers served: its 8 bytes through the server framer
    (`prefix`.framer.per_byte, their total) and the frame served (`prefix`.serve.fc03_10),
    both measured in the same image; stack: the worse of the two."""
    framer = next(r for r in rows if r["operation"] == prefix + ".framer.per_byte" + suffix)
    serve = next(r for r in rows if r["operation"] == prefix + ".serve.fc03_10" + suffix)
    return [dict(operation=prefix + ".request.fc03_10" + suffix,
                 instructions=framer["total"] + serve["instructions"],
                 stack_bytes=max(framer["stack_bytes"], serve["stack_bytes"]))]


def measure_capi(m):
    """The C API (c/include/motionbus/c.h) in its own image (tests/meter/capi_ops.cpp and
    c/motionbus_c.cpp): the calls a C firmware makes, each checked as its C++ twin in
    measure() is: a CRC-16 over 256 bytes, an ID3 response decoded and received byte by byte
    by the stream receiver, the server framer fed an
    FC03 request byte by byte and the frame served through a callback table, a BiSS-C frame
    decoded, and the control master reading two registers."""
    results = []

    def record(op, instructions, stack, **extra):
        results.append(dict(operation=op, instructions=instructions, stack_bytes=stack, **extra))

    def once(fn, *args):
        m.clear_out()
        _, n, s = m.call(fn, *args)
        return n, s

    r = rng(7)
    block = [next(r) for _ in range(256)]
    m.write("meter_in", block)
    m.write_u32("meter_in_size", len(block))
    n, s = once("op_capi_crc16")
    expect("capi.crc16_modbus.per_byte", m.out(1)[0], crc16_modbus(block))
    record("capi.crc16_modbus.per_byte", round(n / len(block), 1), s, per="byte",
           units=len(block), total=n)

    id3 = tformat_id3(123456, 0x17, 3898, almc=0x00)
    m.write("meter_in", id3)
    m.write_u32("meter_in_size", len(id3))
    n, s = once("op_capi_tformat_decode_response")
    m.call("op_capi_report_tformat")
    o = m.out(8)
    expect("capi.tformat.decode_response.id3", o[:6] + [o[7]],
           [STATUS_COMPLETE, 0, 123456, 3898, 0, 0x17, id3[0]])
    record("capi.tformat.decode_response.id3", n, s)
    n, s, worst, _ = stream_per_byte(m, "capi.tformat.receiver.id3_per_byte", "op_capi_receiver",
                                     "op_capi_report_receiver", tformat_id3(1, 0x17, 2),
                                     [STATUS_COMPLETE, 0, 1], id3,
                                     [STATUS_COMPLETE, 0, 123456, 3898, 0, 0x17], (3,))
    record("capi.tformat.receiver.id3_per_byte", round(n / len(id3), 1), s, per="byte",
           units=len(id3), total=n)
    record("capi.tformat.receiver.id3_worst_byte", worst, s)

    request = rtu(1, [0x03, 0x00, 0x05, 0x00, 0x0A])
    first = rtu(1, [0x06, 0x00, 0x01, 0x00, 0x03])
    n, s, worst, _ = stream_per_byte(
        m, "capi.modbus.framer.per_byte", "op_capi_framer", "op_capi_report_framer", first,
        [STATUS_COMPLETE, 0, 1, 5], request,
        [STATUS_COMPLETE, 0, 1, 5, 3, request[-2] | (request[-1] << 8)])
    record("capi.modbus.framer.per_byte", round(n / len(request), 1), s, per="byte",
           units=len(request), total=n)
    record("capi.modbus.framer.worst_byte.fc03", worst, s)
    registers = [(0x1000 + 7 * i) & 0xFFFF for i in range(128)]
    m.write("meter_registers", b"".join(struct.pack("<H", v) for v in registers))
    data = []
    for v in registers[5:15]:
        data += [v >> 8, v & 0xFF]
    n, s = once("op_capi_serve_frame")
    expect("capi.modbus.serve.fc03_10", list(m.out_bytes()), rtu(1, [0x03, 20] + data))
    expect("capi.modbus.serve.fc03_10 error", m.out(3)[2], 0)
    record("capi.modbus.serve.fc03_10", n, s)

    position = 0x89ABCDEF
    data34 = (position << 2) | 0b11
    crc = crc_msb_first(data34, 34, 6, 0x03) ^ 0x3F
    frame = [1, 1, 1, 0, 0, 1, 0] + [(data34 >> i) & 1 for i in range(33, -1, -1)] + \
            [(crc >> i) & 1 for i in range(5, -1, -1)]
    m.write("meter_in", words_msb_first(frame, 4))
    m.write_u32("meter_in_size", 64)
    n, s = once("op_capi_biss_decode_frame")
    m.call("op_capi_report_biss")
    expect("capi.biss.decode_frame.absys64", m.out(6), [STATUS_COMPLETE, 0, position, 3, crc, 5])
    record("capi.biss.decode_frame.absys64", n, s)

    regs = [(0x30 + 5 * i) & 0xFF for i in range(128)]
    m.write("meter_in", regs)
    m.clear_out()
    m.call("op_capi_control_start", 0x42)
    expect("capi.biss.control_master start", m.out(2)[1], 0)
    total, worst, frames, cds = 0, 0, 0, 0
    while frames < 200:
        cdm, n, s = m.call("op_capi_master_step", cds)
        total, worst, frames = total + n, max(worst, s), frames + 1
        cds, _, _ = m.call("op_capi_slave_step", cdm)
        m.call("op_capi_report_control")
        if m.out(1)[0] != 1:  # busy
            break
    o = m.out(5)
    expect("capi.biss.control_master.per_frame", [o[0], o[2], o[3], o[4]],
           [2, regs[0x42], regs[0x43], 0])
    record("capi.biss.control_master.per_frame", round(total / frames, 1), worst, per="frame",
           units=frames, total=total)
    measure_framer_noise(m, record)  # last: it leaves the framer's frame buffer on the noise
    return results


def self_check(m):
    """The meter against code of known instruction count and stack use."""
    for n in (1, 10, 100):
        _, count, stack = m.call("selfcheck_loop", n)
        if count != 2 + 2 * n or stack != 0:
            raise MeterError(f"self-check: loop of {n} counted {count} instructions "
                             f"(want {2 + 2 * n}), {stack} B of stack (want 0)")
    _, count, stack = m.call("selfcheck_stack", 7)
    if count != 4 or stack != 64:
        raise MeterError(f"self-check: stack probe counted {count} instructions, {stack} B "
                         f"(want 4, 64)")
    if m.core == "cortex-m0plus":
        try:
            m.call("selfcheck_thumb2", 1)
        except MeterError as e:
            if "not ARMv6-M" not in str(e):
                raise
            m.violations = []
        else:
            raise MeterError("self-check: a Thumb-2 instruction passed the ARMv6-M check")
    if m.core == "cortex-m4":
        for arg, want in ((0, 1), (1, 2)):
            result, count, _ = m.call("selfcheck_it", arg)
            if count != 5 or result != want:
                raise MeterError(f"self-check: IT block ({arg}) counted {count} instructions "
                                 f"(want 5), result {result}")


def load(elf):
    image = Image(elf)
    if ".init_array" in image.section_names:
        raise MeterError(elf + ": the meter image needs run-time construction (.init_array)")
    return image


def cmd_run(a):
    tools = json.loads(a.tools)
    elf = build(a.core, a.opt, a.out, a.include, tools)
    m = Machine(a.core, load(elf))
    self_check(m)
    rows = [dict(core=a.core, opt=a.opt, **r) for r in measure(m)]
    alone = load(build(a.core, a.opt, a.out, a.include, tools, "-alone"))
    rows += [dict(core=a.core, opt=a.opt, **r) for r in measure_alone(Machine(a.core, alone))]
    rows += [dict(core=a.core, opt=a.opt, **r) for r in per_request(rows, "modbus", "")]
    capi = load(build(a.core, a.opt, a.out, a.include, tools, "-capi"))
    capi_rows = measure_capi(Machine(a.core, capi))
    capi_rows += per_request(capi_rows, "capi.modbus", "")
    rows += [dict(core=a.core, opt=a.opt, **r) for r in capi_rows]
    path = os.path.join(a.out, f"meter-{a.core}-{a.opt}.json")
    with open(path, "w") as f:
        json.dump(rows, f, indent=1)
    for r in rows:
        print(f"{r['core']:14} {r['opt']:3} {r['operation']:36} {r['instructions']:>8} "
              f"{r['stack_bytes']:>6} B")


def over_budget(row, budget):
    return any(key in budget and row[key] > budget[key]
               for key in ("instructions", "stack_bytes"))


def cmd_report(a):
    rows = []
    missing = []
    for core in CORES:
        for opt in OPTS:
            path = os.path.join(a.out, f"meter-{core}-{opt}.json")
            if not os.path.exists(path):
                missing.append(path)
                continue
            with open(path) as f:
                rows += json.load(f)
    if missing:
        raise MeterError("no measurements: " + ", ".join(missing))
    if not a.expect_breaks:
        with open(os.path.join(a.out, "meter.json"), "w") as f:
            json.dump(rows, f, indent=1)
    with open(a.budgets) as f:
        budgets = json.load(f)
    failures = []
    for b in budgets["budgets"]:
        row = next((r for r in rows if r["core"] == b["core"] and r["opt"] == b["opt"] and
                    r["operation"] == b["operation"]), None)
        if row is None:
            failures.append(f"{b['operation']} ({b['core']} -{b['opt']}): not measured")
            continue
        if a.expect_breaks:
            # Each budget set just below its figure, one at a time: each must be reported.
            for key in ("instructions", "stack_bytes"):
                tight = dict(b, **{key: row[key] - 1})
                if not over_budget(row, tight):
                    failures.append(f"{b['operation']}: {key} one below its figure not caught")
            continue
        if over_budget(row, b):
            failures.append(f"{b['operation']} ({b['core']} -{b['opt']}): "
                            f"{row['instructions']} instructions, {row['stack_bytes']} B: over "
                            f"the budget of {b.get('instructions', '-')} instructions, "
                            f"{b.get('stack_bytes', '-')} B")
        print(f"budget {b['operation']:36} {b['core']} -{b['opt']}: "
              f"{row['instructions']} instructions (<= {b.get('instructions', '-')}), "
              f"{row['stack_bytes']} B (<= {b.get('stack_bytes', '-')})")
    for t in budgets.get("targets", []):
        row = next((r for r in rows if r["core"] == t["core"] and r["opt"] == t["opt"] and
                    r["operation"] == t["operation"]), None)
        if row is None:
            failures.append(f"{t['operation']} ({t['core']} -{t['opt']}): not measured")
            continue
        state = "not met" if over_budget(row, t) else "met"
        print(f"target {t['operation']:36} {t['core']} -{t['opt']}: "
              f"{row['instructions']} instructions (target {t['instructions']}), "
              f"{row['stack_bytes']} B (target {t['stack_bytes']}): {state}")
    if a.expect_breaks:
        if failures:
            raise MeterError("the budget check missed:\n  " + "\n  ".join(failures))
        print(f"every budget ({len(budgets['budgets'])}), set one below its figure, fails")
        return
    ops = []
    for r in rows:
        if r["operation"] not in ops:
            ops.append(r["operation"])
    lines = ["| operation | " + " | ".join(f"{c} -{o}" for c in CORES for o in OPTS) + " |",
             "|---|" + "---:|" * (len(CORES) * len(OPTS))]
    for op in ops:
        cells = []
        for c in CORES:
            for o in OPTS:
                r = next(x for x in rows if x["core"] == c and x["opt"] == o and
                         x["operation"] == op)
                cells.append(f"{r['instructions']} / {r['stack_bytes']} B")
        lines.append(f"| `{op}` | " + " | ".join(cells) + " |")
    table = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "meter.md"), "w") as f:
        f.write(table)
    print(table)
    if failures:
        raise MeterError("over budget:\n  " + "\n  ".join(failures))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run")
    r.add_argument("--core", choices=CORES, required=True)
    r.add_argument("--opt", choices=OPTS, required=True)
    r.add_argument("--out", required=True)
    r.add_argument("--include", required=True)
    r.add_argument("--tools", required=True, help="JSON: arm_gxx, clangxx, riscv_ld, newlib_cxx")
    r.set_defaults(fn=cmd_run)
    q = sub.add_parser("report")
    q.add_argument("--out", required=True)
    q.add_argument("--budgets", required=True)
    q.add_argument("--expect-breaks", action="store_true",
                   help="set each budget one below its figure and require that it fails; "
                        "writes nothing")
    q.set_defaults(fn=cmd_report)
    a = p.parse_args()
    try:
        a.fn(a)
    except MeterError as e:
        print("meter: " + str(e), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
