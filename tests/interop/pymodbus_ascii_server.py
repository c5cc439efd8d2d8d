"""pymodbus_server.py's server and data in Modbus ASCII (pymodbus's ModbusAsciiFramer), for
`motionbus read modbus --ascii` (tests/interop/run_ascii_interop.sh).

Usage: pymodbus_ascii_server.py DEVICE. Serves until killed. Run with Debian's python3.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pymodbus_server  # noqa: E402  (the same server, its framer replaced)
from pymodbus.transaction import ModbusAsciiFramer  # noqa: E402

if __name__ == "__main__":
    pymodbus_server.ModbusRtuFramer = ModbusAsciiFramer
    pymodbus_server.main()
