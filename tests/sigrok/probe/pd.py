import sigrokdecode as srd


def describe(ptype, data):
    if ptype == 'REQUEST':
        q, err = data
        return 'REQUEST cf=0x%02X error=%s' % (q.cf, err.name if err is not None else None)
    if ptype == 'RESPONSE':
        r, id3 = data
        return 'RESPONSE id=%d abs=%d abm=%d id3_reply=%s' % (int(r.id), r.abs, r.abm, id3)
    if ptype == 'MISSING':
        return 'MISSING cf=0x%02X' % data.cf
    if ptype == 'ERROR':
        return 'ERROR %s' % data.name
    if ptype == 'FRAME':
        f, cdm = data
        return 'FRAME st=%s cds=%d cdm=%d' % (','.join(str(s.single_turn) for s in f.slaves),
                                                int(f.cds), int(cdm))
    if ptype == 'REGISTER':
        return 'REGISTER %s address=0x%02X data=0x%02X' % (data.kind, data.address, data.data)
    return 'UNKNOWN %s' % ptype


class Decoder(srd.Decoder):
    api_version = 3
    id = 'mbprobe'
    name = 'mbprobe'
    longname = 'motionbus stacking probe'
    desc = 'Shows the Python output of tformat / biss (tests only).'
    license = 'gplv2+'
    inputs = ['tformat', 'biss']
    outputs = []
    tags = ['Debug/trace']
    annotations = (('packet', 'Packet'),)

    def reset(self):
        pass

    def start(self):
        self.out_ann = self.register(srd.OUTPUT_ANN)

    def decode(self, ss, es, data):
        self.put(ss, es, self.out_ann, [0, [describe(data[0], data[1])]])
