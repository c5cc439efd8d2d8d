'''A test decoder stacked on tformat or biss: one annotation per OUTPUT_PYTHON packet, so that
tests/sigrok checks what a decoder stacked on them receives.'''

from .pd import Decoder
