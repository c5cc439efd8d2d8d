"""The RTU framer (modbus/framer.hpp, server and client roles) against pymodbus 3.0's
ModbusRtuFramer on random streams from a fixed seed: valid frames, frames for other nodes,
noise bytes, frames with bit flips and frames cut short, in bursts. Every frame either framer
accepts is compared; a difference of a class docs/modbus.md §14 lists is counted by class, any
other fails the test.

What each framer knows. pymodbus's framer has no t3.5: it gets the bytes in the chunks its
transport reads, here one chunk a burst (what a serial read returns after a silence), and uses
the chunks only in that a failed check drops what it holds at that moment. The library's
framer is run twice: with frame_end::length (the byte stream alone: chunking changes nothing,
the information pymodbus has; this is the comparison) and with frame_end::silence, told of the
silence after each burst by idle() (information pymodbus lacks: its figures are reported, and
every valid frame alone in its burst must be read).

A server (address 0x11) gets requests for it, broadcasts and requests for other addresses; a
client gets, after each request, its response (normal or exception) among responses of other
slaves, responses to other functions, noise, corrupted and cut copies; each exchange starts
both framers empty (pymodbus's transaction manager resets its framer per request).

Usage: pymodbus_framer_differential.py FRAMERS_TOOL [--seed N] [--frames N] [--exchanges N]
Exit 0: every difference is of a documented class.
"""
import argparse
import collections
import random
import struct
import sys

import pymodbus_framers as shared
from pymodbus.factory import ClientDecoder, ServerDecoder
from pymodbus.framer.rtu_framer import ModbusRtuFramer
from pymodbus.utilities import computeCRC

ADDRESS = 0x11  # the server's
USER_FUNCTIONS = list(range(0x41, 0x49)) + list(range(0x64, 0x6F))  # no length rule anywhere
FLUSH = b"\xff" * 300  # the end of a server stream: no framer frames it, each drops what it held


def u16(x):
    return struct.pack(">H", x & 0xFFFF)


def adu(unit, pdu):
    packet = bytes([unit]) + pdu
    return packet + struct.pack(">H", computeCRC(packet))


def random_bytes(rng, n):
    return bytes(rng.randrange(256) for _ in range(n))


