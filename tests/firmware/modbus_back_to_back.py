#!/usr/bin/python3
"""Back-to-back requests to the interrupt-driven generic Modbus server image (slave 1) on a
serial device: nothing lost, nothing answered twice, every answer the one its request asks for.

  sequence  each request sent t3.5 after the answer to the one before (a master as fast as the
            protocol allows it to be, waiting for each answer);
  burst     each request sent t3.5 after the previous one, without waiting for the answers
            (full duplex: RS-422 or RS-232; the answers go out while the next requests come in;
            a pseudo-terminal carries a request's bytes at once, so that its end is its write);
  one write many requests in one write, no silence at all between them: more than an RTU line
            allows (frames must be t3.5 apart; the server frames them by the lengths their
            function codes give), and more than the server can keep up with when the bytes come
            faster than its answers go out (under QEMU they come as fast as the UART model takes
            them). Here the image may drop requests on its full queue, but must count each one
            it drops, and answer the others once, in order, each as asked.

In the first two, each step writes a register (FC06, answered by its echo) and reads it back
(FC03), the values unique to the step, so that a lost, repeated or reordered answer shows in the
bytes: every answer byte is compared with what was expected, and the line is watched for a
further second for anything more. In the third, the writes alternate with reads of input
registers (FC04), each answer unique and independent of the others: the answers must be those
expected with some left out, and as many left out as the image counted dropped. The image's
counters (input registers 1000-1006: frames handed over, dropped on a full queue, put()
failures, idle() failures (a request cut by a silence), early timer expiries, frames ended by
idle(); and the longest silence inside a request, shown) are read before, between and after:
in the first two nothing dropped, nothing failed, a frame handed over for every request.

Usage: modbus_back_to_back.py DEVICE [BAUD [sequence]]  (BAUD: the image's line rate; by
default the environment's MOTIONBUS_BAUD, else 9600; "sequence": the sequence alone, for the
deliberately broken images). Exit 0 when every check holds.
"""
import os
import select
import sys
import time

from modbus_raw_checks import Line, adu  # tests/firmware/modbus_raw_checks.py

SLAVE = 1
COUNTER_NAMES = ["frames", "dropped (queue full)", "put() failures", "idle() failures",
                 "early timer expiries", "frames ended by idle()"]
# the seventh register: the longest silence between two bytes of one request (100 us units),
# not a count (shown as measured, over the whole run)
GAP = len(COUNTER_NAMES)


def t35_seconds(baud):
    """t3.5 as modbus/timing.hpp computes it (11-bit characters; 1750 us above 19200 baud)."""
    return 0.00175 if baud > 19200 else 3.5 * 11 / baud


def write_request(register, value):
    return adu(SLAVE, [0x06, register >> 8, register & 0xFF, value >> 8, value & 0xFF])


def read_request(register):
    return adu(SLAVE, [0x03, register >> 8, register & 0xFF, 0x00, 0x01])


def read_answer(value):
    return adu(SLAVE, [0x03, 0x02, value >> 8, value & 0xFF])


def steps(first, count):
    """(request, expected answer) pairs: a write of register (k % 100), then its read back."""
    pairs = []
    for k in range(first, first + count):
        register = k % 100
        value = (k * 7919 + 1) & 0xFFFF
        pairs.append((write_request(register, value), write_request(register, value)))
        pairs.append((read_request(register), read_answer(value)))
    return pairs


def receive_exactly(line, size, seconds):
    """Bytes until `size` have arrived (or `seconds` passed), then whatever else comes within a
    further second (an answer sent twice)."""
    got = b""
    deadline = time.monotonic() + seconds
    while len(got) < size:
        left = deadline - time.monotonic()
        if left <= 0:
            break
        ready, _, _ = select.select([line.fd], [], [], left)
        if ready:
            got += os.read(line.fd, 4096)
    return got + line.receive(1.0)


def first_difference(got, expected, answers):
    """Which answer is the first to differ, as text."""
    at = 0
    for i, a in enumerate(answers):
        if got[at:at + len(a)] != a:
            return "answer %d of %d (expected %s, got %s)" % (
                i + 1, len(answers), a.hex(), got[at:at + len(a)].hex() or "nothing")
        at += len(a)
    return "%d bytes more than the %d expected" % (len(got) - len(expected), len(expected))


def input_read_request(register):
    return adu(SLAVE, [0x04, register >> 8, register & 0xFF, 0x00, 0x01])


def input_read_answer(register):
    value = 1000 + register
    return adu(SLAVE, [0x04, 0x02, value >> 8, value & 0xFF])


def independent_steps(first, count):
    """(request, expected answer) pairs whose answers do not depend on each other: a write of
    register (k % 100), then a read of input register k % 100 (which reads 1000 + k % 100)."""
    pairs = []
    for k in range(first, first + count):
        register = k % 100
        value = (k * 7919 + 1) & 0xFFFF
        pairs.append((write_request(register, value), write_request(register, value)))
        pairs.append((input_read_request(register), input_read_answer(register)))
    return pairs


def answers_left_out(got, answers):
    """How many of `answers` (in order, each unique) `got` leaves out, when `got` is exactly
    the others in order; None when it is not (an answer twice, out of order, or corrupted)."""
    at = 0
    missing = 0
    for a in answers:
        if got[at:at + len(a)] == a:
            at += len(a)
        else:
            missing += 1
    return missing if at == len(got) else None


