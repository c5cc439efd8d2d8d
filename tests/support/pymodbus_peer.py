"""What the pymodbus peers of the tests share (tests/interop/pymodbus_client.py,
tests/firmware/pymodbus_generic.py): the master's port, 9600 8E1 (or Modbus TCP to a
gateway), and the checks' tally."""
from pymodbus.client import ModbusSerialClient, ModbusTcpClient


def open_master(port):
    """The master on `port` (a pty; strict=False: pymodbus would otherwise set an
    inter-character timeout that pyserial cannot apply to a pseudo-terminal); `tcp:PORT` is a
    Modbus TCP client of 127.0.0.1:PORT instead (a gateway in front of the device)."""
    if port.startswith("tcp:"):
        client = ModbusTcpClient("127.0.0.1", port=int(port[4:]), timeout=3)
        assert client.connect(), "cannot connect"
        return client
    client = ModbusSerialClient(port=port, baudrate=9600, parity="E", stopbits=1, bytesize=8,
                                timeout=1, strict=False)
    assert client.connect(), "cannot open the port"
    return client


class Checks:
    """Prints each check; `failures` names those that did not hold."""

    def __init__(self):
        self.failures = []

    def __call__(self, name, condition):
        print(("ok   " if condition else "FAIL ") + name)
        if not condition:
            self.failures.append(name)
