"""motionbus's FC14/FC15 codec (tests/interop/file_record_peer.cpp) against pymodbus 3.0's
file_message classes: requests encode to the same bytes both ways, pymodbus decodes what the
motionbus server answers, motionbus decodes what pymodbus's WriteFileRecordResponse encodes; and
pymodbus's ReadFileRecordResponse.encode, which puts the reference type before the sub-response
length and writes the length in registers (06 N instead of 1+2N 06, Application Protocol
§6.14), is refused, as docs/modbus.md says.

usage: file_record_check.py FILE_RECORD_PEER
"""
import subprocess
import sys

from pymodbus.file_message import (FileRecord, ReadFileRecordRequest, ReadFileRecordResponse,
                                   WriteFileRecordRequest, WriteFileRecordResponse)

failures = []


class Peer:
    def __init__(self, path):
        self.p = subprocess.Popen([path], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)

    def ask(self, line):
        self.p.stdin.write(line + "\n")
        self.p.stdin.flush()
        return self.p.stdout.readline().strip()

    def close(self):
        self.p.stdin.close()
        if self.p.wait(timeout=10) != 0:
            failures.append(f"peer exited with {self.p.returncode}")


def pdu(message):
    return bytes([message.function_code]) + message.encode()


READS = [
    [(4, 1, 2), (3, 9, 2)],  # the spec's example
    [(1, 0, 1)],
    [(0xFFFF, 0x270F, 1)],
    [(7, 100, 124)],  # the largest answer
    [(f, f, 1) for f in range(1, 36)],  # 35 sub-requests
]
WRITES = [
    [(4, 7, bytes.fromhex("06af04be100d"))],  # the spec's example
    [(1, 0, bytes.fromhex("1234")), (2, 0x270E, bytes.fromhex("abcdef01"))],
    [(9, 5, bytes(range(244)))],  # the longest request
]


def main():
    peer = Peer(sys.argv[1])
    for reads in READS:
        records = [FileRecord(file_number=f, record_number=r, record_length=n) for f, r, n in reads]
        theirs = pdu(ReadFileRecordRequest(records))
        ours = peer.ask("encode14 " + ",".join(f"{f}:{r}:{n}" for f, r, n in reads))
        if ours != theirs.hex():
            failures.append(f"FC14 request {reads}: motionbus {ours} pymodbus {theirs.hex()}")
        answer = peer.ask("serve " + theirs.hex())
        response = ReadFileRecordResponse()
        response.decode(bytes.fromhex(answer)[1:])
        want = [b"".join(((f * 0x100 + r + i) & 0xFFFF).to_bytes(2, "big") for i in range(n))
                for f, r, n in reads]
        got = [rec.record_data for rec in response.records]
        if got != want:
            failures.append(f"pymodbus decoding motionbus's FC14 answer {answer}: {got}")
        # pymodbus's own response encoding: not the spec's layout, refused
        mine = ReadFileRecordResponse([FileRecord(record_data=d) for d in want])
        verdict = peer.ask(f"check14 {theirs.hex()} {pdu(mine).hex()}")
        if verdict != "byte_count_mismatch" or pdu(mine).hex() == answer:
            failures.append(f"pymodbus's FC14 response {pdu(mine).hex()}: {verdict}")
        if peer.ask(f"check14 {theirs.hex()} {answer}") != "ok " + " ".join(w.hex() for w in want):
            failures.append(f"motionbus decoding its own FC14 answer {answer}")
    for writes in WRITES:
        records = [FileRecord(file_number=f, record_number=r, record_data=d) for f, r, d in writes]
        theirs = pdu(WriteFileRecordRequest(records))
        ours = peer.ask("encode15 " + ",".join(f"{f}:{r}:{d.hex()}" for f, r, d in writes))
        if ours != theirs.hex():
            failures.append(f"FC15 request {writes}: motionbus {ours} pymodbus {theirs.hex()}")
        answer = peer.ask("serve " + theirs.hex())
        response = WriteFileRecordResponse()
        response.decode(bytes.fromhex(answer)[1:])
        if answer != theirs.hex() or response.records != records:
            failures.append(f"FC15 answer {answer} to {theirs.hex()}")
        echo = pdu(WriteFileRecordResponse(records))
        if peer.ask(f"check15 {theirs.hex()} {echo.hex()}") != "ok":
            failures.append(f"motionbus decoding pymodbus's FC15 response {echo.hex()}")
    # a request pymodbus builds that the specification forbids: refused with its own error
    bad = pdu(ReadFileRecordRequest([FileRecord(file_number=0, record_number=0, record_length=1)]))
    if peer.ask("serve " + bad.hex()) != "file_number":
        failures.append("file number 0 accepted")
    bad = pdu(ReadFileRecordRequest([FileRecord(file_number=1, record_number=0x2710,
                                                record_length=1)]))
    if peer.ask("serve " + bad.hex()) != "record_number":
        failures.append("record number 0x2710 accepted")
    peer.close()
    for f in failures:
        print("FAIL", f)
    print(f"{len(READS)} FC14 and {len(WRITES)} FC15 request sets against pymodbus")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
