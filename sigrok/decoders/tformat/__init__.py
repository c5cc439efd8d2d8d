##
## This file is part of motionbus (a sigrok protocol decoder).
##

'''
Tamagawa T-format (smartabs) encoder protocol on one half-duplex line, stacked on the uart
decoder (2.5 or 5 Mbaud, 8N1). Requests and responses are framed, paired and checked by the
motionbus package (tformat.Listener): Data ID, CF, SF, ABS, ABM, ENID, ALMC, EEPROM address
and data, the alarms spelled out, CRC good or bad, abnormal-request replies (ID3 data) and
missing responses.

Needs the Python package motionbus on libsigrokdecode's Python path (docs/sigrok.md).
'''

from .pd import Decoder
