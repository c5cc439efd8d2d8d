"""A pymodbus RTU server (a third-party Modbus slave) for the library's client side.

Usage: pymodbus_server.py DEVICE [PARITY, ignored]. Slave 1, parity N (pyserial cannot set parity on a pty);
the same data as libmodbus_server.c. Serves until killed. Run with Debian's python3.
"""
import sys

from pymodbus.datastore import (ModbusSequentialDataBlock, ModbusServerContext,
                                ModbusSlaveContext)
from pymodbus.server import StartSerialServer
from pymodbus.transaction import ModbusRtuFramer


def main() -> None:
    slave = ModbusSlaveContext(
        di=ModbusSequentialDataBlock(0, [1 if i % 3 == 0 else 0 for i in range(100)]),
        co=ModbusSequentialDataBlock(0, [i % 2 for i in range(100)]),
        hr=ModbusSequentialDataBlock(0, [3 * i for i in range(100)]),
        ir=ModbusSequentialDataBlock(0, [1000 + i for i in range(100)]),
        zero_mode=True)
    context = ModbusServerContext(slaves={1: slave}, single=False)
    StartSerialServer(context=context, framer=ModbusRtuFramer, port=sys.argv[1], baudrate=9600,
                      parity="N", stopbits=1, bytesize=8, timeout=0.05)


if __name__ == "__main__":
    main()
