"""Bad input never crashes the process: every public function, constructor and method of the
package, called with wrong types, short or empty buffers, oversized counts and values, raises
a clear TypeError/ValueError (motionbus.Error is a ValueError) or returns; and every decoder
fed random bytes (Hypothesis) returns or raises DecodeError. This process surviving the whole
file is the test."""

import inspect
from typing import Any, Callable, Iterator, List, Tuple

from hypothesis import given, strategies as st

import motionbus
from motionbus import biss, crc, modbus, tformat
from motionbus.devices import absys, sm_unit, ts5700n8500

MODULES = [crc, tformat, modbus, biss, ts5700n8500, sm_unit, absys]
BAD: List[Any] = [None, "text", b"", b"\x00", bytes(300), bytearray(3), memoryview(b"\x01\x02"),
                  -1, 2**16, 2**64, 1.5, [], [1] * 2001, [2**17] * 3, [None], object()]
FILLER: List[Any] = [0, b"\x00", 1, 1, 1]
CLEAR = (TypeError, ValueError, BufferError, OverflowError, modbus.ModbusException)
# Calls that take a callback object or would wait on one: given a fresh object each time.
SKIP = {"serve_rtu", "Server", "ControlSlave"}


def callables() -> Iterator[Tuple[str, Callable[..., Any]]]:
    for mod in MODULES:
        for name in mod.__all__:
            obj = getattr(mod, name)
            if name in SKIP or (inspect.isclass(obj) and issubclass(obj, BaseException)):
                continue
            if callable(obj) and not (inspect.isclass(obj) and issubclass(obj, int)):
                yield f"{mod.__name__}.{name}", obj
            if inspect.isclass(obj):
                try:
                    inst = obj()
                except Exception:  # noqa: BLE001 - a class without a default constructor
                    continue
                for attr in dir(obj):
                    if attr.startswith("_"):
                        continue
                    member = getattr(inst, attr)
                    if callable(member) and not inspect.isclass(member):
                        yield f"{mod.__name__}.{name}.{attr}", member


def call(name: str, f: Callable[..., Any], args: Tuple[Any, ...]) -> None:
    try:
        f(*args)
    except CLEAR as e:
        assert str(e), f"{name}{args!r}: an exception without a message"
    except Exception as e:  # noqa: BLE001
        raise AssertionError(f"{name}{args!r} raised {type(e).__name__}: {e}") from e


def test_every_callable_refuses_bad_arguments_clearly() -> None:
    count = 0
    for name, f in callables():
        for arity in range(0, 5):
            for k in range(arity):
                for bad in BAD:
                    args = tuple(bad if i == k else FILLER[i] for i in range(arity))
                    call(name, f, args)
                    count += 1
    assert count > 5000


def test_callback_objects_that_misbehave() -> None:
    for device in (None, 5, "x", object()):
        for adu in (b"", b"\x01", modbus.encode_rtu(1, modbus.encode_read(3, 0, 1))):
            call("serve_rtu", modbus.serve_rtu, (device, 1, adu))
            call("Server.serve", modbus.Server(device, 1).serve, (adu,))
    class Wrong:
        def read_holding_registers(self, a: int, n: int) -> Any:
            return "not registers"

        def read_coils(self, a: int, n: int) -> Any:
            return None

        def write_registers(self, a: int, v: Any) -> Any:
            raise MemoryError("simulated")

    for adu in (modbus.encode_read(3, 0, 2), modbus.encode_read(1, 0, 2), modbus.encode_write_single_register(0, 1)):
        try:
            modbus.serve_rtu(Wrong(), 1, modbus.encode_rtu(1, adu))
        except (TypeError, ValueError, MemoryError):
            pass
    for regs in (None, object(), 5):
        slave = biss.ControlSlave(regs)
        m = biss.ControlMaster()
        m.start_read(0, 1)
        cds = False
        for _ in range(500):
            cds = slave.step(m.step(cds))


DECODERS: List[Callable[[bytes], Any]] = [
    tformat.decode_response, tformat.decode_request,
    lambda d: tformat.decode_response_for(b"\x1a", d),
    lambda d: tformat.decode_response_for(d[:4], d[4:]),
    lambda d: tformat.decode_response(d, exact=True),
    modbus.decode_request, modbus.decode_response, modbus.decode_rtu, modbus.decode_tcp,
    lambda d: modbus.decode_response_for(d[:6], d[6:]),
    lambda d: modbus.decode_response_for(modbus.encode_read(3, 0, 3), d),
    lambda d: biss.decode_frame_bytes(d, biss.ABSYS_LAYOUT),
    lambda d: biss.decode_frame_bytes(d, [biss.ABSYS_LAYOUT] * 3, order=biss.BitOrder.lsb_first),
    lambda d: biss.decode_frame(list(d), biss.SlaveLayout(single_turn_bits=3)),
    biss.decode_bp3, biss.decode_eds_common, lambda d: biss.decode_bp3(d, verify_checksum=True),
    absys.decode_serial_number, absys.decode_device_id,
    lambda d: sm_unit.decode_instantaneous(sm_unit.read_instantaneous(1), d),
    lambda d: sm_unit.decode_version(sm_unit.read_version(1), d),
    lambda d: ts5700n8500.Emulator().respond(d),
    lambda d: sm_unit.Emulator().serve(d),
]


@given(st.binary(max_size=300))
def test_decoders_on_random_bytes(data: bytes) -> None:
    for decode in DECODERS:
        try:
            decode(data)
        except motionbus.DecodeError as e:
            assert e.name != "unknown" and isinstance(e.code, motionbus.Errc)
        except motionbus.EncodeError:
            pass
    rx = tformat.Receiver(tformat.Echo.expected)
    rx.sent(data[:4])
    events = rx.feed(data) + [e for b in data for e in rx.put(b)]
    fr = modbus.RtuFramer(modbus.FramerRole.listener)
    events += fr.feed(data) + fr.idle()
    client = modbus.RtuFramer(modbus.FramerRole.client)
    client.sent(data[:8])
    events += client.feed(data) + [e for b in data for e in client.put(b)] + client.idle()
    assert all(isinstance(e, (tformat.Response, modbus.RtuFrame, motionbus.DecodeError)) for e in events)
