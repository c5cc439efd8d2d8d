"""Device profiles: ts5700n8500 (T-format encoder), sm_unit (Modbus), absys (BiSS-C)."""

from . import absys, sm_unit, ts5700n8500

__all__ = ["absys", "sm_unit", "ts5700n8500"]