def main():
    line = Line(sys.argv[1])
    baud = int(sys.argv[2] if len(sys.argv) > 2 else os.environ.get("MOTIONBUS_BAUD", "9600"))
    t35 = t35_seconds(baud)
    failures = []

    def check(name, condition, detail=""):
        print(("ok   " if condition else "FAIL ") + name + ("" if condition else ": " + detail))
        if not condition:
            failures.append(name)

    def counters():
        time.sleep(t35)
        n = len(COUNTER_NAMES) + 1
        request = adu(SLAVE, [0x04, 1000 >> 8, 1000 & 0xFF, 0x00, n])
        line.send(request)
        size = 5 + 2 * n
        got = receive_exactly(line, size, 5.0)
        if len(got) != size or got[:3] != bytes([SLAVE, 0x04, 2 * n]) or \
                adu(SLAVE, list(got[1:-2])) != got:
            print("FAIL the image's counters: got %s" % got.hex())
            failures.append("counters")
            return None
        return [int.from_bytes(got[3 + 2 * i:5 + 2 * i], "big") for i in range(n)]

    def difference(after, before):
        delta = [(a - b) & 0xFFFF for a, b in zip(after, before)]
        print("     the image's counters: " +
              ", ".join("%s %d" % (n, d) for n, d in zip(COUNTER_NAMES, delta)) +
              "; the longest silence inside a request so far %.1f ms (t3.5 %.1f ms)" % (
                  after[GAP] / 10, t35 * 1000))
        return delta

    def run(name, pairs, send):
        expected = b"".join(a for _, a in pairs)
        start = time.monotonic()
        got = send(pairs)
        check("%s: %d requests, each answered once, as asked (%.2f s)" % (
            name, len(pairs), time.monotonic() - start), got == expected,
            first_difference(got, expected, [a for _, a in pairs]))
        return got

    def sequence(pairs):
        got = b""
        for request, answer in pairs:
            time.sleep(t35)
            line.send(request)
            got += receive_exactly_quiet(line, len(answer), 2.0)
        return got + line.receive(1.0)

    def burst(pairs):
        for request, _ in pairs:
            line.send(request)
            time.sleep(t35)
        return receive_exactly(line, sum(len(a) for _, a in pairs), 10.0)

    before = counters()
    legal = steps(0, 20)
    run("sequence", legal, sequence)
    if sys.argv[3:] == ["sequence"]:
        os.close(line.fd)
        return 1 if failures else 0
    more = steps(100, 20)
    run("burst", more, burst)
    middle = counters()
    if before is not None and middle is not None:
        delta = difference(middle, before)
        # the read of `middle` is counted in its own frames (handed over before it was served)
        sent = len(legal) + len(more) + 1
        check("sequence and burst: a frame handed over for every request",
              delta[0] == sent, "%d frames for %d requests" % (delta[0], sent))
        check("sequence and burst: nothing dropped, no put() or idle() failure",
              delta[1:4] == [0, 0, 0], str(delta[1:4]))

    pairs = independent_steps(200, 25)
    answers = [a for _, a in pairs]
    time.sleep(t35)
    start = time.monotonic()
    line.send(b"".join(r for r, _ in pairs))
    got = receive_until_quiet(line, sum(len(a) for a in answers), 5.0)
    elapsed = time.monotonic() - start
    after = counters()
    missing = answers_left_out(got, answers)
    check("one write: %d requests, each answer once, in order, as asked (%.2f s)" % (
        len(pairs), elapsed), missing is not None,
        "the answers are not those expected with some left out: " +
        first_difference(got, b"".join(answers), answers))
    if middle is not None and after is not None:
        delta = difference(after, middle)
        if missing is not None:
            check("one write: %d answers left out, as many as the image dropped" % missing,
                  missing == delta[1], "the image dropped %d" % delta[1])
        check("one write: a frame handed over or counted dropped for every request",
              delta[0] + delta[1] == len(pairs) + 1, "%d + %d for %d requests" % (
                  delta[0], delta[1], len(pairs) + 1))
        check("one write: no put() or idle() failure", delta[2:4] == [0, 0], str(delta[2:4]))
    os.close(line.fd)
    return 1 if failures else 0


def receive_until_quiet(line, size, seconds):
    """Bytes until `size` have arrived, or none for a second, or `seconds` passed with none;
    then whatever else comes within a further second."""
    got = b""
    deadline = time.monotonic() + seconds
    while len(got) < size:
        left = deadline - time.monotonic()
        if left <= 0:
            break
        ready, _, _ = select.select([line.fd], [], [], left)
        if ready:
            got += os.read(line.fd, 4096)
            deadline = time.monotonic() + 1.0
    return got + line.receive(1.0)


def receive_exactly_quiet(line, size, seconds):
    """Bytes until `size` have arrived (or `seconds` passed)."""
    got = b""
    deadline = time.monotonic() + seconds
    while len(got) < size:
        left = deadline - time.monotonic()
        if left <= 0:
            break
        ready, _, _ = select.select([line.fd], [], [], left)
        if ready:
            got += os.read(line.fd, 4096)
    return got


if __name__ == "__main__":
    sys.exit(main())
