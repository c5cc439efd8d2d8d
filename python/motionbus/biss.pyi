from typing import Any, List, Optional, Sequence, Tuple, Union

from . import BitOrder as BitOrder, ControlState as ControlState, CrcOutput as CrcOutput
from . import EncoderType as EncoderType, Errc
from ._types import BytesLike

__all__: List[str]
MAX_CHAIN: int
PREAMBLE_FRAMES: int

class CrcFormat:
    width: int
    poly: int
    start: int
    inverted: bool
    def __init__(self, width: int = ..., poly: int = ..., start: int = ...,
                 inverted: bool = ...) -> None: ...

def crc_from_biss_notation(poly: int, start: int = ..., output: int = ...) -> CrcFormat: ...
def crc_from_eds(cpoly: int, start: int = ...) -> CrcFormat: ...

class SlaveLayout:
    multi_turn_bits: int
    single_turn_bits: int
    alignment_bits: int
    has_error: bool
    has_warning: bool
    crc: CrcFormat
    def __init__(self, *, multi_turn_bits: int = ..., single_turn_bits: int = ...,
                 alignment_bits: int = ..., has_error: bool = ..., has_warning: bool = ...,
                 crc: CrcFormat = ...) -> None: ...
    @property
    def data_bits(self) -> int: ...
    @property
    def frame_bits(self) -> int: ...
    def validate(self) -> None: ...

ABSYS_LAYOUT: SlaveLayout
Layouts = Union[SlaveLayout, Sequence[SlaveLayout]]

class SlaveData:
    data: int
    multi_turn: int
    single_turn: int
    ne: bool
    nw: bool
    crc: int
    crc_computed: int
    crc_ok: bool
    error: bool
    warning: bool

class Frame:
    line_delay: int
    start: int
    cds: bool
    slaves: List[SlaveData]
    end: int
    ack_bits: int

class SlaveValues:
    multi_turn: int
    single_turn: int
    ne: bool
    nw: bool
    def __init__(self, *, multi_turn: int = ..., single_turn: int = ..., ne: bool = ...,
                 nw: bool = ...) -> None: ...

def decode_frame(bits: Sequence[int], layout: Layouts, *, max_line_delay: int = ...,
                 max_ack_bits: int = ...) -> Frame: ...
def decode_frame_bytes(data: BytesLike, layout: Layouts, *, bit_count: Optional[int] = ...,
                       order: int = ..., max_line_delay: int = ...,
                       max_ack_bits: int = ...) -> Frame: ...
def decode_frame_words(words: Sequence[int], layout: Layouts, *, word_bits: int,
                       bit_count: Optional[int] = ..., order: int = ...,
                       max_line_delay: int = ..., max_ack_bits: int = ...) -> Frame: ...
def encoded_bits(layout: Layouts, *, line_delay: int = ..., ack_bits: int = ...,
                 timeout_bits: int = ...) -> int: ...
def encode_frame(layout: Layouts, values: Union[SlaveValues, Sequence[SlaveValues]], *,
                 line_delay: int = ..., ack_bits: int = ..., cds: bool = ...,
                 timeout_bits: int = ...) -> List[int]: ...
def encode_frame_bytes(layout: Layouts, values: Union[SlaveValues, Sequence[SlaveValues]], *,
                       line_delay: int = ..., ack_bits: int = ..., cds: bool = ...,
                       timeout_bits: int = ..., order: int = ...) -> Tuple[bytes, int]: ...
def header_crc(slave_id: int, address: int, cts: bool = ...) -> int: ...
def data_crc(data: int) -> int: ...
def header_bits(slave_id: int, address: int, write: bool) -> int: ...

class ControlMaster:
    def __init__(self, *, max_wait_frames: int = ...) -> None: ...
    def start_read(self, slave_id: int, address: int, count: int = ...) -> None: ...
    def start_write(self, slave_id: int, address: int, data: BytesLike) -> None: ...
    def abort(self) -> None: ...
    def step(self, cds: bool) -> bool: ...
    @property
    def state(self) -> ControlState: ...
    busy: bool
    @property
    def error(self) -> Optional[Errc]: ...
    transferred: int
    frames: int
    data: bytes
    @staticmethod
    def frames_for(bytes: int) -> int: ...

class ControlSlave:
    def __init__(self, registers: Any, *, slave_id: int = ...,
                 refuse_while_busy: bool = ...) -> None: ...
    def step(self, cdm: bool) -> bool: ...
    accesses: int
    rejected_writes: int
    refused_busy: int

class ObservedAccess:
    @property
    def kind(self) -> str: ...
    slave_id: int
    address: int
    write: bool
    cts: bool
    crc: int
    crc_ok: bool
    echo: int
    data: int
    answer: int
    answer_crc: int
    stop: bool
    waits: int

class ControlObserver:
    def __init__(self) -> None: ...
    def step(self, cds: bool, cdm: bool) -> Optional[ObservedAccess]: ...
    def reset(self) -> None: ...

class EdsCommon:
    version: int
    length: int
    user_bank_start: int
    user_bank_end: int
    channels: int
    validity: int
    location: int
    profile_bank: int
    data_length: int
    data_format: int
    crc_poly: int
    def __init__(self) -> None: ...

class Bp3Profile:
    version: int
    length: int
    profile_id: int
    feedback1: int
    feedback2: int
    power_on_delay_ms: int
    type: EncoderType
    positions: int
    mt_length: int
    mt_format: int
    coarse_length: int
    coarse_format: int
    fine_length: int
    fine_format: int
    mt_count: int
    sip_count: int
    sip_resolution: int
    crc_poly: int
    crc_start: int
    pulses_per_revolution: int
    lsb_nm: float
    def __init__(self) -> None: ...
    def layout(self) -> SlaveLayout: ...

def bank_checksum(bank: BytesLike) -> int: ...
def decode_eds_common(bank: BytesLike, *, verify_checksum: bool = ...) -> EdsCommon: ...
def decode_bp3(bank: BytesLike, *, verify_checksum: bool = ...) -> Bp3Profile: ...
def encode_eds_common(common: EdsCommon) -> bytes: ...
def encode_bp3(profile: Bp3Profile) -> bytes: ...
