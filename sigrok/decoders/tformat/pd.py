##
## This file is part of motionbus (a sigrok protocol decoder).
## The decoding is the motionbus package's (tformat.Listener, the library's line_listener);
## this file only places its results on the samples (docs/sigrok.md).
##

import sigrokdecode as srd

try:
    import motionbus
    from motionbus import tformat
except ImportError as e:  # a clear message in sigrok-cli / PulseView instead of a traceback
    raise ImportError('tformat decoder: the motionbus Python package is not importable '
                      '(set PYTHONPATH, docs/sigrok.md): %s' % e)

'''
OUTPUT_PYTHON format:

[<ptype>, <data>]
 - 'REQUEST': (motionbus.tformat.Request, request_error: motionbus.Errc or None)
 - 'RESPONSE': (motionbus.tformat.Response, id3_reply: bool)
 - 'ERROR': motionbus.DecodeError (a rejected response: CRC, mismatch, truncated)
 - 'MISSING': the request (motionbus.tformat.Request) no response answered
'''

# Where each field sits in a frame, to place its annotation (T-format spec Table 2; the values
# come from the package). Response: by Data ID.
_RESPONSE_FIELDS = {
    'pos': (('CF', 0, 1), ('SF', 1, 1), ('ABS', 2, 3)),
    'abm': (('CF', 0, 1), ('SF', 1, 1), ('ABM', 2, 3)),
    'enid': (('CF', 0, 1), ('SF', 1, 1), ('ENID', 2, 1)),
    'all': (('CF', 0, 1), ('SF', 1, 1), ('ABS', 2, 3), ('ENID', 5, 1), ('ABM', 6, 3),
            ('ALMC', 9, 1)),
    'eeprom': (('CF', 0, 1), ('ADF', 1, 1), ('EDF', 2, 1)),
}
_LAYOUT_OF_ID = {0: 'pos', 7: 'pos', 8: 'pos', 0xC: 'pos', 1: 'abm', 2: 'enid', 3: 'all',
                 6: 'eeprom', 0xD: 'eeprom'}

_ALARMS = {
    'os': 'over-speed', 'fs': 'full absolute status', 'ce': 'counting error',
    'of': 'counter overflow', 'oh': 'over-heat', 'me': 'multi-turn error',
    'be': 'battery error', 'ba': 'battery alarm',
}

ANN_REQ, ANN_RESP, ANN_FIELD, ANN_CRC_OK, ANN_CRC_BAD, ANN_ALARM, ANN_EEPROM, ANN_ERROR = range(8)


