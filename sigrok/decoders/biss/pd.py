##
## This file is part of motionbus (a sigrok protocol decoder).
## The decoding is the motionbus package's (biss.decode_frame, biss.ControlObserver); this
## file samples SLO at MA's rising edges, finds the frames and places the results on the
## samples (docs/sigrok.md).
##

import sigrokdecode as srd

try:
    import motionbus
    from motionbus import biss
except ImportError as e:
    raise ImportError('biss decoder: the motionbus Python package is not importable '
                      '(set PYTHONPATH, docs/sigrok.md): %s' % e)

'''
OUTPUT_PYTHON format:

[<ptype>, <data>]
 - 'FRAME': (motionbus.biss.Frame, cdm: bool or None)
 - 'ERROR': motionbus.DecodeError (no frame could be read from the clocked bits)
 - 'REGISTER': motionbus.biss.ObservedAccess (kind 'header' or 'byte')
'''

(ANN_DELAY, ANN_ACK, ANN_START, ANN_CDS, ANN_MT, ANN_ST, ANN_NE, ANN_NW, ANN_CRC_OK,
 ANN_CRC_BAD, ANN_FRAME, ANN_CDM, ANN_REG, ANN_REG_BAD, ANN_ERROR) = range(15)


def _chain(text):
    '''"12+13/26": a chain of two slaves, 12 multi-turn + 13 single-turn bits, then 26 (no ':'
    or ',': sigrok-cli's -P syntax takes them).'''
    out = []
    for part in str(text).split('/'):
        part = part.strip()
        mt, _, st = part.rpartition('+')
        out.append((int(mt) if mt else 0, int(st)))
    return out


