"""pymodbus's TCP client and raw MBAP sockets through `motionbus gateway` to `motionbus serve
sm-unit` on a pty (tests/interop/run_gateway_interop.sh starts them).

Usage: pymodbus_gateway.py full PORT TIMEOUT_MS IDLE_MS   every function, 0B, 8 clients, bad input
       pymodbus_gateway.py policy PORT                    --read-only --units 1 --functions 3,4,6
       pymodbus_gateway.py rtu PORT                       --rtu-over-tcp, pymodbus's RTU framer
       pymodbus_gateway.py generic PORT [gateway]         `serve modbus --units 1-4` (through the
                                                          gateway, or alone with --tcp-listen)
Exit 0 when every check holds. Run with Debian's python3 (python3-pymodbus).
"""
import os
import socket
import struct
import sys
import threading
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from pymodbus_peer import Checks  # noqa: E402  (tests/support/pymodbus_peer.py)
from pymodbus.client import ModbusTcpClient  # noqa: E402

check = Checks()
PASSWORD = [0x7061, 0x7373, 0x776F, 0x7264, 0, 0, 0, 0]  # "password", NUL padded


def mbap(tid, unit, pdu, protocol=0, length=None):
    return struct.pack(">HHHB", tid, protocol, len(pdu) + 1 if length is None else length,
                       unit) + pdu


def recv_adu(s):
    """One MBAP ADU from socket s, or b"" when the connection is closed."""
    head = b""
    while len(head) < 6:
        got = s.recv(6 - len(head))
        if not got:
            return b""
        head += got
    rest = b""
    need = struct.unpack(">H", head[4:6])[0]
    while len(rest) < need:
        got = s.recv(need - len(rest))
        if not got:
            return b""
        rest += got
    return head + rest


def connect(port):
    s = socket.create_connection(("127.0.0.1", port), timeout=5)
    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return s


def closed_by_peer(s, wait=3.0):
    s.settimeout(wait)
    try:
        return s.recv(1) == b""
    except ConnectionResetError:
        return True
    except socket.timeout:
        return False


def served_functions(port):
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
    check("pymodbus connects", client.connect())
    r = client.read_input_registers(100, 9, slave=1)
    check("FC04 instantaneous data: 9 registers", not r.isError() and len(r.registers) == 9)
    check("frequency register is 50 Hz", not r.isError() and r.registers[7] == 50)
    r = client.write_register(36, 750, slave=1)
    check("FC06 overheat limit 75.0 degC", not r.isError())
    r = client.read_holding_registers(36, 1, slave=1)
    check("FC03 reads it back", not r.isError() and r.registers[0] == 750)
    r = client.write_register(0, 201, slave=1)
    check("FC06 out of limits: exception 03", r.isError() and r.exception_code == 3)
    r = client.read_holding_registers(200, 1, slave=1)
    check("FC03 one address of a block: exception 02", r.isError() and r.exception_code == 2)
    r = client.read_holding_registers(200, 8, slave=1)
    text = b"".join(v.to_bytes(2, "big") for v in r.registers) if not r.isError() else b""
    check("FC03 password block reads 'password'", text.rstrip(b"\0") == b"password")
    r = client.write_registers(37, [6000, 20], slave=1)
    check("FC10 two settings", not r.isError())
    r = client.write_coil(100, True, slave=1)
    check("FC05 warning reset", not r.isError())
    r = client.write_registers(100, PASSWORD, slave=1)
    check("FC10 the password logs out", not r.isError())
    r = client.write_register(36, 700, slave=1)
    check("FC06 while logged out: exception 04", r.isError() and r.exception_code == 4)
    r = client.write_registers(100, PASSWORD, slave=1)
    check("FC10 the password logs in again", not r.isError())
    r = client.read_input_registers(300, 1, slave=1)
    check("FC04 login status: logged in again", not r.isError() and r.registers[0] == 0xFF00)
    r = client.read_input_registers(100, 1, slave=250)
    check("unit 250 (no path): exception 0A from the gateway",
          r.isError() and r.exception_code == 0x0A)
    client.close()
    # FC11 in the SM unit's layout (two bytes, no count): the MBAP length frames it.
    s = connect(port)
    s.sendall(mbap(77, 1, b"\x11"))
    a = recv_adu(s)
    check("FC11 answered with the unit's two bytes, id 77",
          a[:2] == struct.pack(">H", 77) and a[7:8] == b"\x11" and len(a) == 10)
    # FC16 (pymodbus 3.0's mask_write_register drops its slave argument: sent raw)
    s.sendall(mbap(78, 1, b"\x16\x00\x24\xFF\xFF\x00\x00"))
    check("FC16 not served by the unit: exception 01 from the device",
          recv_adu(s) == mbap(78, 1, b"\x96\x01"))
    s.close()