class Decoder(srd.Decoder):
    api_version = 3
    id = 'tformat'
    name = 'T-format'
    longname = 'Tamagawa T-format encoder protocol'
    desc = 'Tamagawa T-format (smartabs) absolute encoder requests and responses.'
    license = 'gplv2+'
    inputs = ['uart']
    outputs = ['tformat']
    tags = ['Embedded/industrial']
    options = (
        {'id': 'gap_us', 'desc': 'Line silence that ends a frame exchange (us)', 'default': 10.0},
        {'id': 'single_turn_bits', 'desc': 'Single-turn bits (0: the package default)', 'default': 0},
        {'id': 'multi_turn_bits', 'desc': 'Multi-turn bits (0: the package default)', 'default': 0},
    )
    annotations = (
        ('request', 'Request'),
        ('response', 'Response'),
        ('field', 'Field'),
        ('crc-ok', 'CRC good'),
        ('crc-bad', 'CRC bad'),
        ('alarm', 'Alarm'),
        ('eeprom', 'EEPROM access'),
        ('error', 'Error'),
    )
    annotation_rows = (
        ('frames', 'Frames', (ANN_REQ, ANN_RESP)),
        ('fields', 'Fields', (ANN_FIELD, ANN_CRC_OK, ANN_CRC_BAD)),
        ('eeprom', 'EEPROM', (ANN_EEPROM,)),
        ('alarms', 'Alarms', (ANN_ALARM,)),
        ('errors', 'Errors', (ANN_ERROR,)),
    )

    def __init__(self):
        self.reset()

    def reset(self):
        self.samplerate = None
        self.held = []           # (value, ss, es) of the bytes the listener holds
        self.last_es = None
        self.request = None      # (Request, ss, es) awaiting its response
        self.listener = None

    def metadata(self, key, value):
        if key == srd.SRD_CONF_SAMPLERATE:
            self.samplerate = value

    def start(self):
        self.out_ann = self.register(srd.OUTPUT_ANN)
        self.out_python = self.register(srd.OUTPUT_PYTHON)
        kw = {k: self.options[k] for k in ('single_turn_bits', 'multi_turn_bits')
              if self.options[k] > 0}
        self.listener = tformat.Listener(**kw)

    def put_ann(self, ss, es, cls, texts):
        self.put(ss, es, self.out_ann, [cls, texts])

    def put_py(self, ss, es, data):
        self.put(ss, es, self.out_python, data)

    def gap_samples(self):
        if not self.samplerate:
            return None
        return int(self.options['gap_us'] * 1e-6 * self.samplerate)

    def decode(self, ss, es, data):
        ptype, rxtx, pdata = data
        if ptype == 'INVALID STOPBIT':
            # A delimiter error (T-format spec §8.4 Table 5): the UART's to see; the byte still
            # goes to the listener as read, and the encoder answers it with ID3 data (SF CA1).
            self.put_ann(ss, es, ANN_ERROR, ['Delimiter error (stop bit 0)', 'Delimiter', 'D!'])
            return
        gap = self.gap_samples()
        if ptype == 'IDLE':
            # uart's IDLE: the line stayed idle for a whole character time, up to `es`. It
            # comes while the capture goes on, so a silence longer than the gap ends the
            # exchange there, also after the capture's last request (libsigrokdecode's API 3
            # has no end-of-capture call: docs/sigrok.md).
            if self.last_es is not None and gap is not None and es - self.last_es > gap:
                self.silence()
            return
        if ptype != 'DATA':
            return
        if self.last_es is not None and gap is not None and ss - self.last_es > gap:
            self.silence()
        self.last_es = es
        self.held.append((pdata[0] & 0xFF, ss, es))
        self.handle(self.listener.put(pdata[0] & 0xFF))

    def silence(self):
        self.last_es = None          # once a silence: the next IDLE packets are the same one
        expecting = self.listener.expecting_response
        self.handle(self.listener.idle())
        if expecting and self.request is not None:
            self.missing()
        self.request = None

    def missing(self):
        req, ss, es = self.request
        self.put_ann(ss, es, ANN_ERROR, ['Missing response to ID%X request' % int(req.id),
                                         'Missing response', 'Missing'])
        self.put_py(ss, es, ['MISSING', req])
        self.request = None

    def handle(self, events):
        for ev in events:
            if isinstance(ev, motionbus.DecodeError):
                self.rejected(ev)
            else:
                self.heard(ev)
        # What the listener dropped (no sync code, a rejected frame's bytes) is off its buffer.
        while len(self.held) > self.listener.pending:
            self.held.pop(0)

    def rejected(self, err):
        ss, es = self.held[0][1], self.held[-1][2]
        if err.name == 'crc_mismatch':
            self.put_ann(ss, es, ANN_CRC_BAD,
                         ['CRC bad: expected 0x%02X, received 0x%02X' % (err.expected, err.received),
                          'CRC bad', 'CRC!'])
        self.put_ann(ss, es, ANN_ERROR, ['Rejected response: %s' % err.name, err.name, 'Err'])
        self.put_py(ss, es, ['ERROR', err])
        self.request = None  # answered, if badly
        self.held.pop(0)     # the listener rescans from the next byte

    def heard(self, h):
        frame = bytes(h.bytes)
        n = len(frame)
        i = 0
        while i + n <= len(self.held) and bytes(b for b, _, _ in self.held[i:i + n]) != frame:
            i += 1
        spans = self.held[i:i + n]
        del self.held[:i + n]
        ss, es = spans[0][1], spans[-1][2]
        if h.is_response:
            self.response(h, spans, ss, es)
        else:
            if self.request is not None:
                self.missing()
            self.request_frame(h, spans, ss, es)

    def field(self, spans, name, first, size, text):
        if first + size <= len(spans):
            self.put_ann(spans[first][1], spans[first + size - 1][2], ANN_FIELD,
                         ['%s: %s' % (name, text), text])

    def crc(self, spans, crc, ok):
        s = spans[-1]
        if ok:
            self.put_ann(s[1], s[2], ANN_CRC_OK, ['CRC good: 0x%02X' % crc, 'CRC ok', 'C'])
        else:
            self.put_ann(s[1], s[2], ANN_CRC_BAD, ['CRC bad: 0x%02X' % crc, 'CRC bad', 'C!'])

    def request_frame(self, h, spans, ss, es):
        q = h.request
        did = int(q.id)
        err = h.request_error
        self.put_ann(ss, es, ANN_REQ, ['Request ID%X (CF 0x%02X)' % (did, q.cf), 'Req ID%X' % did,
                                       'Q%X' % did])
        self.field(spans, 'CF', 0, 1, '0x%02X ID%X' % (q.cf, did))
        if len(spans) >= 3:
            self.field(spans, 'ADF', 1, 1, '0x%02X' % q.address)
            if len(spans) == 4:
                self.field(spans, 'EDF', 2, 1, '0x%02X' % q.edf)
            self.crc(spans, q.crc, err is None or err.name != 'crc_mismatch')
            op = 'write' if did == 6 else 'read'
            text = 'EEPROM %s address 0x%02X' % (op, q.address)
            if did == 6:
                text += ' data 0x%02X' % q.edf
            self.put_ann(ss, es, ANN_EEPROM, [text, 'EEPROM %s 0x%02X' % (op, q.address)])
        if err is not None:
            self.put_ann(ss, es, ANN_ERROR, ['Abnormal request: %s' % err.name, err.name, 'Abn'])
        self.put_py(ss, es, ['REQUEST', (q, err)])
        self.request = (q, ss, es)

    def response(self, h, spans, ss, es):
        r = h.response
        did = int(r.id)
        text = 'Response ID%X' % did
        if h.id3_reply:
            text += ' (ID3 reply to an abnormal request)'
        self.put_ann(ss, es, ANN_RESP, [text, 'Resp ID%X' % did, 'R%X' % did])
        values = {'CF': '0x%02X ID%X' % (r.cf, did), 'SF': '0x%02X' % r.sf, 'ABS': str(r.abs),
                  'ABM': str(r.abm), 'ENID': '0x%02X' % r.enid, 'ALMC': '0x%02X' % r.almc,
                  'ADF': '0x%02X' % r.address, 'EDF': '0x%02X' % r.edf}
        for name, first, size in _RESPONSE_FIELDS.get(_LAYOUT_OF_ID.get(did, ''), ()):
            self.field(spans, name, first, size, values[name])
        self.crc(spans, r.crc, True)  # the listener hands over only responses whose CRC is good
        sf = [(r.ea0, 'EA0 counting error'), (r.ea1, 'EA1 encoder error (OH/ME/BE/BA)'),
              (r.ca0, 'CA0 request parity error'), (r.ca1, 'CA1 request delimiter error')]
        for on, name in sf:
            if on:
                self.put_ann(spans[1][1], spans[1][2], ANN_ALARM, ['SF: ' + name, name[:3]])
        if did == 3:
            for a in r.alarms:
                name = getattr(a, 'name', str(a))
                self.put_ann(spans[9][1], spans[9][2], ANN_ALARM,
                             ['ALMC: %s (%s)' % (_ALARMS.get(name, name), name.upper()),
                              name.upper()])
        if did in (6, 0xD):
            op = 'write' if did == 6 else 'read'
            busy = ' (busy)' if r.busy else ''
            self.put_ann(ss, es, ANN_EEPROM,
                         ['EEPROM %s address 0x%02X data 0x%02X%s' % (op, r.address, r.edf, busy),
                          'EEPROM 0x%02X=0x%02X' % (r.address, r.edf)])
        self.put_py(ss, es, ['RESPONSE', (r, h.id3_reply)])
        self.request = None
