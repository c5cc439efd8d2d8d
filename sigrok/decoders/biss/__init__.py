##
## This file is part of motionbus (a sigrok protocol decoder).
##

'''
BiSS-C (point-to-point or a chain of slaves) on two lines: MA (the master's clock) and SLO
(the slave's data). Each sensor data frame is decoded by the motionbus package
(biss.decode_frame): line delay, Ack, Start, CDS, each slave's multi-turn, single-turn, nE,
nW and CRC verdict. The register access carried by the CDM (MA held low after a frame = 1)
and CDS bits over successive frames is followed by motionbus's biss.ControlObserver: header
(slave ID, address, read/write, CRC4) and each byte (data, CRC4, the slave's answers).

Needs the Python package motionbus on libsigrokdecode's Python path (docs/sigrok.md).
'''

from .pd import Decoder