def no_answer(port, timeout_ms):
    s = connect(port)
    start = time.monotonic()
    s.sendall(mbap(9, 5, b"\x04\x00\x64\x00\x01"))
    a = recv_adu(s)
    took = (time.monotonic() - start) * 1000
    check("unit 5 does not answer: exception 0B, the request's ids",
          a == mbap(9, 5, b"\x84\x0B"))
    check("0B within the timeout (%d ms) and its margin: %.0f ms" % (timeout_ms, took),
          timeout_ms * 0.9 <= took <= timeout_ms + 500)
    s.close()


def concurrent(port, clients=8, each=12):
    answers = [[] for _ in range(clients)]
    errors = []

    def run(k):
        try:
            s = connect(port)
            for i in range(each):
                tid = (k << 8) | i
                # holding register 37..38 reads its value; the quantity tells the clients apart
                s.sendall(mbap(tid, 1, struct.pack(">BHH", 3, 36, 1 + k % 4)))
                answers[k].append((tid, recv_adu(s)))
            s.close()
        except OSError as e:
            errors.append(str(e))

    threads = [threading.Thread(target=run, args=(k,)) for k in range(clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    ok = not errors
    for k in range(clients):
        for tid, a in answers[k]:
            n = 1 + k % 4
            ok = ok and len(a) == 9 + 2 * n and struct.unpack(">H", a[:2])[0] == tid and \
                a[6] == 1 and a[7] == 3 and a[8] == 2 * n
        ok = ok and len(answers[k]) == each
    check("%d concurrent clients: every answer, with its own transaction id" % clients, ok)


def bad_input(port, idle_ms):
    good = connect(port)

    def still_answered(after, tid):
        good.sendall(mbap(tid, 1, b"\x03\x00\x24\x00\x01"))
        a = recv_adu(good)
        check("after %s: the other connection is still answered" % after,
              a[:2] == struct.pack(">H", tid) and a[7:8] == b"\x03")

    s = connect(port)
    s.sendall(mbap(1, 1, b"\x03\x00\x24\x00\x01", protocol=1))
    check("protocol id 1: the connection is closed", closed_by_peer(s, idle_ms / 2000))
    still_answered("protocol id 1", 0x101)
    s = connect(port)
    s.sendall(struct.pack(">HHH", 2, 0, 300) + b"\x01\x03")
    check("length 300 (an ADU over 260): closed", closed_by_peer(s, idle_ms / 2000))
    still_answered("length 300", 0x102)
    s = connect(port)
    s.sendall(mbap(3, 1, b"\x03\x00\x24\x00\x01\x00\x00\x00"))  # FC03 is 5 bytes, not 8
    check("a length the PDU contradicts (FC03 in 8 bytes): closed",
          closed_by_peer(s, idle_ms / 2000))
    still_answered("a lying length", 0x103)
    s = connect(port)
    s.sendall(b"\x00\x04\x00")
    start = time.monotonic()
    still_answered("half a header on another connection", 0x104)
    closed = closed_by_peer(s, idle_ms / 1000 + 3)
    took = (time.monotonic() - start) * 1000
    check("half a header, then nothing: closed after the idle timeout (%.0f ms)" % took,
          closed and took >= idle_ms * 0.8)
    good.close()
    good = connect(port)
    still_answered("the idle timeout", 0x105)
    good.close()


def policy(port):
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
    check("pymodbus connects", client.connect())
    r = client.read_holding_registers(36, 1, slave=1)
    check("read-only: FC03 forwarded", not r.isError())
    r = client.write_register(36, 700, slave=1)
    check("read-only: FC06 refused with 01", r.isError() and r.exception_code == 1)
    r = client.write_coil(100, True, slave=1)
    check("--functions 3,4,6: FC05 refused with 01", r.isError() and r.exception_code == 1)
    r = client.read_holding_registers(36, 1, slave=2)
    check("--units 1: unit 2 refused with 0A", r.isError() and r.exception_code == 0x0A)
    client.close()


def rtu(port):
    from pymodbus.framer.rtu_framer import ModbusRtuFramer
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=3, framer=ModbusRtuFramer)
    check("pymodbus (RTU framer over TCP) connects", client.connect())
    r = client.read_input_registers(100, 9, slave=1)
    check("RTU over TCP: FC04 9 registers", not r.isError() and len(r.registers) == 9)
    r = client.read_holding_registers(200, 1, slave=1)
    check("RTU over TCP: exception 02", r.isError() and r.exception_code == 2)
    r = client.read_holding_registers(36, 1, slave=5)
    check("RTU over TCP: unit 5 silent: 0B", r.isError() and r.exception_code == 0x0B)
    client.close()


def generic(port, through_gateway):
    """serve modbus --units 1-4 --points 100: every function it serves, its exceptions."""
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
    check("pymodbus connects", client.connect())
    for u in range(1, 5):
        r = client.read_input_registers(0, 2, slave=u)
        check("unit %d is its own device: FC04 reads %d, %d" % (u, 1000 * u, 1000 * u + 1),
              not r.isError() and r.registers == [1000 * u, 1000 * u + 1])
    check("FC10 unit 2", not client.write_registers(5, [1, 2, 3], slave=2).isError())
    r = client.read_holding_registers(5, 3, slave=2)
    check("FC03 unit 2 reads it back", not r.isError() and r.registers == [1, 2, 3])
    r = client.read_holding_registers(5, 3, slave=1)
    check("FC03 unit 1 is untouched", not r.isError() and r.registers == [0, 0, 0])
    check("FC06", not client.write_register(7, 0x1234, slave=3).isError())
    r = client.read_holding_registers(7, 1, slave=3)
    check("FC06 read back", not r.isError() and r.registers == [0x1234])
    check("FC0F", not client.write_coils(0, [True, False, True], slave=3).isError())
    r = client.read_coils(0, 3, slave=3)
    check("FC01 reads them back", not r.isError() and r.bits[:3] == [True, False, True])
    check("FC05", not client.write_coil(1, True, slave=3).isError())
    r = client.read_coils(0, 3, slave=3)
    check("FC01 after FC05", not r.isError() and r.bits[:3] == [True, True, True])
    r = client.read_discrete_inputs(0, 4, slave=3)
    check("FC02: input i on when i % 3 == 0",
          not r.isError() and r.bits[:4] == [True, False, False, True])
    r = client.read_holding_registers(99, 2, slave=1)
    check("past the points: exception 02", r.isError() and r.exception_code == 2)
    r = client.read_holding_registers(0, 126, slave=1)
    check("126 registers: exception 03", r.isError() and r.exception_code == 3)
    client.close()
    s = connect(port)
    # FC16 (raw: pymodbus 3.0's mask_write_register and readwrite_registers drop the slave)
    s.sendall(mbap(40, 4, b"\x16\x00\x07\x00\xFF\x00\x01"))
    check("FC16 mask write answered", recv_adu(s) == mbap(40, 4, b"\x16\x00\x07\x00\xFF\x00\x01"))
    # FC17 (raw too): read 7..8 after writing 0x0055 to 8
    s.sendall(mbap(44, 3, b"\x17\x00\x07\x00\x02\x00\x08\x00\x01\x02\x00\x55"))
    check("FC17 reads after its write",
          recv_adu(s) == mbap(44, 3, b"\x17\x04\x12\x34\x00\x55"))
    s.sendall(mbap(41, 1, b"\x07"))
    check("FC07 (not served): exception 01", recv_adu(s) == mbap(41, 1, b"\x87\x01"))
    s.sendall(mbap(42, 2, b"\x11"))
    a = recv_adu(s)
    check("FC11 reports unit 2", a[:2] == b"\x00\x2a" and a[7:8] == b"\x11" and
          a.endswith(b"motionbus unit 2"))
    if through_gateway:
        s.sendall(mbap(43, 5, b"\x03\x00\x00\x00\x01"))
        check("unit 5 (not served): 0B from the gateway", recv_adu(s) == mbap(43, 5, b"\x83\x0B"))
    s.close()


def main():
    mode, port = sys.argv[1], int(sys.argv[2])
    if mode == "full":
        served_functions(port)
        no_answer(port, int(sys.argv[3]))
        concurrent(port)
        bad_input(port, int(sys.argv[4]))
    elif mode == "policy":
        policy(port)
    elif mode == "generic":
        generic(port, len(sys.argv) > 3)
    else:
        rtu(port)
    return 1 if check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
