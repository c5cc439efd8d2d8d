from typing import List

from . import absys as absys, sm_unit as sm_unit, ts5700n8500 as ts5700n8500

__all__: List[str]