class Decoder(srd.Decoder):
    api_version = 3
    id = 'biss'
    name = 'BiSS-C'
    longname = 'BiSS-C encoder interface'
    desc = 'BiSS-C sensor data frames and register access (CDM/CDS).'
    license = 'gplv2+'
    inputs = ['logic']
    outputs = ['biss']
    tags = ['Embedded/industrial']
    channels = (
        {'id': 'ma', 'name': 'MA', 'desc': 'Master clock'},
        {'id': 'slo', 'name': 'SLO', 'desc': 'Slave data out'},
    )
    options = (
        {'id': 'chain', 'desc': 'Slaves: [multi-turn+]single-turn bits, / between slaves',
         'default': '32'},
        {'id': 'crc_poly', 'desc': 'CRC polynomial, BiSS notation (0x43: CRC6)',
         'default': '0x43'},
        {'id': 'crc_start', 'desc': 'CRC start value', 'default': 0},
        {'id': 'ne', 'desc': 'nE bit', 'default': 'yes', 'values': ('yes', 'no')},
        {'id': 'nw', 'desc': 'nW bit', 'default': 'yes', 'values': ('yes', 'no')},
    )
    annotations = (
        ('line-delay', 'Line delay'),
        ('ack', 'Ack'),
        ('start', 'Start'),
        ('cds', 'CDS'),
        ('multi-turn', 'Multi-turn'),
        ('single-turn', 'Single-turn'),
        ('ne', 'nE'),
        ('nw', 'nW'),
        ('crc-ok', 'CRC good'),
        ('crc-bad', 'CRC bad'),
        ('frame', 'Frame'),
        ('cdm', 'CDM'),
        ('register', 'Register access'),
        ('register-bad', 'Register access error'),
        ('error', 'Error'),
    )
    annotation_rows = (
        ('frames', 'Frames', (ANN_FRAME,)),
        ('fields', 'Fields', (ANN_DELAY, ANN_ACK, ANN_START, ANN_CDS, ANN_MT, ANN_ST, ANN_NE,
                              ANN_NW, ANN_CRC_OK, ANN_CRC_BAD, ANN_CDM)),
        ('registers', 'Register access', (ANN_REG, ANN_REG_BAD)),
        ('errors', 'Errors', (ANN_ERROR,)),
    )

    def __init__(self):
        self.reset()

    def reset(self):
        self.observer = None

    def start(self):
        self.out_ann = self.register(srd.OUTPUT_ANN)
        self.out_python = self.register(srd.OUTPUT_PYTHON)
        crc = biss.crc_from_biss_notation(int(str(self.options['crc_poly']), 0),
                                          int(self.options['crc_start']))
        self.layout = [biss.SlaveLayout(multi_turn_bits=mt, single_turn_bits=st,
                                        has_error=self.options['ne'] == 'yes',
                                        has_warning=self.options['nw'] == 'yes', crc=crc)
                       for mt, st in _chain(self.options['chain'])]
        for s in self.layout:
            s.validate()
        self.observer = biss.ControlObserver()

    def ann(self, ss, es, cls, texts):
        self.put(ss, es, self.out_ann, [cls, texts])

    def decode(self):
        ma, slo = 0, 1
        self.wait({ma: 'h'})
        while True:
            # A frame starts with MA's first falling edge after the line was idle.
            self.wait({ma: 'f'})
            first_fall = self.samplenum
            (_, s) = self.wait({ma: 'r'})
            half = max(self.samplenum - first_fall, 1)
            limit = 6 * half          # a clock half-period 3 times its length: the frame ended
            bits = [s]
            edges = [self.samplenum]
            cdm = False
            while True:
                pins = self.wait([{ma: 'f'}, {'skip': limit}])
                if self.matched[1]:   # MA stays high: the frame ended, CDM = 0
                    break
                fall = self.samplenum
                pins = self.wait([{ma: 'r'}, {'skip': limit}])
                if self.matched[1]:   # MA held low after the frame: CDM = 1
                    cdm = True
                    self.wait({ma: 'r'})
                    edges.append(fall)
                    break
                bits.append(pins[slo])
                edges.append(self.samplenum)
            self.frame(bits, edges, half, cdm)

    def span(self, edges, half, first, count):
        '''The samples of bits first .. first + count - 1 (each centred on its rising edge).'''
        ss = edges[first] - half
        es = edges[min(first + count - 1, len(edges) - 1)] + half
        return ss, es

    def frame(self, bits, edges, half, cdm):
        nbits = len(bits)
        ss_all, es_all = edges[0] - half, edges[nbits - 1] + half
        try:
            f = biss.decode_frame(bits, self.layout)
        except motionbus.DecodeError as e:
            # The package rejects a frame whose CRC is wrong (its evidence: the CRC the data
            # calls for, the CRC sent, the bit just past that CRC); the CDS it carries is not
            # trusted, and the register access is no longer followed.
            if e.name == 'crc_mismatch':
                self.ann(ss_all, es_all, ANN_FRAME, ['Frame: CRC bad, CDM %d' % int(cdm),
                                                     'CRC bad', 'F!'])
                width = self.layout[0].crc.width
                first = max(0, min(e.offset, nbits) - width)
                self.ann(*self.span(edges, half, first, width), ANN_CRC_BAD,
                         ['CRC bad: expected 0x%02X, received 0x%02X' % (e.expected, e.received),
                          'CRC bad', 'C!'])
            else:
                self.ann(ss_all, es_all, ANN_ERROR, ['No frame: %s' % e.name, e.name, 'E'])
            self.ann(es_all, es_all + 2 * half, ANN_CDM, ['CDM: %d' % int(cdm), 'CDM', 'M'])
            self.put(ss_all, es_all, self.out_python, ['ERROR', e])
            self.observer.reset()
            return
        sp = lambda first, count: self.span(edges, half, first, count)
        crc_ok = all(s.crc_ok for s in f.slaves)
        verdict = 'CRC good' if crc_ok else 'CRC bad'
        self.ann(ss_all, es_all, ANN_FRAME,
                 ['Frame: %s, CDM %d (%s)' % (', '.join(
                     'slave %d %s' % (i, s.single_turn if not self.layout[i].multi_turn_bits
                                      else '%d/%d' % (s.multi_turn, s.single_turn))
                     for i, s in enumerate(f.slaves)), int(cdm), verdict), 'Frame', 'F'])
        if f.line_delay:
            self.ann(*sp(0, f.line_delay), ANN_DELAY, ['Line delay: %d bits' % f.line_delay,
                                                       'Delay %d' % f.line_delay, 'D'])
        self.ann(*sp(f.line_delay, f.start - f.line_delay), ANN_ACK, ['Ack', 'A'])
        self.ann(*sp(f.start, 1), ANN_START, ['Start', 'S'])
        self.ann(*sp(f.start + 1, 1), ANN_CDS, ['CDS: %d' % int(f.cds), 'CDS', 'C'])
        at = f.start + 2
        for i, (lay, s) in enumerate(zip(self.layout, f.slaves)):
            if lay.multi_turn_bits:
                self.ann(*sp(at, lay.multi_turn_bits), ANN_MT,
                         ['Slave %d multi-turn: %d' % (i, s.multi_turn), 'MT %d' % s.multi_turn])
            self.ann(*sp(at + lay.multi_turn_bits, lay.single_turn_bits + lay.alignment_bits),
                     ANN_ST, ['Slave %d single-turn: %d' % (i, s.single_turn),
                              'ST %d' % s.single_turn])
            at += lay.data_bits
            if lay.has_error:
                self.ann(*sp(at, 1), ANN_NE, ['Slave %d nE: %d%s' % (
                    i, int(s.ne), '' if s.ne else ' (error)'), 'nE', 'E'])
                at += 1
            if lay.has_warning:
                self.ann(*sp(at, 1), ANN_NW, ['Slave %d nW: %d%s' % (
                    i, int(s.nw), '' if s.nw else ' (warning)'), 'nW', 'W'])
                at += 1
            width = lay.crc.width
            if s.crc_ok:
                self.ann(*sp(at, width), ANN_CRC_OK, ['Slave %d CRC good: 0x%02X' % (i, s.crc),
                                                      'CRC ok', 'C'])
            else:
                self.ann(*sp(at, width), ANN_CRC_BAD,
                         ['Slave %d CRC bad: 0x%02X, expected 0x%02X' % (i, s.crc,
                                                                         s.crc_computed),
                          'CRC bad', 'C!'])
            at += width
        self.ann(es_all, es_all + 2 * half, ANN_CDM, ['CDM: %d' % int(cdm), 'CDM', 'M'])
        self.put(ss_all, es_all, self.out_python, ['FRAME', (f, cdm)])
        if not crc_ok:
            # a frame whose CRC is bad carries no trustworthy CDS: the access is not followed
            self.observer.reset()
            return
        seen = self.observer.step(f.cds, cdm)
        if seen is not None:
            self.register_access(seen, ss_all, es_all)

    def register_access(self, a, ss, es):
        op = 'write' if a.write else 'read'
        if a.kind == 'header':
            echo = {2: 'read acknowledged', 1: 'write acknowledged', 3: 'refused',
                    0: 'no answer'}[a.echo]
            ok = a.crc_ok and a.echo == (1 if a.write else 2)
            text = 'Register %s slave %d address 0x%02X CRC4 0x%X %s, %s' % (
                op, a.slave_id, a.address, a.crc, 'good' if a.crc_ok else 'bad', echo)
            short = 'Reg %s 0x%02X' % (op, a.address)
        else:
            ok = a.crc_ok and (not a.write or (a.answer == a.data and not a.stop))
            text = 'Register %s address 0x%02X data 0x%02X CRC4 0x%X %s' % (
                op, a.address, a.data, a.crc, 'good' if a.crc_ok else 'bad')
            if a.write:
                text += ', echo 0x%02X%s' % (a.answer, ', refused' if a.stop else '')
            if a.waits:
                text += ', %d wait states' % a.waits
            short = '0x%02X=0x%02X' % (a.address, a.data)
        self.ann(ss, es, ANN_REG if ok else ANN_REG_BAD, [text, short])
        self.put(ss, es, self.out_python, ['REGISTER', a])