def packed_bits(rng, quantity):
    data = bytearray(random_bytes(rng, (quantity + 7) // 8))
    if quantity % 8:
        data[-1] &= (1 << (quantity % 8)) - 1  # unused high bits 0
    return bytes(data)


def random_request(rng, client=False):
    """A request PDU as the specification defines it, random fields within its limits (no
    FC07/0B/0C/11: without fields their frames repeat, and a frame's bytes identify it here;
    a client sends no FC2B: pymodbus 3.0 raises on a part of its response, not a framing
    question)."""
    functions = [1, 2, 3, 4, 5, 6, 0x0F, 0x10, 0x16, 0x17, 0x08, 0x18] + ([] if client else [0x2B])
    f = rng.choice(functions)
    a = u16(rng.randrange(0x10000))
    if f in (1, 2):
        return bytes([f]) + a + u16(rng.randint(1, 2000))
    if f in (3, 4):
        return bytes([f]) + a + u16(rng.randint(1, 125))
    if f == 5:
        return bytes([f]) + a + u16(rng.choice([0xFF00, 0]))
    if f == 6:
        return bytes([f]) + a + u16(rng.randrange(0x10000))
    if f == 0x0F:
        q = rng.randint(1, 400)
        data = packed_bits(rng, q)
        return bytes([f]) + a + u16(q) + bytes([len(data)]) + data
    if f == 0x10:
        q = rng.randint(1, 40)
        return bytes([f]) + a + u16(q) + bytes([2 * q]) + random_bytes(rng, 2 * q)
    if f == 0x16:
        return bytes([f]) + a + random_bytes(rng, 4)
    if f == 0x17:
        q = rng.randint(1, 30)
        return (bytes([f]) + a + u16(rng.randint(1, 125)) + u16(rng.randrange(0x10000)) + u16(q)
                + bytes([2 * q]) + random_bytes(rng, 2 * q))
    if f == 0x08:
        if rng.random() < 0.5:  # Return Query Data: any even number of bytes, 2 the commonest
            return bytes([f, 0, 0]) + random_bytes(rng, 2 * (1 if rng.random() < 0.5
                                                              else rng.randint(2, 12)))
        return bytes([f]) + u16(rng.choice([1, 2, 3, 4, 0x0A, 0x0B, 0x0C, 0x0D, 0x0E])) + \
            random_bytes(rng, 2)
    if f == 0x18:
        return bytes([f]) + a
    return bytes([0x2B, 0x0E, rng.randint(1, 4), rng.randrange(256)])


def response_to(rng, req):
    """A valid response PDU to the request PDU `req`: normal, or an exception (one in 8)."""
    f = req[0]
    if rng.random() < 0.125:
        return bytes([f | 0x80, rng.choice([1, 2, 3, 4, 6])])
    if f in (1, 2):
        data = packed_bits(rng, struct.unpack(">H", req[3:5])[0])
        return bytes([f, len(data)]) + data
    if f in (3, 4, 0x17):
        n = 2 * struct.unpack(">H", req[3:5])[0]
        return bytes([f, n]) + random_bytes(rng, n)
    if f in (0x0F, 0x10):
        return req[:5]
    if f == 0x08 and req[1:3] != b"\0\0":
        return req[:3] + random_bytes(rng, 2)  # a counter
    if f == 0x18:
        count = rng.randint(0, 31)
        return bytes([f]) + u16(2 + 2 * count) + u16(count) + random_bytes(rng, 2 * count)
    return req  # 05, 06, 16, 08/00: the echo


def user_function(rng):
    return bytes([rng.choice(USER_FUNCTIONS)]) + random_bytes(rng, rng.randint(0, 12))


def flip_bits(rng, frame):
    out = bytearray(frame)
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        bit = rng.randrange(8 * len(out))
        out[bit // 8] ^= 1 << (bit % 8)
    return bytes(out)


def cut(rng, frame):
    return frame[:rng.randint(1, len(frame) - 1)]


def long_query_data(pdu):
    return pdu[0] == 0x08 and pdu[1:3] == b"\0\0" and len(pdu) > 5


class Item:
    """One piece of a stream: its bytes, where they start, and what they are."""

    def __init__(self, kind, data, truth=False):
        self.kind, self.data, self.truth = kind, data, truth
        self.start = self.end = 0
        self.key = (data[0], data[1:-2].hex()) if kind in FRAMES else None


FRAMES = ("frame", "broadcast", "user function", "other address", "other slave",
          "other function")


class Watched(ModbusRtuFramer):
    """pymodbus's RTU framer as it is, with a record of what it did: the frames it accepted
    (at which stream offset) and the bytes each reset dropped (and why)."""

    def __init__(self, decoder, base):
        super().__init__(decoder)
        self.added = base  # stream offset of the end of the bytes given so far
        self.framed = {}  # offset -> (unit, pdu hex)
        self.resets = []  # (first offset, end offset, why)
        self.unit_refused = False

    def addToFrame(self, message):
        super().addToFrame(message)
        self.added += len(message)

    def _validate_unit_id(self, units, single):
        ok = super()._validate_unit_id(units, single)
        self.unit_refused = not ok
        return ok

    def resetFrame(self):
        why = "unit" if self.unit_refused else "check"
        self.resets.append((self.added - len(self._buffer), self.added, why))
        self.unit_refused = False
        super().resetFrame()

    def _process(self, callback, error=False):
        start = self.added - len(self._buffer)
        frame = self._buffer[:self._header["len"]]
        self.framed[start] = (frame[0], frame[1:-2].hex())
        super()._process(callback, error)

    def give(self, data, units):
        """processIncomingPacket as pymodbus's server and sync client call it; an exception
        (its decoder on a frame it framed) resets the framer, as its server does."""
        try:
            self.processIncomingPacket(data, lambda _: None, unit=units, single=False)
        except Exception:  # pylint: disable=broad-except
            self.unit_refused = False
            self.resets.append((self.added - len(self._buffer), self.added, "raised"))
            ModbusRtuFramer.resetFrame(self)

    def held_from(self):
        return self.added - len(self._buffer)


def place(items, offset):
    for it in items:
        it.start, it.end = offset, offset + len(it.data)
        offset = it.end
    return offset


def bursts_of(rng, items):
    """The items in bursts: a silence before an item one time in two."""
    out = []
    for it in items:
        if not out or rng.random() < 0.5:
            out.append([])
        out[-1].append(it)
    return out


def ours_frames(ours, lines, end=None):
    """The frames framers_tool reports for `lines`; `end` (a list) gets whether it reported
    `error truncated` (idle(): bytes held whose length rule wants more)."""
    got = [g.split() for g in ours.results(lines)]
    if end is not None:
        end.append(["error", "truncated"] in got)
    return [(int(w[1]), w[2]) for w in got if w[0] == "frame"]


class Tally:
    def __init__(self, role):
        self.role = role
        self.classes = collections.Counter()
        self.figures = collections.Counter()
        self.failures = 0

    def fail(self, what, items=()):
        self.failures += 1
        if self.failures <= 10:
            print(f"{self.role}: DIFFERENT {what}")
            for it in items:  # the stream around it: offset, burst, kind, bytes
                print(f"    {it.start:6} burst {getattr(it, 'burst', '-'):4} {it.kind:14} "
                      f"{it.data.hex()}")


def compare(t, items, lib_frames, lib_waiting, silence_frames, py, bursts):
    """Classifies every frame accepted by one side and not the other (items: one stream or
    one exchange; lib_frames: the library's (frame_end::length) frames with the index of the
    burst that delivered them; lib_waiting: its idle() at the end found bytes its length rule
    had not seen the end of)."""
    truth = {it.key: it for it in items if it.truth}
    decoys = {it.key: it for it in items if it.key and not it.truth}
    lib_got = {k for _, k in lib_frames}
    spurious_bursts = set()
    for b, k in lib_frames:
        if k in truth:
            continue
        if k in decoys:
            t.fail(f"the library took a {decoys[k].kind} frame {k}")
        else:  # not a frame of the stream: its CRC matched by chance
            t.classes["library: a CRC match by chance"] += 1
            spurious_bursts.add(b)
    for it in truth.values():
        t.figures["truth frames"] += 1
        in_lib = it.key in lib_got
        in_py = py.framed.get(it.start) == it.key
        t.figures["pymodbus"] += in_py
        t.figures["library, frame_end::length"] += in_lib
        t.figures["library, frame_end::silence"] += it.key in silence_frames
        if in_lib and in_py:
            continue
        if in_lib:
            resets = [r for r in py.resets if r[0] < it.end and r[1] > it.start]
            if long_query_data(bytes.fromhex(it.key[1])) and any(
                    r[0] == it.start and r[2] == "check" for r in resets):
                t.classes["Return Query Data of more than 2 data bytes"] += 1
            elif it.kind == "broadcast" and any(r[0] == it.start and r[2] == "unit"
                                                for r in resets):
                t.classes["broadcast: pymodbus's server refuses unit 0"] += 1
            elif resets:
                t.classes["dropped with the bytes pymodbus held (" + resets[0][2] + ")"] += 1
            elif it.start >= py.held_from():
                t.classes["pymodbus still waiting for a length its rule read"] += 1
            else:
                t.fail(f"pymodbus missed {it.kind} {it.key} at {it.start}, no reset")
        elif not in_py:
            t.figures["missed by both"] += 1
        elif it.kind == "user function":
            t.classes["a function without a length rule: pymodbus's 5-byte guess fits"] += 1
        elif spurious_bursts & {it.burst, it.burst - 1}:
            t.classes["library: a frame inside a chance CRC match"] += 1
        elif lib_waiting:
            t.classes["library (frame_end::length) still waiting for a length its rule read"] += 1
        else:
            t.fail(f"the library missed {it.kind} {it.key} (pymodbus read it)",
                   [x for x in items if it.burst - 2 <= x.burst <= it.burst + 1])
    # pymodbus's frames that are no frame of the truth
    for start, k in py.framed.items():
        if k in truth and truth[k].start == start:
            continue
        if k in decoys and decoys[k].kind == "other function":
            t.classes["client: a response to another function (pymodbus takes it)"] += 1
        elif k in decoys:
            t.fail(f"pymodbus took a {decoys[k].kind} frame {k}")
        else:
            t.classes["pymodbus: a CRC match by chance"] += 1
    # the frame_end::silence framer: every truth frame alone in its burst is read
    for burst in bursts:
        if len(burst) == 1 and burst[0].truth:
            t.figures["alone in their burst"] += 1
        if len(burst) == 1 and burst[0].truth and burst[0].key not in silence_frames:
            t.fail(f"frame_end::silence missed {burst[0].kind} {burst[0].key}, alone in its burst")


def unique(seen, rng, make):
    while True:
        data = make()
        if data not in seen:
            seen.add(data)
            return data


def server_stream(rng, frames):
    """Items for a server at ADDRESS: requests for it (the truth), broadcasts (truth too: a
    server takes them), requests for other addresses, user functions, noise, bit flips, cuts."""
    seen, items = set(), []
    others = [a for a in range(1, 248) if a != ADDRESS]
    while sum(it.truth for it in items) < frames:
        r = rng.random()
        if r < 0.50:
            items.append(Item("frame", unique(seen, rng, lambda: adu(ADDRESS, random_request(rng))),
                              True))
        elif r < 0.56:
            items.append(Item("broadcast", unique(seen, rng, lambda: adu(0, random_request(rng))),
                              True))
        elif r < 0.64:
            items.append(Item("other address", unique(
                seen, rng, lambda: adu(rng.choice(others), random_request(rng)))))
        elif r < 0.68:
            items.append(Item("user function", unique(
                seen, rng, lambda: adu(ADDRESS, user_function(rng))), True))
        elif r < 0.78:
            items.append(Item("noise", random_bytes(rng, rng.randint(1, 12))))
        elif r < 0.90:
            items.append(Item("bit flips", flip_bits(rng, adu(ADDRESS, random_request(rng)))))
        else:
            items.append(Item("cut", cut(rng, adu(ADDRESS, random_request(rng)))))
    return items


def run_server(rng, frames, t):
    items = server_stream(rng, frames)
    end = place(items, 0)
    bursts = bursts_of(rng, items)
    py = Watched(ServerDecoder(), 0)
    lib = shared.Ours("rtu-tcp", "server", ADDRESS)
    silence = shared.Ours("rtu", "server", ADDRESS)
    lib_frames, silence_frames = [], set()
    for b, burst in enumerate(bursts):
        data = b"".join(it.data for it in burst)
        for it in burst:
            it.burst = b
        py.give(data, [ADDRESS])
        lib_frames += [(b, k) for k in ours_frames(lib, [f"feed 64 {data.hex()}"])]
        silence_frames.update(ours_frames(silence, [f"feed 64 {data.hex()}", "idle"]))
    py.give(FLUSH, [ADDRESS])
    waiting = []
    lib_frames += [(len(bursts), k)
                   for k in ours_frames(lib, [f"feed 64 {FLUSH.hex()}", "idle"], waiting)]
    lib.close()
    silence.close()
    t.figures["bursts"] += len(bursts)
    t.figures["bytes"] += end + len(FLUSH)
    t.figures["items"] += len(items)
    compare(t, items, lib_frames, waiting[0], silence_frames, py, bursts)


def run_client(rng, exchanges, t):
    """One exchange at a time: the request sent, the response among other bytes."""
    lib = shared.Ours("rtu-tcp", "client", 0)
    silence = shared.Ours("rtu", "client", 0)
    offset = 0
    for _ in range(exchanges):
        unit = rng.randint(1, 247)
        req = random_request(rng, client=True)
        good = adu(unit, response_to(rng, req))
        items = []
        if rng.random() < 0.15:
            items.append(Item("noise", random_bytes(rng, rng.randint(1, 12))))
        if rng.random() < 0.15:
            other = rng.choice([a for a in range(1, 248) if a != unit])
            items.append(Item("other slave", adu(other, response_to(rng, req))))
        if rng.random() < 0.15:
            while True:
                other = random_request(rng, client=True)
                if other[0] != req[0]:
                    break
            pdu = response_to(rng, other)
            while pdu[0] & 0x80:  # a normal response: an exception is framed by its flag alone
                pdu = response_to(rng, other)
            items.append(Item("other function", adu(unit, pdu)))
        if rng.random() < 0.15:
            items.append(Item("bit flips", flip_bits(rng, good)))
        if rng.random() < 0.15:
            items.append(Item("cut", cut(rng, good)))
        rng.shuffle(items)
        if rng.random() < 0.9:
            items.append(Item("frame", good, True))
        if not items:
            continue
        keys = [it.key for it in items if it.key]
        if len(keys) != len(set(keys)):
            continue  # a decoy the same as the response: nothing to tell them apart
        end = place(items, offset)
        bursts = bursts_of(rng, items)
        py = Watched(ClientDecoder(), offset)
        request_adu = adu(unit, req).hex()
        lib_frames, silence_frames = [], set()
        lib.ask(f"sent {request_adu}")
        silence.ask(f"sent {request_adu}")
        for b, burst in enumerate(bursts):
            data = b"".join(it.data for it in burst)
            for it in burst:
                it.burst = b
            py.give(data, unit)
            lib_frames += [(b, k) for k in ours_frames(lib, [f"feed 64 {data.hex()}"])]
            silence_frames.update(ours_frames(silence, [f"feed 64 {data.hex()}", "idle"]))
        waiting = []
        lib_frames += [(len(bursts), k) for k in ours_frames(lib, ["idle"], waiting)]
        offset = end
        t.figures["exchanges"] += 1
        t.figures["bursts"] += len(bursts)
        t.figures["items"] += len(items)
        compare(t, items, lib_frames, waiting[0], silence_frames, py, bursts)
    t.figures["bytes"] += offset
    lib.close()
    silence.close()


# docs/modbus.md §14's rows, as this run's figures fill them (--docs checks that the file holds
# each one, so that its figures are this run's): the summary table, then each class's row up
# to its server and client counts (0 where the class did not occur).
SUMMARY_ROWS = (
    ("bursts", lambda s, c: f"{s['bursts']} | {c['bursts']} ({c['exchanges']} exchanges)"),
    ("frames to read (for the server or its broadcasts; the response to the request)",
     lambda s, c: f"{s['truth frames']} | {c['truth frames']}"),
    ("read by pymodbus", lambda s, c: f"{s['pymodbus']} | {c['pymodbus']}"),
    ("read by the library, `frame_end::length`",
     lambda s, c: f"{s['library, frame_end::length']} | {c['library, frame_end::length']}"),
    ("read by the library, `frame_end::silence`",
     lambda s, c: f"{s['library, frame_end::silence']} | {c['library, frame_end::silence']}"),
    ("frames alone between two silences, all read with `frame_end::silence`",
     lambda s, c: f"{s['alone in their burst']} | {c['alone in their burst']}"),
)
CLASS_ROWS = (
    ("a frame behind a failed check in pymodbus's buffer",
     "dropped with the bytes pymodbus held (check)"),
    ("the same, the frame at the front being for a unit it does not serve (another address, a "
     "broadcast)", "dropped with the bytes pymodbus held (unit)"),
    ("a broadcast (server)", "broadcast: pymodbus's server refuses unit 0"),
    ("Return Query Data (FC08/00) with more than 2 data bytes",
     "Return Query Data of more than 2 data bytes"),
    ("a user-defined function (no length rule), pymodbus's guess fits",
     "a function without a length rule: pymodbus's 5-byte guess fits"),
    ("a response to another function (client)",
     "client: a response to another function (pymodbus takes it)"),
    ("pymodbus still waiting for a length its rule read (client)",
     "pymodbus still waiting for a length its rule read"),
    ("the library (`frame_end::length`) still waiting for a length its rule read (client)",
     "library (frame_end::length) still waiting for a length its rule read"),
    ("a CRC that matches by chance, in the library's scan", "library: a CRC match by chance"),
    ("a CRC that matches by chance, in pymodbus's", "pymodbus: a CRC match by chance"),
    ("a frame inside a CRC match by chance (the library)",
     "library: a frame inside a chance CRC match"),
)


def docs_problems(path, tallies):
    """The rows of docs/modbus.md §14 this run's figures make that the file does not hold."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    s, c = tallies["server"], tallies["client"]
    rows = [f"| {label} | {cells(s.figures, c.figures)} |" for label, cells in SUMMARY_ROWS]
    rows.append(f"| read by neither (`frame_end::length` and pymodbus) | "
                f"{s.figures['missed by both']} | {c.figures['missed by both']} |")
    rows += [f"| {label} | {s.classes[key]} | {c.classes[key]} |" for label, key in CLASS_ROWS]
    known = {key for _, key in CLASS_ROWS}
    unlisted = [k for t in tallies.values() for k in t.classes if k not in known]
    return [f"{path}: no row {row}" for row in rows if row not in text] + [
        f"{path}: class {k!r} has no row" for k in unlisted]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("tool")
    parser.add_argument("--seed", type=lambda s: int(s, 0), default=28)
    parser.add_argument("--frames", type=int, default=3000)
    parser.add_argument("--exchanges", type=int, default=1500)
    parser.add_argument("--docs", help="docs/modbus.md: check that §14 holds this run's figures")
    args = parser.parse_args()
    shared.TOOL = args.tool
    failures = 0
    tallies = {}
    for role in ("server", "client"):
        rng = random.Random(f"{args.seed}-{role}")
        t = tallies[role] = Tally(role)
        if role == "server":
            run_server(rng, args.frames, t)
        else:
            run_client(rng, args.exchanges, t)
        f = t.figures
        print(f"{role} (seed {args.seed}): " + ", ".join(f"{k} {v}" for k, v in f.items()))
        for cls, n in sorted(t.classes.items()):
            print(f"  documented difference {cls}: {n}")
        failures += t.failures
    stale = docs_problems(args.docs, tallies) if args.docs else []
    for problem in stale:
        print(problem)
    if stale:
        print("pymodbus framer differential: docs/modbus.md §14 does not hold this run's figures")
    if failures or shared.FAILURES:
        print(f"pymodbus framer differential: {failures} differences of no documented class")
    return 1 if stale or failures or shared.FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
