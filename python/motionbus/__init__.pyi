# Type stubs of the motionbus package (checked by the test suite with mypy).
from enum import IntEnum
from typing import List, Tuple

from . import biss as biss, crc as crc, devices as devices, modbus as modbus, tformat as tformat

__version__: str
__all__: List[str]

class Error(Exception):
    code: Errc
    name: str
    context: str
    detail: str
    def __init__(self, code: int, context: str = ..., detail: str = ...) -> None: ...

class DecodeError(Error, ValueError):
    expected: int
    received: int
    offset: int
    needed: int
    unit: str
    def __init__(self, code: int, context: str = ..., offset: int = ..., expected: int = ...,
                 received: int = ..., needed: int = ..., unit: str = ...) -> None: ...

class IncompleteError(DecodeError): ...
class EncodeError(Error, ValueError): ...

class Errc(IntEnum):
    ok = 0
    truncated = 1
    buffer_too_small = 2
    invalid_argument = 3
    crc_mismatch = 4
    out_of_range = 5
    length_mismatch = 6
    reserved_bits = 7
    no_frame = 8
    tformat_sync_code = 32
    tformat_parity = 33
    tformat_unknown_data_id = 34
    tformat_length = 35
    tformat_cf_mismatch = 36
    tformat_address_mismatch = 37
    tformat_communication_alarm = 38
    tformat_start_bit = 39
    tformat_delimiter = 40
    tformat_data_mismatch = 41
    modbus_illegal_function = 64
    modbus_quantity = 65
    modbus_byte_count = 66
    modbus_address_overflow = 67
    modbus_coil_value = 68
    modbus_mismatch = 69
    modbus_slave_address = 70
    modbus_pdu_length = 71
    modbus_ascii_character = 80
    modbus_ascii_odd_digits = 81
    modbus_ascii_end = 82
    modbus_reference_type = 96
    modbus_file_number = 97
    modbus_record_number = 98
    biss_no_ack = 128
    biss_no_start = 129
    biss_not_acknowledged = 130
    biss_access_denied = 131
    biss_echo_mismatch = 132
    biss_timeout = 133
    biss_write_not_confirmed = 134
    biss_aborted = 135
    biss_busy = 136
    biss_layout = 137
    biss_eds = 138

class AlmcBit(IntEnum):
    os = 1
    fs = 2
    ce = 4
    of = 8
    oh = 16
    me = 32
    be = 64
    ba = 128

class BitOrder(IntEnum):
    msb_first = 0
    lsb_first = 1

class Channel(IntEnum):
    voltage = 0
    current = 1
    power = 2
    temperature = 3
    acceleration_x = 4
    acceleration_y = 5
    acceleration_z = 6
    frequency = 7
    torque = 8

class Command(IntEnum):
    set_offset_to_position = 2
    reset_offset = 3
    reset_errors = 6

class ControlState(IntEnum):
    idle = 0
    busy = 1
    done = 2
    failed = 3

class CrcOutput(IntEnum):
    inverted = 0
    plain = 1

class DataId(IntEnum):
    read_abs = 0
    read_abm = 1
    read_enid = 2
    read_all = 3
    eeprom_write = 6
    reset_errors = 7
    reset_single_turn = 8
    reset_multi_turn = 12
    eeprom_read = 13

class Echo(IntEnum):
    none = 0
    expected = 1

class EncoderType(IntEnum):
    rotary = 0
    linear = 1

class ExceptionCode(IntEnum):
    illegal_function = 1
    illegal_data_address = 2
    illegal_data_value = 3
    server_device_failure = 4
    acknowledge = 5
    server_device_busy = 6
    memory_parity_error = 8
    gateway_path_unavailable = 10
    gateway_target_failed = 11

class FrameEnd(IntEnum):
    silence = 0
    length = 1

class FramerRole(IntEnum):
    server = 0
    client = 1
    listener = 2

class FunctionCode(IntEnum):
    read_coils = 1
    read_discrete_inputs = 2
    read_holding_registers = 3
    read_input_registers = 4
    write_single_coil = 5
    write_single_register = 6
    read_exception_status = 7
    diagnostics = 8
    get_comm_event_counter = 11
    get_comm_event_log = 12
    write_multiple_coils = 15
    write_multiple_registers = 16
    report_server_id = 17
    mask_write_register = 22
    read_write_multiple_registers = 23
    read_fifo_queue = 24
    encapsulated_interface = 43

class LatchRule(IntEnum):
    none = 0
    latched = 1
    by_speed = 2

class Parity(IntEnum):
    none = 0
    even = 1
    odd = 2

class PresetMode(IntEnum):
    with_offset = 0
    actual = 1

class ReportIdFormat(IntEnum):
    standard = 0
    two_bytes_no_count = 1

class SensorError(IntEnum):
    none = 0
    in_operation = 1
    at_power_on = 2

